"""What `sph-fsi validate` runs: each case a list of rungs (a scene, overrides, an end time), with the bound
that `--quick` asserts on its coarse rungs. Running them is ladder.py's; the tables and plots report.py's."""
from . import spheric2
from .rung import Rung  # noqa: F401  (the cases' rungs; ladder.py and report.py take it from here)


# The default scheme as the rungs that carry this were run, before it took the implicit pressure and the fit turned
# with the body (2026-12-03: solid/implicit_pressure.py, solid/fit_rotation.py): the pressure explicit, the fit's rows
# remade as they turn. Case `solid_pressure` runs their twins with the scheme as it is.
EXPLICIT_PRESSURE = {"solid.pressure": "explicit", "solid.fit_refresh": "remake"}

# The paper's gate as the rungs that carry this were run, across the paper's 36 mm, before the scene took the
# narrowest periodic slab (2026-12-05: the same answer, case gate_span).
PAPER_SPAN = {"geometry.span": 0.036}


def cantilever_end_time(overrides, periods):
    """`periods` periods of the 3D reference frequency of the beam the overrides make (the scene's defaults else)."""
    from .references import cantilever_references
    beam = {"geometry.length": 0.04, "geometry.thickness": 0.004, "geometry.width": 0.006,
            "solid.young_modulus": 1.859e6, "solid.poisson_ratio": 0.49, "solid.density": 1000.0}
    beam.update({k: v for k, v in overrides.items() if k in beam})
    refs = cantilever_references(*beam.values())
    return periods / refs["reference_hz"]


# The default scheme's cantilever over shapes and materials (the verification issue's item 4): quadratic_gradient
# with the mirrored clamp at 4 particles through the paper's 4 x 6 mm section (dp = 1 mm), nu = 0.3, 0.4, 0.49 and
# L / H = 10, 20, 30, each judged against the project's 3D FE for its own shape and nu
# (reference_data/cantilever_fe3d_nondimensional.csv). The cost grows as (L / H)^3 and with the bulk sound speed
# (nu = 0.49's step is 3.6x nu = 0.3's): the nu = 0.49, L / H = 30 rung is the long one (~40 min on 2 threads).
CANTILEVER_SHAPE_POISSON = (0.3, 0.4, 0.49)
CANTILEVER_SHAPE_SLENDERNESS = (10, 20, 30)


def _cantilever_shape_rungs():
    rungs = []
    for nu in CANTILEVER_SHAPE_POISSON:
        for ratio in CANTILEVER_SHAPE_SLENDERNESS:
            quick = nu == 0.3 and ratio == 10     # CI's: the default scheme as it is
            overrides = {"geometry.length": ratio * 0.004, "solid.poisson_ratio": nu, "solid.clamp": "mirrored",
                         **({} if quick else EXPLICIT_PRESSURE)}
            rungs.append(Rung("cantilever_shapes", f"nu{nu:g}_L_over_H_{ratio}", "cantilever", overrides,
                              periods=2.25, quick=quick, bound=0.02,
                              note=f"L / H = {ratio}, nu = {nu:g}, 4 particles through, solid.clamp = mirrored"
                                   + ("" if quick else ", solid.pressure = explicit")))
    return rungs


def _cantilever_rungs():
    rungs = []
    # quadratic_gradient, the quadratic fit with the strain-gradient nodal integration, with the fixed clamp: as these
    # rungs were run, before the scheme took the mirrored clamp (the default scheme itself: cantilever_shapes).
    fixed = {"solid.clamp": "fixed", **EXPLICIT_PRESSURE}
    # Resolution ladder H/dp = 4, 6, 8 (2.25 periods of the reference each: the zero-crossing fit and the damping
    # ratio need two full periods of the tip). CI runs H/dp = 4 (the paper's spacing), bound 3 %.
    for ratio, quick in ((4, True), (6, False), (8, False)):
        dp = 0.004 / ratio
        rungs.append(Rung("cantilever_ladder", f"H_over_dp_{ratio}", "cantilever",
                          {"numerics.spacing": dp, **fixed}, periods=2.25, quick=quick, bound=0.03,
                          note=f"dp = {dp * 1e3:.3f} mm"))
    # Length sweep at dp = 1 mm, as the paper's Fig. 5 (2.25 periods, as the ladder; shorter records let the
    # free end's higher modes bias the frequency). The cost grows as L^3 (particles x period).
    rungs += [Rung("cantilever_length", f"L{length_mm}", "cantilever", {"geometry.length": length_mm * 1e-3, **fixed},
                   periods=2.25, note=f"L = {length_mm} mm, dp = 1 mm") for length_mm in (40, 60, 80, 100, 120)]
    # The paper's beam at the paper's spacing, 10 periods: frequency, damping, energy, sideways mode.
    rungs.append(Rung("cantilever", "L40_dp1.0_10periods", "cantilever", fixed, periods=10.0,
                      note="the paper's beam, 10 periods"))
    # The same beams with quadratic_plain, the plain nodal integration (each particle's strain at its centre, the
    # scheme before the gradient integration; a 4-layer beam's EI 6 % short, docs/method.md).
    plain = {"solid.scheme": "quadratic_plain"}
    for ratio in (4, 6, 8):
        dp = 0.004 / ratio
        rungs.append(Rung("cantilever_plain_ladder", f"H_over_dp_{ratio}", "cantilever",
                          {"numerics.spacing": dp, **plain}, periods=2.25,
                          note=f"dp = {dp * 1e3:.3f} mm, solid.scheme = quadratic_plain"))
    rungs += [Rung("cantilever_plain_length", f"L{length_mm}", "cantilever",
                   {"geometry.length": length_mm * 1e-3, **plain}, periods=2.25,
                   note=f"L = {length_mm} mm, dp = 1 mm, solid.scheme = quadratic_plain")
              for length_mm in (40, 60, 80, 100, 120)]
    rungs.append(Rung("cantilever_plain", "L40_dp1.0_10periods", "cantilever", plain, periods=10.0,
                      note="the paper's beam, 10 periods, solid.scheme = quadratic_plain"))
    # The paper's own scheme (gray2001: Gray's SPH gradient, plain sum) on the same beams: close at L = 40 mm, too
    # stiff beyond. As these rungs were run (the cantilever scene's artificial stress was 0 and its step factor
    # 0.25): without gray2001's artificial stress and at the quadratic schemes' step factor.
    paper = {"solid.scheme": "gray2001", "solid.artificial_stress_epsilon": 0.0, "solid.cfl": 0.25}
    for length_mm in (40, 60, 80):
        rungs.append(Rung("cantilever_paper_scheme", f"L{length_mm}", "cantilever",
                          {"geometry.length": length_mm * 1e-3, **paper},
                          periods=2.25, note=f"L = {length_mm} mm, dp = 1 mm, solid.scheme = gray2001 without "
                                             f"artificial stress, solid.cfl = 0.25"))
    return rungs


