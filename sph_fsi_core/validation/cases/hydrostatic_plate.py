"""Water at rest on a clamped plate (scenes/hydrostatic_plate.py, Fourey et al. 2017; judged by the scene's evaluate
on the settled mid-span deflection against plane-strain FE and the water's load against its weight), with the plate
alone under the exact load and the water alone on a rigid floor beside it; one table."""
from ..report_tools import fmt
from ..rung import Rung
from .as_run import EXPLICIT_PRESSURE


# The same plate under 2 m of water (config/hydrostatic_plate.yaml, Fourey et al. 2017), coupled: settled deflection
# against the same FE value and the water's load against its weight. The benchmark's aluminium takes a solid step
# of 0.7 us at 4 particles through; the ladder runs the plate 20 times softer (E = 3.375 GPa: the deflection 20
# times larger, 3 % of the thickness, still linear: the FE reference is for the same E), whose step is sqrt(20) =
# 4.5 times longer; the benchmark's own plate runs at the coarse rung. The water's step is held at 1 ms: its
# correction iterations per step grow as dt^2 (docs/method.md), 160-200 at the automatic 5 ms in this 2 m column.
HYDROSTATIC_PLATE_SCALED_E = 67.5e9 / 20.0
HYDROSTATIC_PLATE_LAYERS = (4, 6, 8, 10)
# The small plate of test/validation/test_hydrostatic_plate_quick.py (span 0.2 m, 0.02 m thick, E = 0.1 GPa, under
# 0.1 m of water; nondimensional load q L^4 / (D t) = 1.07 against the benchmark's 0.51 and the scaled plate's 10.2),
# with the default scheme as it is: a coupled ladder to 10 particles through that settles (the scaled plate does not
# at 6 through: docs/validation/OPEN.md, 1.0), 6 breathing periods of its column (0.04 s each), judged on the last
# half.
SMALL_PLATE = {"geometry.span": 0.2, "geometry.thickness": 0.02, "solid.young_modulus": 1.0e8,
               "geometry.water_height": 0.1, "geometry.wall_height": 0.11, "fluid.time_step": 1.0e-3}
SMALL_PLATE_SOLID = ("geometry.span", "geometry.thickness", "solid.young_modulus")
SMALL_PLATE_PRESSURE = 1000.0 * 9.81 * 0.1   # rho_f g H of its column (whole layers at every rung's spacing)


