"""Antoci's gate held static, coupled and under its water's exact pressure (scenes/antoci_gate_static.py and
scenes/antoci_gate_loaded.py, judged by their evaluate against plane-strain FE): the load transfer apart from the
bending, one table."""
from ..report_tools import fmt
from ..rung import Rung
from .as_run import EXPLICIT_PRESSURE


# Antoci's gate held static under its water (config/antoci_gate_static.yaml) and under its water's exact pressure
# (config/antoci_gate_loaded.yaml), both against plane-strain FE: coupled against loaded is the load transfer, loaded
# against FE the gate's bending, at the validation spacings where the quadratic fit is determined (3 and 4 particles
# through the gate), with the antoci_gate scene's scheme; and the solid under the exact load with the default
# scheme and the mirrored clamp (as the plates converge, docs/validation/studies/solid_static).
GATE_STATIC_SPACINGS = ((0.005 / 3, "dp1.67mm"), (0.00125, "dp1.25mm"))


def rungs():
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


def table(out_dir, rungs, summaries):
    """Antoci's gate held static: coupled, under the exact pressure and FE, per spacing and scheme; the two ratios
    that separate the load transfer from the bending."""
    spacings = list(dict.fromkeys(r.label.rsplit("_", 1)[1] for r in rungs if r.case == "gate_static"))
    schemes = (("quadratic_plain_artificial_stress", "coupled", "loaded"),
               ("quadratic_gradient, mirrored clamp (default)", "coupled_gradient_mirrored",
                "loaded_gradient_mirrored"),
               ("the default, the push relaxed (coupling.relaxation 0.15)", "coupled_gradient_mirrored_relaxed",
                "loaded_gradient_mirrored"),
               ("the same, the water's density tolerance 0.3 %", "coupled_gradient_mirrored_relaxed_tol0.3pct",
                "loaded_gradient_mirrored"),
               ("the default, the water built compressed with its walls (geometry.water_start)",
                "coupled_gradient_mirrored_compressed", "loaded_gradient_mirrored"),
               ("the default as it is (implicit pressure), built compressed, to 0.6 s, the fluid's step 1 ms",
                "coupled_default_compressed_fluid_dt1ms", "loaded_gradient_mirrored"),
               ("the same, the fluid's step 0.5 ms", "coupled_default_compressed_fluid_dt0.5ms",
                "loaded_gradient_mirrored"))
    lines = []
    for label in spacings:
        for scheme, coupled_kind, loaded_kind in schemes:
            coupled, loaded = (s if s and s.get("tip_deflection_m") is not None else None for s in (
                summaries.get(f"gate_static/{kind}_{label}") for kind in (coupled_kind, loaded_kind)))
            if not any((coupled, loaded)) or (coupled is None and coupled_kind not in ("coupled",
                                                                                   "coupled_gradient_mirrored")):
                continue   # a variant not run at this spacing
            fe = next((s["reference_tip_deflection_m"] for s in (coupled, loaded)
                       if s and s.get("reference_tip_deflection_m")), None)

            def mm(s):
                return "not run" if s is None else f"{1e3 * s['tip_deflection_m']:.3f} ({s['wall_time_s']:.0f} s)"

            transfer = (f"{100 * (coupled['tip_deflection_m'] / loaded['tip_deflection_m'] - 1):+.2f} %"
                        if coupled and loaded else "-")
            bending = (f"{100 * loaded['error_signed']:+.2f} %" if loaded and loaded.get("error_signed") is not None
                       else "-")
            coupled_error = (f"{100 * coupled['error_signed']:+.2f} %"
                             if coupled and coupled.get("error_signed") is not None else "-")
            swing = f"{1e3 * coupled['tip_deflection_swing_m']:.3f}" if coupled else "-"
            load = (f"{1e3 * coupled['water_load_n']:.1f} / {1e3 * coupled['water_load_exact_n']:.1f} mN "
                    f"({100 * coupled['water_load_error']:+.1f} %)"
                    if coupled and coupled.get("water_load_n") is not None else "-")
            lines.append(f"| {label} | {scheme} | {mm(coupled)} | {swing} | {load} | {mm(loaded)} | "
                         f"{fmt(fe and 1e3 * fe, '.3f')} | {coupled_error} | {transfer} | {bending} |")
    if not lines:
        return []
    return ["", "## Antoci's gate held static (gate_static)", "",
            "The gap closed, gravity 1 m/s^2 (the free end deflects about 5 % of the gate's length), both phases "
            "relaxed to rest: the free end's settled deflection [mm] coupled (scenes/antoci_gate_static.py; its swing "
            "over the settled window; the water's push on the free length against the exact hydrostatic force), under "
            "the water's exact hydrostatic pressure (scenes/antoci_gate_loaded.py), and plane-strain FE of the free "
            "length read where the probe sits (the lowest particle layer, half a spacing above the free end), for the "
            "antoci_gate scene's former scheme and the default one. Coupled against FE is the whole answer; load "
            "transfer: coupled against loaded (same solid); bending: loaded against FE.", "",
            "| spacing | scheme | coupled | swing | water on the gate / exact | loaded | FE | coupled vs FE | "
            "load transfer | bending |",
            "|---|---|---|---|---|---|---|---|---|---|", *lines]