def _fluid_rungs():
    """Hydrostatic tank and Martin & Moyce dam break, each over a resolution ladder (fixed end times)."""
    rungs = []
    # Hydrostatic: 0.6 s, judged on the last 30 %; dp = 5 mm is CI's. The step is held at 2.5 mm: the iterations per
    # step grow as (dt / dp)^2 (docs/method.md), so the finer tank takes a proportionally finer step.
    for dp, quick, extra in ((0.005, True, {}), (0.0025, False, {"fluid.time_step": 0.0025})):
        rungs.append(Rung("hydrostatic", f"dp_{dp * 1e3:g}mm", "hydrostatic", {"numerics.spacing": dp, **extra},
                          end_time=0.6, quick=quick, bound=0.02,
                          note=f"H / dp = {0.1 / dp:.0f}; floor pressure against rho g H"))
    # Dam break to T = 3.15 at a / dp = 10, 20, 30.
    a = 0.05715
    for ratio, quick in ((10, True), (20, False), (30, False)):
        rungs.append(Rung("dam_break", f"a_over_dp_{ratio}", "dam_break", {"numerics.spacing": a / ratio},
                          end_time=0.17, quick=quick, bound=0.15,
                          note=f"dp = {a / ratio * 1e3:.3f} mm; front vs Martin & Moyce, RMS over T <= 3"))
    # Lobovsky et al. 2014's 600 mm column (issue 27) at H / dp = 30, 60, 90: both releases (the gate gone at t = 0,
    # or lifted at the measured 4.53 m/s), each from the lattice at zero pressure and settled behind its gate for
    # 0.3 s (fluid.settle_time; about three of the column's breathing periods); RMS of Z over T >= 1.
    height = 0.6
    for ratio in (30, 60, 90):
        for release in ("instant", "lifted"):
            for settle in (0.0, 0.3):
                label = f"{release}{'_settled' if settle else ''}_H_over_dp_{ratio}"
                rungs.append(Rung("lobovsky_dam_break", label, "lobovsky_dam_break",
                                  {"numerics.spacing": height / ratio, "geometry.release": release,
                                   "fluid.settle_time": settle}, end_time=0.4, quick=ratio == 30, bound=0.05,
                                  note=f"dp = {height / ratio * 1e3:.3g} mm, gate {release}, "
                                       f"{'settled 0.3 s' if settle else 'from zero pressure'}; front vs Lobovsky "
                                       f"et al. 2014, RMS over T >= 1"))
    # the front's speed against the water's compressibility (issue 27: the tolerance measured on the fronts too): the
    # scene's default (lifted, settled) with the density tolerance 0.3 % and 0.1 % instead of 1 %
    for ratio in (30, 60):
        for tolerance, tag in ((0.003, "0.3pct"), (0.001, "0.1pct")):
            rungs.append(Rung("lobovsky_dam_break", f"lifted_settled_tol{tag}_H_over_dp_{ratio}", "lobovsky_dam_break",
                              {"numerics.spacing": height / ratio, "geometry.release": "lifted",
                               "fluid.settle_time": 0.3, "fluid.density_tolerance": tolerance}, end_time=0.4,
                              note=f"dp = {height / ratio * 1e3:.3g} mm, gate lifted, settled 0.3 s, "
                                   f"fluid.density_tolerance = {tolerance:g}"))
    # the front's speed against the fluid's time step: the scene's default with fluid.cfl halved and quartered
    for ratio in (30, 60, 90):
        for cfl in (0.1, 0.05):
            rungs.append(Rung("lobovsky_dam_break", f"lifted_settled_cfl{cfl:g}_H_over_dp_{ratio}",
                              "lobovsky_dam_break",
                              {"numerics.spacing": height / ratio, "geometry.release": "lifted",
                               "fluid.settle_time": 0.3, "fluid.cfl": cfl}, end_time=0.4,
                              quick=ratio == 30 and cfl == 0.05,
                              note=f"dp = {height / ratio * 1e3:.3g} mm, gate lifted, settled 0.3 s, "
                                   f"fluid.cfl = {cfl:g}"))
    # the experiment's tank in 3D at the coarse spacing: 600 mm wide (30 layers), closed by free-slip side walls
    rungs.append(Rung("lobovsky_dam_break", "lifted_settled_3d_H_over_dp_30", "lobovsky_dam_break",
                      {"numerics.spacing": height / 30, "geometry.release": "lifted", "fluid.settle_time": 0.3,
                       "geometry.periodic_y": False, "geometry.span_layers": 30}, end_time=0.4,
                      note="dp = 20 mm, the 600 mm wide tank in 3D with side walls, gate lifted, settled 0.3 s"))
    return rungs