def rungs():
    rungs = []
    thickness = 0.05
    common = {"fluid.time_step": 1.0e-3, **EXPLICIT_PRESSURE}
    for layers in HYDROSTATIC_PLATE_LAYERS:
        dp = thickness / layers
        rungs.append(Rung("hydrostatic_plate", f"scaled_t_over_dp_{layers}", "hydrostatic_plate",
                          {"numerics.spacing": dp, "solid.young_modulus": HYDROSTATIC_PLATE_SCALED_E, **common},
                          end_time=0.3, note=f"{layers} particles through the plate, E = 3.375 GPa (the benchmark's "
                                             f"/ 20)"))
        if layers == 6:    # the benchmark's own plate after the first two scaled rungs (a run of ~30 min)
            rungs.append(Rung("hydrostatic_plate", "benchmark_t_over_dp_4", "hydrostatic_plate",
                              {"numerics.spacing": thickness / 4, **common}, end_time=0.3,
                              note="4 particles through the plate, the benchmark's E = 67.5 GPa"))
    for layers in HYDROSTATIC_PLATE_LAYERS:
        dp = SMALL_PLATE["geometry.thickness"] / layers
        rungs.append(Rung("hydrostatic_plate", f"small_t_over_dp_{layers}", "hydrostatic_plate",
                          {"numerics.spacing": dp, **SMALL_PLATE}, end_time=0.24, quick=layers == 4, bound=0.08,
                          note=f"{layers} particles through a small plate (0.2 m x 0.02 m, E = 0.1 GPa) under 0.1 m "
                               f"of water; the default scheme as it is"))
        # the same plate under the water's exact pressure rho_f g H (981 Pa): coupled against it is the load transfer
        rungs.append(Rung("hydrostatic_plate", f"small_loaded_t_over_dp_{layers}", "clamped_plate",
                          {"numerics.spacing": dp, **{k: v for k, v in SMALL_PLATE.items() if k in SMALL_PLATE_SOLID},
                           "geometry.load_pressure": SMALL_PLATE_PRESSURE}, end_time=0.06,
                          note=f"{layers} particles through the small plate under rho_f g H = 981 Pa, no water"))
    # The added-mass alternation of the staggered push (docs/validation/OPEN.md, 1.0): the small plate made light
    # (rho_s 300: the water's added mass about 10x the plate's, against about 1x at 2700) alternates from fluid step
    # to fluid step unrelaxed; coupling.relaxation below 2 / (1 + m_a / m_s) settles it. And the scaled benchmark
    # plate (m_a / m_s about 2.4) at 6 through, which does not settle unrelaxed (solid_pressure's twin), relaxed.
    light = {**SMALL_PLATE, "solid.density": 300.0}
    for layers in (4, 6):
        dp = SMALL_PLATE["geometry.thickness"] / layers
        rungs.append(Rung("hydrostatic_plate", f"light_t_over_dp_{layers}", "hydrostatic_plate",
                          {"numerics.spacing": dp, **light}, end_time=0.24,
                          note=f"{layers} particles through the small plate at rho_s = 300 kg/m^3, the push unrelaxed"))
    for layers in (4, 6):
        rungs.append(Rung("hydrostatic_plate", f"light_relaxed_t_over_dp_{layers}", "hydrostatic_plate",
                          {"numerics.spacing": SMALL_PLATE["geometry.thickness"] / layers, **light,
                           "coupling.relaxation": 0.1}, end_time=0.24,
                          note=f"{layers} particles through the small plate at rho_s = 300 kg/m^3, "
                               f"coupling.relaxation = 0.1"))
    # The fluid's step shrinks with the spacing past 6 through: the correction's iterations per step grow as
    # (dt / dp)^2 (29 per step at 8 through with 1 ms, the dt1ms rung, kept as it ran). It did not keep the 8-through
    # plate from leaving its deflection at 0.24-0.28 s either way (docs/validation/OPEN.md 1.0).
    for layers in HYDROSTATIC_PLATE_LAYERS:
        rungs.append(Rung("hydrostatic_plate", f"scaled_relaxed_t_over_dp_{layers}", "hydrostatic_plate",
                          {"numerics.spacing": thickness / layers, "solid.young_modulus": HYDROSTATIC_PLATE_SCALED_E,
                           "fluid.time_step": 1.0e-3 * min(1.0, 6 / layers), "coupling.relaxation": 0.3},
                          end_time=0.3, note=f"{layers} particles through the plate, E = 3.375 GPa, the default scheme "
                                             f"as it is, coupling.relaxation = 0.3"))
    rungs.append(Rung("hydrostatic_plate", "scaled_relaxed_dt1ms_t_over_dp_8", "hydrostatic_plate",
                      {"numerics.spacing": thickness / 8, "solid.young_modulus": HYDROSTATIC_PLATE_SCALED_E,
                       "fluid.time_step": 1.0e-3, "coupling.relaxation": 0.3}, end_time=0.3,
                      note="8 particles through the plate, E = 3.375 GPa, the default scheme as it is, "
                           "coupling.relaxation = 0.3, the fluid's step 1 ms as at 4 and 6 through"))
    # The fluid's part alone: the same 2 m column, relaxed the same way, on the rigid floor of the hydrostatic tank
    # (config/hydrostatic.yaml), its walls as the plate's side walls. Its departure at 0.25-0.4 s is the coupled
    # 8-through plate's (docs/validation/OPEN.md 1.0); the narrow tank (0.1 m: 16 columns) shows it in a minute.
    column = {"geometry.depth": 2.0, "geometry.wall_height": 2.1, "geometry.span_layers": 6,
              "geometry.water_damping_ratio": 1.0, "fluid.time_step": 1.0e-3, "output.timeseries_interval": 1.0e-3}
    for width, layers, end in ((1.0, 8, 0.32), (0.1, 8, 0.32), (0.1, 6, 0.6)):
        label = "fluid_alone" + ("_narrow" if width < 1.0 else "") + f"_t_over_dp_{layers}"
        rungs.append(Rung("hydrostatic_plate", label, "hydrostatic",
                          {**column, "geometry.width": width, "numerics.spacing": thickness / layers}, end_time=end,
                          note=f"the plate's column ({width:g} m wide, 2 m of water) on a rigid floor at the "
                               f"{layers}-through rung's spacing, relaxed as on the plate"))
    # The cure: the water built compressed as the correction holds it, its walls in register (tank.compress_column);
    # the tank to 0.6 s, twice the time the lattice-built column held
    for layers in (6, 8):
        rungs.append(Rung("hydrostatic_plate", f"fluid_alone_narrow_compressed_t_over_dp_{layers}", "hydrostatic",
                          {**column, "geometry.width": 0.1, "numerics.spacing": thickness / layers,
                           "geometry.water_start": "compressed"}, end_time=0.6,
                          note=f"the plate's column (0.1 m wide) on a rigid floor at the {layers}-through rung's "
                               f"spacing, built compressed with its walls"))
    # and the coupled benchmark-shaped plate so (the scene's start)
    for layers in (6, 8):
        rungs.append(Rung("hydrostatic_plate", f"scaled_relaxed_compressed_t_over_dp_{layers}", "hydrostatic_plate",
                          {"numerics.spacing": thickness / layers, "solid.young_modulus": HYDROSTATIC_PLATE_SCALED_E,
                           "fluid.time_step": 1.0e-3, "coupling.relaxation": 0.3,
                           "geometry.water_start": "compressed"}, end_time=0.3,
                          note=f"{layers} particles through the plate, E = 3.375 GPa, the default scheme as it is, "
                               f"coupling.relaxation = 0.3, the water built compressed with its walls"))
    # the rungs before the compressed start became the scene's keep the start they ran with
    for rung in rungs:
        if rung.scene == "hydrostatic_plate":
            rung.overrides.setdefault("geometry.water_start", "lattice")
    return rungs