# The paper's 4 mm gate with 3 and 6 particles through it, beside its 1 mm (4): (spacing, label, particles through)
PAPER_GATE_LADDER = ((0.004 / 3, "dp1.33mm", 3), (0.002 / 3, "dp0.67mm", 6))


def _gate_rungs():
    """The coupled cases (issue 4), both coupling models at two resolutions each.

    antoci_gate: Antoci et al. 2007's measured free end over 0-0.4 s at dp = 2.5 mm (2 particles through the 5 mm
    gate) and 5/3 mm (3) with Gray's SPH gradient, and at 5/3 and 1.25 mm (4) with the quadratic fit (the scene's
    solid since session 3: solid.scheme = quadratic_plain_artificial_stress). elastic_gate: the paper's case to
    t = 0.14 s at 2 mm and at the paper's 1 mm (80k-particle class runs: the 1 mm rungs are the long ones). CI runs
    shorter versions (test/validation/test_gate_quick.py).
    """
    rungs = []
    # Gray's scheme as these rungs were run: at the quadratic schemes' step factor (the Antoci scene never set 0.5).
    gray = {"solid.scheme": "gray2001", "solid.cfl": 0.25}
    for dp, label in ((0.0025, "dp2.5mm"), (0.005 / 3, "dp1.67mm")):
        for model in ("pressure", "seed"):
            rungs.append(Rung("antoci_gate", f"{model}_{label}", "antoci_gate",
                              {"numerics.spacing": dp, "coupling.model": model, **gray},
                              end_time=0.4, note=f"dp = {dp * 1e3:.3g} mm, coupling {model}, solid.scheme = gray2001 "
                                                 f"(solid.cfl = 0.25); free end vs Antoci et al. 2007"))
    # With three layers through the 5 mm gate the quadratic fit is determined; Gray's SPH gradient is too stiff at
    # this gate's L/H = 16 (docs/validation/OPEN.md, sec. 2). The scene's scheme.
    for dp, label in ((0.005 / 3, "dp1.67mm"), (0.00125, "dp1.25mm")):
        rungs.append(Rung("antoci_gate", f"pressure_quadratic_{label}", "antoci_gate",
                          {"numerics.spacing": dp, "coupling.model": "pressure",
                           "solid.scheme": "quadratic_plain_artificial_stress"}, end_time=0.4,
                          note=f"dp = {dp * 1e3:.3g} mm, coupling pressure, "
                               f"solid.scheme = quadratic_plain_artificial_stress"))
    # The scene keeps Gray's artificial stress (eps = 0.15, its runs above); the quadratic fit needs none, and at
    # nu = 0.49 it feeds a growing mode (docs/method.md): the same run without it.
    rungs.append(Rung("antoci_gate", "pressure_quadratic_eps0_dp1.67mm", "antoci_gate",
                      {"numerics.spacing": 0.005 / 3, "coupling.model": "pressure",
                       "solid.scheme": "quadratic_plain"}, end_time=0.4,
                      note="dp = 1.67 mm, coupling pressure, solid.scheme = quadratic_plain (no artificial stress)"))
    # Three layers through the gate sum z^2 = 2 dp^2 where the section has H^3 / 12 = 2.25 dp^2: the plain nodal sum
    # leaves the gate 11 % soft in bending; the strain-gradient nodal integration puts it back (docs/method.md).
    rungs.append(Rung("antoci_gate", "pressure_gradient_eps0_dp1.67mm", "antoci_gate",
                      {"numerics.spacing": 0.005 / 3, "coupling.model": "pressure",
                       "solid.scheme": "quadratic_gradient", "solid.clamp": "fixed", **EXPLICIT_PRESSURE},
                      end_time=0.4,
                      note="dp = 1.67 mm, coupling pressure, solid.scheme = quadratic_gradient (strain-gradient "
                           "nodal integration, no artificial stress) with the fixed clamp"))
    for dp, label, extra in ((0.002, "dp2mm", {"geometry.gate_clamp_height": 0.004}), (0.001, "dp1mm", {})):
        for model in ("seed", "pressure"):
            rungs.append(Rung("elastic_gate", f"{model}_{label}", "elastic_gate",
                              {"numerics.spacing": dp, "coupling.model": model, "solid.scheme": "gray2001", **extra,
                               **PAPER_SPAN},
                              end_time=0.14,
                              snapshot_interval=0.02,
                              note=f"dp = {dp * 1e3:g} mm, coupling {model}; the paper's Figs. 6-8 (qualitative)"))
    # Gray's scheme on the default's ladder (solid_pressure's gate_default_elastic_gate_*): 3 and 6 particles through
    for dp, label, through in PAPER_GATE_LADDER:
        rungs.append(Rung("elastic_gate", f"pressure_{label}", "elastic_gate",
                          {"numerics.spacing": dp, "coupling.model": "pressure", "solid.scheme": "gray2001",
                           **PAPER_SPAN}, end_time=0.14, snapshot_interval=0.02,
                          note=f"dp = {dp * 1e3:.3g} mm ({through} particles through the gate), coupling "
                               f"pressure, solid.scheme = gray2001; the paper's Figs. 6-8 (qualitative)"))
    # At 1 mm the paper's gate is 4 particles thick, enough for the quadratic-fit solid (the scene pins gray2001
    # for its 2 mm runs, where the gate is 2 particles thick and the fit falls back to linear). quadratic_plain
    # brings its own solid.cfl, 0.25: gray2001's 0.5 suits Gray's gradient, not the fit.
    rungs.append(Rung("elastic_gate", "pressure_quadratic_dp1mm", "elastic_gate",
                      {"numerics.spacing": 0.001, "coupling.model": "pressure", "solid.scheme": "quadratic_plain",
                       **PAPER_SPAN},
                      end_time=0.14, snapshot_interval=0.02,
                      note="dp = 1 mm, coupling pressure, solid.scheme = quadratic_plain (quadratic-fit solid without "
                           "artificial stress)"))
    return rungs


# Both gates with the default scheme (quadratic_gradient and its mirrored clamp, every scene's since 2026-12; the
# verification issue's items 5 and 6): the paper's gate at its 1 mm against its figures' window and Gray's run above,
# Antoci's on a ladder of 3 / 4 / 5 particles through the gate against the experiment.
def _gate_default_rungs():
    """As they were run: with the pressure explicit (EXPLICIT_PRESSURE); their twins with the implicit pressure, and
    the Antoci ladder's third rung (1 mm), are case `solid_pressure`'s."""
    explicit = EXPLICIT_PRESSURE
    rungs = [Rung("gate_default", "elastic_gate_dp1mm", "elastic_gate",
                  {"numerics.spacing": 0.001, **explicit, **PAPER_SPAN},
                  end_time=0.14, snapshot_interval=0.02, note="the paper's gate at its 1 mm, solid.pressure = explicit")]
    for dp, label in ((0.005 / 3, "dp1.67mm"), (0.00125, "dp1.25mm")):
        rungs.append(Rung("gate_default", f"antoci_gate_{label}", "antoci_gate", {"numerics.spacing": dp, **explicit},
                          end_time=0.4, note=f"dp = {dp * 1e3:.3g} mm ({round(0.005 / dp)} particles through the gate), "
                                             f"solid.pressure = explicit; free end vs Antoci et al. 2007"))
    # the other published material (CoCoNuT's row of reference/antoci2007_material_by_source.csv): the band's edge
    rungs.append(Rung("gate_default", "antoci_gate_E10MPa_nu0.49_dp1.67mm", "antoci_gate",
                      {"numerics.spacing": 0.005 / 3, "solid.young_modulus": 1.0e7, "solid.poisson_ratio": 0.49,
                       **explicit}, end_time=0.4,
                      note="E = 10 MPa, nu = 0.49 (CoCoNuT's plane-strain FE row) at dp = 5/3 mm, solid.pressure = "
                           "explicit"))
    # the water settled at rest behind the gate (held straight, a plug in the gap) before t = 0 (fluid.settle_time;
    # the verification issue's item 7), and the paper's gate with the 0.1 % tolerance as well
    rungs += [Rung("gate_default", "elastic_gate_settled_dp1mm", "elastic_gate",
                   {"numerics.spacing": 0.001, "fluid.settle_time": 0.1, **explicit, **PAPER_SPAN}, end_time=0.14,
                   note="the paper's gate at 1 mm, the water settled 0.1 s behind it, solid.pressure = explicit"),
              Rung("gate_default", "elastic_gate_settled_tolerance0.1pct_dp1mm", "elastic_gate",
                   {"numerics.spacing": 0.001, "fluid.settle_time": 0.1, "fluid.density_tolerance": 0.001,
                    **explicit, **PAPER_SPAN}, end_time=0.14,
                   note="the paper's gate at 1 mm, settled, density tolerance 0.1 %, solid.pressure = explicit"),
              Rung("gate_default", "antoci_gate_settled_dp1.67mm", "antoci_gate",
                   {"numerics.spacing": 0.005 / 3, "fluid.settle_time": 0.2, **explicit}, end_time=0.4,
                   note="Antoci's gate at dp = 5/3 mm, the water settled 0.2 s behind it, solid.pressure = explicit")]
    return rungs


# The solid's static answer under a prescribed load (scenes/clamped_plate.py: the hydrostatic-plate benchmark's
# plate with the water's exact pressure), judged against plane-strain FE; every scheme on a resolution ladder.
SOLID_STATIC_SCHEMES = ("quadratic_gradient", "quadratic_plain", "gray2001")
SOLID_STATIC_LAYERS = (4, 6, 8, 10)


def _solid_static_rungs():
    """solid_static: 4 / 6 / 8 / 10 particles through the plate for each scheme with the fixed clamp, and the
    default scheme with the mirrored clamp (whose face is where the FE clamp is)."""
    rungs = []
    thickness = 0.05
    variants = [(scheme, {"solid.scheme": scheme, "solid.clamp": "fixed",
                          **(EXPLICIT_PRESSURE if scheme == "quadratic_gradient" else {})})
                for scheme in SOLID_STATIC_SCHEMES]
    variants.append(("quadratic_gradient_mirrored", {"solid.scheme": "quadratic_gradient", "solid.clamp": "mirrored",
                                                     **EXPLICIT_PRESSURE}))
    for name, overrides in variants:
        for layers in SOLID_STATIC_LAYERS:
            dp = thickness / layers
            rungs.append(Rung("solid_static", f"{name}_t_over_dp_{layers}", "clamped_plate",
                              {"numerics.spacing": dp, **overrides}, end_time=0.02,
                              note=f"{layers} particles through the plate, " + ", ".join(
                                  f"{k} = {v}" for k, v in overrides.items())))
    return rungs