_HYDROSTATIC_PLATE_LIGHT = (
    " The light_* rungs are the small plate at rho_s = 300 kg/m^3 (the water's added mass about 10x the plate's), "
    "whose staggered push alternates from fluid step to fluid step; *_relaxed_* hold coupling.relaxation w of each "
    "new push (0.1 there, 0.3 on the scaled plate), which damps that alternation below w = 2 / (1 + m_a / m_s) "
    "(docs/validation/OPEN.md, 1.0).")


def table(out_dir, rungs, summaries):
    """The coupled plate: settled deflection against FE, the water's load against its weight, each rung's cost."""
    lines = []
    for r in rungs:
        s = summaries.get(r.key)
        if r.case != "hydrostatic_plate" or s is None or s.get("water_load_n") is None:
            continue
        dp = s["settings"]["numerics.spacing"]
        t = s["settings"]["geometry.thickness"]
        # the same plate under the water's exact pressure, where the case has it (small_loaded_*)
        loaded = summaries.get(r.key.replace("/small_t_over", "/small_loaded_t_over"))
        alone = (f"{100 * loaded['error_signed']:+.2f} % | "
                 f"{100 * (s['midspan_deflection_m'] / loaded['midspan_deflection_m'] - 1.0):+.2f} %"
                 if loaded and "/small_t_over" in r.key else "- | -")
        lines.append(
            f"| {r.label} | {t / dp:.0f} | {s['settings']['solid.young_modulus'] / 1e9:.4g} | "
            f"{1e6 * s['midspan_deflection_m']:.2f} | {1e6 * s['reference_midspan_deflection_m']:.2f} | "
            f"{100 * s['error_signed']:+.2f} % | {alone} | {fmt(1e6 * s['midspan_deflection_swing_m'], '.3g')} | "
            f"{' / '.join(f'{1e6 * w:.1f}' for w in s.get('midspan_deflection_blocks_m', []))} | "
            f"{s['water_load_n']:.1f} / {s['water_weight_n']:.1f} N ({100 * s['water_load_error']:+.2f} %) | "
            f"{' / '.join(f'{f:.4g}' for f in s.get('water_load_blocks_n', []))} | "
            f"{s['water_load_all_n']:.1f} N | {s['particles'].get('fluid')} + {s['particles'].get('solid')} | "
            f"{s['solid_steps']} + {s['fluid_steps']} | {s['wall_time_s']:.0f} |")
    if not lines:
        return []
    return ["", "## Water at rest on a clamped plate (hydrostatic_plate)", "",
            "Fourey et al. 2017's benchmark, coupled (scenes/hydrostatic_plate.py): the settled mid-span deflection "
            "against the project's plane-strain FE value for the same plate under rho_f g H and its own weight (+: "
            "softer than FE) over the settled window (the run's last half), its swing there and the means of the "
            "window's three thirds (a trend says it has not settled), and the water's vertical force on the plate's "
            "span against the column's weight rho_f g H L W (its thirds; with the clamps' share: on the whole solid). "
            "Peers at 10 particles through (../shared/reference/hydrostatic_plate_fourey2017.csv): DualSPHysics "
            "about 8.5 %, TrixiParticles about 10 %; SPHinXsys +57 % at 4. The small plate (small_*: 0.2 m x 0.02 m, "
            "E = 0.1 GPa, under 0.1 m of water) also runs without water under the exact pressure rho_f g H "
            "(small_loaded_*): that plate against FE is the solid's error, the coupled one against it the load "
            "transfer's."
            + _HYDROSTATIC_PLATE_LIGHT, "",
            "| run | t/dp | E [GPa] | deflection [um] | FE [um] | error | loaded alone vs FE | coupled vs loaded | "
            "swing [um] | thirds [um] | water on span / weight | thirds [N] | on whole solid | particles (fluid + "
            "solid) | steps (solid + fluid) | wall [s] |",
            "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|", *lines, *peers_table(rungs, summaries)]