# The same plate under 2 m of water (scenes/hydrostatic_plate.py, Fourey et al. 2017), coupled: settled deflection
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


# Where the default scheme's end effect sits (docs/validation/OPEN.md, 6: the cantilever's error falls as H / L):
# one plate, 4 particles through (t = 0.02 m, dp = 5 mm, E = 0.1 GPa, nu = 0.3: the small plate's), clamped at
# both ends (no free end) and clamped at one (a cantilever), over L / t, each against plane-strain FE for itself.
# A clamp acting as if the strip were longer by delta adds 8 delta / L to the first and 4 delta / L to the second
# (scenes/clamped_plate.py); what the cantilever has beyond that is its free end's. The loads scale as (t / L)^4 so
# every strip deflects as much relative to its thickness (0.5 % clamped at both ends, 2 % as a cantilever: linear).
# The runs go 5 periods of the first mode: the load ramps in over 2 and the critical damping settles it.
CLAMP_EFFECT_RATIOS = {"clamped_clamped": (5, 10, 15, 20, 30), "clamped_free": (5, 10, 15, 20)}
CLAMP_EFFECT_PLATE = {"geometry.thickness": 0.02, "numerics.spacing": 0.005, "solid.young_modulus": 1.0e8}
CLAMP_EFFECT_BEAM_RATIOS = (5, 10, 15, 20)
CLAMP_EFFECT_LOAD = {"clamped_clamped": 1000.0 * 9.81 * 0.1, "clamped_free": 1000.0 * 9.81 * 0.01}   # Pa at L/t 10


def _clamp_effect_rungs():
    import math
    from ..scenes.clamped_plate import FIRST_MODE_BETA_L
    t, e, nu, rho = 0.02, 1.0e8, 0.3, 2700.0
    rungs = []
    for supports, ratios in CLAMP_EFFECT_RATIOS.items():
        for ratio in ratios:
            span = ratio * t
            scale = (10.0 / ratio) ** 4
            pressure = CLAMP_EFFECT_LOAD[supports] * scale
            gravity = -9.81 * scale * CLAMP_EFFECT_LOAD[supports] / CLAMP_EFFECT_LOAD["clamped_clamped"]
            omega = (FIRST_MODE_BETA_L[supports] / span) ** 2 * math.sqrt(e * t ** 2 / (12.0 * (1.0 - nu * nu) * rho))
            rungs.append(Rung("clamp_effect", f"{supports}_L_over_t_{ratio}", "clamped_plate",
                              {**CLAMP_EFFECT_PLATE, "geometry.span": span, "geometry.supports": supports,
                               "geometry.load_pressure": pressure, "scene.gravity": (0.0, 0.0, gravity)},
                              end_time=5.0 * 2.0 * math.pi / omega, quick=supports == "clamped_free" and ratio == 5,
                              bound=0.1, note=f"L / t = {ratio}, 4 particles through, {supports}, the default scheme"))
    # the same in 3D, static: the cantilever_shapes beam (4 x 6 mm, 4 particles through, nu = 0.3) under a linear
    # dead load (alpha = 0.05), whose frequency error is a + b H / L (docs/validation/OPEN.md, 6); against 3D FE
    # at the free end's particle layer (validation/end_effect.py)
    for ratio in CLAMP_EFFECT_BEAM_RATIOS:
        rungs.append(Rung("clamp_effect", f"beam3d_L_over_H_{ratio}", "cantilever_loaded",
                          {"geometry.length": ratio * 0.004, "solid.poisson_ratio": 0.3,
                           "geometry.load_parameter": 0.05}, end_time=0.25 * (ratio / 10.0) ** 2,
                          note=f"L / H = {ratio}, the cantilever_shapes beam with nu = 0.3 under a linear dead load, "
                               "the default scheme"))
    return rungs


def _hydrostatic_plate_rungs():
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
    # (scenes/hydrostatic.py), its walls as the plate's side walls. Its departure at 0.25-0.4 s is the coupled
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
    # and the coupled benchmark-shaped plate so (the scene's start since 2026-12-04)
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


# Antoci's gate held static under its water (scenes/antoci_gate_static.py) and under its water's exact pressure
# (scenes/antoci_gate_loaded.py), both against plane-strain FE: coupled against loaded is the load transfer, loaded
# against FE the gate's bending, at the validation spacings where the quadratic fit is determined (3 and 4 particles
# through the gate), with the antoci_gate scene's scheme; and the solid under the exact load with the default
# scheme and the mirrored clamp (as the plates converge, docs/validation/solid_static).
GATE_STATIC_SPACINGS = ((0.005 / 3, "dp1.67mm"), (0.00125, "dp1.25mm"))


def _gate_static_rungs():
    rungs = []
    antoci = {"solid.scheme": "quadratic_plain_artificial_stress"}   # the antoci_gate scene's until 2026-12
    for dp, label in GATE_STATIC_SPACINGS:
        through = round(0.005 / dp)
        rungs.append(Rung("gate_static", f"coupled_{label}", "antoci_gate_static", {"numerics.spacing": dp, **antoci},
                          end_time=1.0, note=f"{through} particles through the gate, coupled, solid.scheme = "
                                             f"quadratic_plain_artificial_stress"))
        rungs.append(Rung("gate_static", f"loaded_{label}", "antoci_gate_loaded", {"numerics.spacing": dp, **antoci},
                          end_time=0.4, note=f"{through} particles through the gate, the exact pressure, solid.scheme "
                                             f"= quadratic_plain_artificial_stress"))
        rungs.append(Rung("gate_static", f"loaded_gradient_mirrored_{label}", "antoci_gate_loaded",
                          {"numerics.spacing": dp, **EXPLICIT_PRESSURE}, end_time=0.4,
                          note=f"{through} particles through the gate, the exact pressure, the default scheme "
                               f"(quadratic_gradient, mirrored clamp)"))
        rungs.append(Rung("gate_static", f"coupled_gradient_mirrored_{label}", "antoci_gate_static",
                          {"numerics.spacing": dp, **EXPLICIT_PRESSURE}, end_time=1.0,
                          note=f"{through} particles through the gate, coupled, the default scheme "
                               f"(quadratic_gradient, mirrored clamp)"))
        # the same with the water built as the correction holds it and the tank's walls level with it (the
        # hydrostatic plate's cure for its first column's zigzag at the walls): is the slow swing the water's start?
        rungs.append(Rung("gate_static", f"coupled_gradient_mirrored_compressed_{label}", "antoci_gate_static",
                          {"numerics.spacing": dp, **EXPLICIT_PRESSURE, "geometry.water_start": "compressed"},
                          end_time=1.0,
                          note=f"{through} particles through the gate, coupled, the default scheme "
                               f"(quadratic_gradient, mirrored clamp), the water built compressed with its walls"))
    # the push relaxed below 2 / (1 + m_a / m_s) (m_a / m_s about 9 here; hydrostatic_plate's light_* rungs), at the
    # scene's own spacing (its YAML's, 3 through) as the unrelaxed run above
    rungs.append(Rung("gate_static", "coupled_gradient_mirrored_relaxed_dp1.67mm", "antoci_gate_static",
                      {**EXPLICIT_PRESSURE, "coupling.relaxation": 0.15}, end_time=1.0,
                      note="3 particles through the gate, coupled, the default scheme (quadratic_gradient, mirrored "
                           "clamp), coupling.relaxation = 0.15"))
    # the same with the water's density tolerance 0.3 % instead of 1 %: is the slow swing the relaxed gate keeps the
    # column breathing within the tolerance band (its period 4 H / sqrt(g H / tolerance), 0.15 s at g = 1 and 1 %)?
    rungs.append(Rung("gate_static", "coupled_gradient_mirrored_relaxed_tol0.3pct_dp1.67mm", "antoci_gate_static",
                      {**EXPLICIT_PRESSURE, "coupling.relaxation": 0.15, "fluid.density_tolerance": 0.003},
                      end_time=1.0,
                      note="3 particles through the gate, coupled, the default scheme, coupling.relaxation = 0.15, "
                           "fluid.density_tolerance = 0.003"))
    # the default scheme as it is (the implicit pressure), built compressed, to 0.6 s (judged over 0.3-0.6 s), at the
    # scene's fluid step (1 ms) and at half of it: is the slow swing driven by the load's pulses at the fluid step
    # (docs/validation/OPEN.md 1.4), which a shorter step makes smaller?
    for step, label in ((0.001, "fluid_dt1ms"), (0.0005, "fluid_dt0.5ms")):
        rungs.append(Rung("gate_static", f"coupled_default_compressed_{label}_dp1.67mm", "antoci_gate_static",
                          {"geometry.water_start": "compressed", "fluid.time_step": step}, end_time=0.6,
                          note=f"3 particles through the gate, coupled, the default scheme as it is (implicit "
                               f"pressure), the water built compressed, fluid.time_step = {step * 1e3:g} ms, to 0.6 s"))
    return rungs


CANTILEVER_CASES = ("cantilever", "cantilever_ladder", "cantilever_length", "cantilever_shapes", "cantilever_plain",
                    "cantilever_plain_ladder", "cantilever_plain_length", "cantilever_paper_scheme")


# The solid under large rotation (scenes/cantilever_loaded.py): the paper's beam (4 particles through, L/H = 10) at
# rest under a distributed dead load, linear (alpha = 0.05) to the free end turning 18 and 34 degrees (alpha = 2, 4;
# the root's bending strain alpha H / (4 L) = 5 and 10 %: Antoci's gate reaches about 7 %), against the elastica;
# Gray's scheme alongside. The quick rung: a beam half as long (L/H = 5, a quarter of the time) at alpha = 2.
# Larger alpha at this L/H strains the root by 20 % and more (alpha = 8: 20 %), beyond what a hypoelastic solid
# means; both schemes then fail at the root (measured at L/H = 5).
LARGE_DEFLECTION_LOADS = (0.05, 2.0, 4.0)


def _large_deflection_rungs():
    rungs = [Rung("large_deflection", f"alpha_{a:g}", "cantilever_loaded",
                  {"geometry.load_parameter": a, **EXPLICIT_PRESSURE}, end_time=0.25,
                  note=f"alpha = {a:g}, the default scheme, solid.pressure = explicit") for a in LARGE_DEFLECTION_LOADS]
    rungs += [Rung("large_deflection", f"gray2001_alpha_{a:g}", "cantilever_loaded",
                   {"geometry.load_parameter": a, "solid.scheme": "gray2001"}, end_time=0.25,
                   note=f"alpha = {a:g}, Gray's scheme (fixed clamp)") for a in (0.05, 4.0)]
    rungs.append(Rung("large_deflection", "short_alpha_2", "cantilever_loaded",
                      {"geometry.load_parameter": 2.0, "geometry.length": 0.02}, end_time=0.0625, quick=True,
                      bound=0.06, note="L/H = 5, alpha = 2: the CI rung"))
    return rungs