# the benchmark's plate (Fourey et al. 2017): span and thickness, m (config/hydrostatic_plate.yaml's defaults)
BENCHMARK_PLATE = (1.0, 0.05)
# Peers on it: (result, method, particles through, mid-span deflection against beam theory in %, positive for less
# deflection), as the comment lines of ../shared/reference/hydrostatic_plate_fourey2017.csv give them ("about" where
# they say so): DualSPHysics from O'Connor & Rogers 2021 (J. Fluids Struct. 104:103312) Fig. 8 as digitised in
# TrixiParticles.jl's validation/hydrostatic_water_column_2d/plot.jl; TrixiParticles' validation_reference_*.json
# (mean over 0.25-0.5 s); SPHinXsys' regression data (nu 0.34, no gravity on the plate: about 57 % more deflection).
PEERS = (("DualSPHysics (O'Connor & Rogers 2021)", "TL-SPH", 5, 14.0),
         ("DualSPHysics (O'Connor & Rogers 2021)", "TL-SPH", 10, 8.5),
         ("DualSPHysics (O'Connor & Rogers 2021)", "TL-SPH", 20, 1.1),
         ("TrixiParticles", "TL-SPH + EDAC or WCSPH", 5, 15.5),
         ("TrixiParticles", "TL-SPH + EDAC or WCSPH", 11, 10.5),
         ("TrixiParticles", "TL-SPH + EDAC or WCSPH", 13, 10.2),
         ("SPHinXsys (nu 0.34; no plate gravity)", "TL-SPH", 4, -57.0))


def peers_table(rungs, summaries, case="hydrostatic_plate"):
    """Ours beside the peers on the benchmark's plate (PEERS): the mid-span deflection against beam theory, positive
    for less deflection, the peers' convention; the plate's own FE value so read is the exact target (beam theory
    leaves out the shear). Only the rungs of the benchmark's shape (the scaled plate's E is linear in the deflection,
    not in the ratio). `case`: the case whose rungs are ours."""
    ours = []
    for r in rungs:
        s = summaries.get(r.key)
        if (r.case != case or s is None or s.get("beam_theory_midspan_deflection_m") is None
                or (s["settings"]["geometry.span"], s["settings"]["geometry.thickness"]) != BENCHMARK_PLATE):
            continue
        beam = s["beam_theory_midspan_deflection_m"]
        ours.append(f"| this code, {r.label} | {s['settings']['solid.scheme']}, "
                    f"{s['settings']['coupling.model']} coupling | "
                    f"{s['settings']['geometry.thickness'] / s['settings']['numerics.spacing']:.0f} | "
                    f"{100 * (1.0 - s['midspan_deflection_m'] / beam):+.1f} % | "
                    f"{100 * (1.0 - s['reference_midspan_deflection_m'] / beam):+.1f} % |")
    if not ours:
        return []
    peers = [f"| {result} | {method} | {through} | {error:+.1f} % | - |" for result, method, through, error in PEERS]
    return ["", "Beside the peers on the benchmark's plate (../shared/reference/hydrostatic_plate_fourey2017.csv's "
            "comments: DualSPHysics, TrixiParticles, SPHinXsys): the mid-span deflection against beam theory, "
            "0.0026 q L^4 / D, positive for less deflection (the peers' convention); the plane-strain FE value, the "
            "exact target, read the same way.", "",
            "| result | method | particles through | against beam theory | FE against beam theory |",
            "|---|---|---|---|---|", *ours, *peers]