def _twin(rung, label=None, **changes):
    """`rung` with the default scheme's implicit pressure (its EXPLICIT_PRESSURE pin dropped), in case
    solid_pressure, its explicit run as the counterpart."""
    overrides = {k: v for k, v in rung.overrides.items() if k not in EXPLICIT_PRESSURE}
    note = rung.note.replace(", solid.pressure = explicit", "").replace("solid.pressure = explicit", "")
    return Rung("solid_pressure", label or f"{rung.case}_{rung.label}", rung.scene, overrides, periods=rung.periods,
                end_time=rung.end_time, note=f"{note.rstrip(', ')}; the implicit pressure", counterpart=rung.key,
                **changes)


def _solid_pressure_rungs():
    """The default scheme's validated runs again with its pressure implicit (solid/implicit_pressure.py, since
    2026-12-03), each beside its explicit counterpart: how far the step set by the shear waves moves each answer, and
    what it saves. The gain is sqrt(3 K / 4 G): 6.1x at nu = 0.49, 1.9x at 0.4, 1.3x at 0.3. And the Antoci
    ladder's third rung (1 mm, 5 particles through the gate), affordable with it."""
    by_key = {r.key: r for r in (_cantilever_shape_rungs() + _large_deflection_rungs() + _solid_static_rungs()
                                 + _gate_default_rungs() + _gate_static_rungs() + _hydrostatic_plate_rungs())}
    keys = ([f"cantilever_shapes/nu{nu:g}_L_over_H_10" for nu in (0.4, 0.49)]
            + ["cantilever_shapes/nu0.49_L_over_H_20", "cantilever_shapes/nu0.49_L_over_H_30"]
            + [f"large_deflection/alpha_{a:g}" for a in LARGE_DEFLECTION_LOADS]
            + [f"solid_static/quadratic_gradient_mirrored_t_over_dp_{n}" for n in (4, 6)]
            + ["gate_static/loaded_gradient_mirrored_dp1.67mm", "hydrostatic_plate/scaled_t_over_dp_4",
               "hydrostatic_plate/scaled_t_over_dp_6",
               "gate_default/elastic_gate_dp1mm", "gate_default/antoci_gate_dp1.67mm",
               "gate_default/antoci_gate_dp1.25mm", "gate_default/antoci_gate_E10MPa_nu0.49_dp1.67mm"])
    rungs = [_twin(by_key[k]) for k in keys]
    # the band's other edge one rung finer (the verification issue's item 5: each published material on the ladder)
    rungs.append(Rung("solid_pressure", "gate_default_antoci_gate_E10MPa_nu0.49_dp1.25mm", "antoci_gate",
                      {"numerics.spacing": 0.00125, "solid.young_modulus": 1.0e7, "solid.poisson_ratio": 0.49},
                      end_time=0.4, note="E = 10 MPa, nu = 0.49 (CoCoNuT's plane-strain FE row) at dp = 1.25 mm (4 "
                                         "particles through the gate); free end vs Antoci et al. 2007; the implicit "
                                         "pressure"))
    rungs.append(Rung("solid_pressure", "gate_default_antoci_gate_dp1mm", "antoci_gate", {"numerics.spacing": 0.001},
                      end_time=0.4, note="dp = 1 mm (5 particles through the gate); free end vs Antoci et al. 2007; "
                                         "the implicit pressure"))
    # the paper's gate on a ladder with the default scheme (the verification issue's item 6: which of the default's
    # -7.4 mm and Gray's -8.2 mm at 1 mm is right): 3 and 6 particles through the 4 mm gate beside the 1 mm twin's 4.
    # At 2/3 mm every length of the scene is whole layers as at 1 mm; at 4/3 mm the builder rounds the 2 mm gap under
    # the gate to 2 layers, 2.67 mm (and the water to 37.3 mm high): summary.json's geometry_effective
    for dp, label, through in PAPER_GATE_LADDER:
        rungs.append(Rung("solid_pressure", f"gate_default_elastic_gate_{label}", "elastic_gate",
                          {"numerics.spacing": dp, **PAPER_SPAN}, end_time=0.14, snapshot_interval=0.02,
                          note=f"the paper's gate at dp = {dp * 1e3:.3g} mm ({through} particles through it); the "
                               f"implicit pressure"))
    # the push relaxed below 2 / (1 + m_a / m_s) (hydrostatic_plate's light_* rungs): does the added-mass alternation
    # move Antoci's peak?
    rungs.append(Rung("solid_pressure", "gate_default_elastic_gate_relaxed_dp1mm", "elastic_gate",
                      {"numerics.spacing": 0.001, "coupling.relaxation": 0.25, **PAPER_SPAN}, end_time=0.14,
                      note="the paper's gate at its 1 mm, the implicit pressure, coupling.relaxation = 0.25"))
    rungs.append(Rung("solid_pressure", "gate_default_antoci_gate_relaxed_dp1.67mm", "antoci_gate",
                      {"numerics.spacing": 0.005 / 3, "coupling.relaxation": 0.25}, end_time=0.4,
                      note="dp = 5/3 mm (3 particles through the gate); free end vs Antoci et al. 2007; the implicit "
                           "pressure, coupling.relaxation = 0.25"))
    # SPHinXsys's material (reference/antoci2007_material_by_source.csv: E 7.8 MPa, nu 0.47): a plane-strain modulus
    # E / (1 - nu^2) of 10.0 MPa, the bending modulus of a beam (plane stress) of E = 10 MPa; the scene's is 14.3 MPa
    for dp, label, through in ((0.005 / 3, "dp1.67mm", 3), (0.00125, "dp1.25mm", 4)):
        rungs.append(Rung("solid_pressure", f"gate_default_antoci_gate_E7.8MPa_nu0.47_{label}", "antoci_gate",
                          {"numerics.spacing": dp, "solid.young_modulus": 7.8e6, "solid.poisson_ratio": 0.47},
                          end_time=0.4, note=f"dp = {dp * 1e3:.3g} mm ({through} particles through the gate); free end "
                                             f"vs Antoci et al. 2007; the implicit pressure, SPHinXsys's material (E "
                                             f"7.8 MPa, nu 0.47)"))
    return rungs


# The default scheme with the strain gradient's volumetric part (solid.volumetric_gradient, since 2026-12-05), time
# stepped on the beams and static solids where the assembled answer (validation/linear_modes, docs/validation/
# linear_modes) predicts it: the cantilever at L/H = 10 -0.230 / -0.316 / -0.080 % at nu = 0.3 / 0.4 / 0.49 (without
# it -0.79 / -0.77 / -0.87 %), the plate at 4 through +0.93 % (+2.68 %), Antoci's gate under its exact load at 5/3 mm
# +0.12 % (+2.15 % assembled, +1.69 % time-stepped).
VOLUMETRIC = {"solid.volumetric_gradient": True}


def _volumetric_gradient_rungs():
    rungs = []
    for nu in CANTILEVER_SHAPE_POISSON:
        rungs.append(Rung("volumetric_gradient", f"cantilever_nu{nu:g}_L_over_H_10", "cantilever",
                          {"geometry.length": 0.04, "solid.poisson_ratio": nu, **VOLUMETRIC}, periods=2.25,
                          note=f"L / H = 10, nu = {nu:g}, 4 particles through, the default scheme with "
                               f"solid.volumetric_gradient"))
    rungs.append(Rung("volumetric_gradient", "plate_t_over_dp_4", "clamped_plate",
                      {"numerics.spacing": 0.0125, **VOLUMETRIC}, end_time=0.02,
                      note="the hydrostatic plate's plate under its exact load, 4 particles through, the default "
                           "scheme with solid.volumetric_gradient"))
    rungs.append(Rung("volumetric_gradient", "gate_loaded_dp1.67mm", "antoci_gate_loaded",
                      {"numerics.spacing": 0.005 / 3, **VOLUMETRIC}, end_time=0.4,
                      note="Antoci's gate under its water's exact pressure, 3 particles through, the default scheme "
                           "with solid.volumetric_gradient"))
    # in motion, beside the default scheme's runs (solid_pressure/gate_default_*): how far the gates move with it
    rungs.append(Rung("volumetric_gradient", "elastic_gate_dp1mm", "elastic_gate",
                      {"numerics.spacing": 0.001, **VOLUMETRIC, **PAPER_SPAN}, end_time=0.14,
                      note="the paper's gate at its 1 mm, the default scheme with solid.volumetric_gradient"))
    rungs.append(Rung("volumetric_gradient", "antoci_gate_dp1.67mm", "antoci_gate",
                      {"numerics.spacing": 0.005 / 3, **VOLUMETRIC}, end_time=0.4,
                      note="dp = 5/3 mm (3 particles through the gate); free end vs Antoci et al. 2007; the default "
                           "scheme with solid.volumetric_gradient"))
    return rungs


# The paper's gate on the narrowest periodic slab (the scene's span since 2026-12-05: 6 layers) beside the same run
# across the paper's 36 mm (each counterpart's kept run): whether the width of a slab uniform across y moves the answer
# (the main job's cost: docs/validation/OPEN.md 5). The default scheme and Gray's, at 3, 4 and 6 particles through.
def _gate_span_rungs():
    rungs = [Rung("gate_span", "default_dp1mm", "elastic_gate", {"numerics.spacing": 0.001}, end_time=0.14,
                  note="the paper's gate at 1 mm on the narrowest slab, the default scheme (the main job)",
                  counterpart="solid_pressure/gate_default_elastic_gate_dp1mm"),
             Rung("gate_span", "gray2001_dp1mm", "elastic_gate",
                  {"numerics.spacing": 0.001, "coupling.model": "pressure", "solid.scheme": "gray2001"}, end_time=0.14,
                  note="the paper's gate at 1 mm on the narrowest slab with the paper's scheme, solid.scheme = "
                       "gray2001",
                  counterpart="elastic_gate/pressure_dp1mm")]
    for dp, label, through in PAPER_GATE_LADDER:
        rungs.append(Rung("gate_span", f"default_{label}", "elastic_gate", {"numerics.spacing": dp}, end_time=0.14,
                          note=f"dp = {dp * 1e3:.3g} mm ({through} particles through the gate) on the narrowest slab, "
                               f"the default scheme", counterpart=f"solid_pressure/gate_default_elastic_gate_{label}"))
        rungs.append(Rung("gate_span", f"gray2001_{label}", "elastic_gate",
                          {"numerics.spacing": dp, "coupling.model": "pressure", "solid.scheme": "gray2001"},
                          end_time=0.14, note=f"dp = {dp * 1e3:.3g} mm ({through} particles through the gate) on the "
                                              f"narrowest slab, solid.scheme = gray2001",
                          counterpart=f"elastic_gate/pressure_{label}"))
    return rungs


def all_rungs():
    return (_cantilever_rungs() + _cantilever_shape_rungs() + _large_deflection_rungs() + _solid_static_rungs()
            + _clamp_effect_rungs() + _hydrostatic_plate_rungs() + _fluid_rungs() + _gate_rungs() + _gate_default_rungs()
            + _gate_static_rungs() + _solid_pressure_rungs() + _volumetric_gradient_rungs() + _gate_span_rungs()
            + spheric2.rungs())


# Names that select several cases at once.
CASE_GROUPS = {"gate": ("antoci_gate", "elastic_gate")}
