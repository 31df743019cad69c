"""The default scheme's runs again with its pressure implicit (solid/implicit_pressure.py), each beside its explicit
counterpart of another case (judged by the same scene's evaluate): how far the answer moves, what the step saves."""
import json
from pathlib import Path

from ..report_tools import fmt
from ..rung import Rung
from . import cantilever_shapes, gate_default, gate_static, hydrostatic_plate, large_deflection, solid_static
from .as_run import EXPLICIT_PRESSURE, PAPER_SPAN
from .gate import PAPER_GATE_LADDER
from .large_deflection import LARGE_DEFLECTION_LOADS


def _twin(rung, label=None, **changes):
    """`rung` with the default scheme's implicit pressure (its EXPLICIT_PRESSURE pin dropped), in case
    solid_pressure, its explicit run as the counterpart."""
    overrides = {k: v for k, v in rung.overrides.items() if k not in EXPLICIT_PRESSURE}
    note = rung.note.replace(", solid.pressure = explicit", "").replace("solid.pressure = explicit", "")
    return Rung("solid_pressure", label or f"{rung.case}_{rung.label}", rung.scene, overrides, periods=rung.periods,
                end_time=rung.end_time, note=f"{note.rstrip(', ')}; the implicit pressure", counterpart=rung.key,
                **changes)


def rungs():
    """The default scheme's validated runs again with its pressure implicit (solid/implicit_pressure.py), each beside
    its explicit counterpart: how far the step set by the shear waves moves each answer, and
    what it saves. The gain is sqrt(3 K / 4 G): 6.1x at nu = 0.49, 1.9x at 0.4, 1.3x at 0.3. And the Antoci
    ladder's third rung (1 mm, 5 particles through the gate), affordable with it."""
    by_key = {r.key: r for r in (cantilever_shapes.rungs() + large_deflection.rungs() + solid_static.rungs()
                                 + gate_default.rungs() + gate_static.rungs() + hydrostatic_plate.rungs())}
    keys = ([f"cantilever_shapes/nu{nu:g}_L_over_H_10" for nu in (0.4, 0.49)]
            + ["cantilever_shapes/nu0.49_L_over_H_20", "cantilever_shapes/nu0.49_L_over_H_30"]
            + [f"large_deflection/alpha_{a:g}" for a in LARGE_DEFLECTION_LOADS]
            + [f"solid_static/quadratic_gradient_mirrored_t_over_dp_{n}" for n in (4, 6)]
            + ["gate_static/loaded_gradient_mirrored_dp1.67mm", "hydrostatic_plate/scaled_t_over_dp_4",
               "hydrostatic_plate/scaled_t_over_dp_6",
               "gate_default/elastic_gate_dp1mm", "gate_default/antoci_gate_dp1.67mm",
               "gate_default/antoci_gate_dp1.25mm", "gate_default/antoci_gate_E10MPa_nu0.49_dp1.67mm"])
    rungs = [_twin(by_key[k]) for k in keys]
    # the band's other edge one rung finer (each published material on the ladder)
    rungs.append(Rung("solid_pressure", "gate_default_antoci_gate_E10MPa_nu0.49_dp1.25mm", "antoci_gate",
                      {"numerics.spacing": 0.00125, "solid.young_modulus": 1.0e7, "solid.poisson_ratio": 0.49},
                      end_time=0.4, note="E = 10 MPa, nu = 0.49 (CoCoNuT's plane-strain FE row) at dp = 1.25 mm (4 "
                                         "particles through the gate); free end vs Antoci et al. 2007; the implicit "
                                         "pressure"))
    rungs.append(Rung("solid_pressure", "gate_default_antoci_gate_dp1mm", "antoci_gate", {"numerics.spacing": 0.001},
                      end_time=0.4, note="dp = 1 mm (5 particles through the gate); free end vs Antoci et al. 2007; "
                                         "the implicit pressure"))
    # the paper's gate on a ladder with the default scheme (which of the default's -7.4 mm and Gray's -8.2 mm at 1 mm is right): 3 and 6 particles through the 4 mm gate beside the 1 mm twin's 4.
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


def _answer(s):
    """The number a run is judged on, as (value, unit text, scale to that unit): the frequency, a static deflection or a
    gate's peak."""
    for key, unit, scale in (("frequency_hz", "Hz", 1.0), ("midspan_deflection_m", "um", 1e6),
                             ("tip_x_peak_m", "mm", 1e3), ("tip_dx_peak_m", "mm", 1e3),
                             ("tip_deflection_m", "mm", 1e3)):
        if s.get(key) is not None:
            return s[key], unit, scale
    return None, "", 1.0


def _error_text(s):
    e = s.get("error_signed", s.get("error"))
    if s.get("frequency_hz") is not None and s.get("reference_hz"):
        e = s["frequency_hz"] / s["reference_hz"] - 1.0
    return "-" if e is None else f"{100 * e:+.2f} %"


def table(out_dir, rungs, summaries):
    """Each solid_pressure run beside its explicit counterpart (read from the counterpart case's own report
    directory next to this one, runs/CASE/LABEL/summary.json): the answer, its error, the steps and the wall time."""
    runs = [r for r in rungs if r.case == "solid_pressure"]
    if not runs:
        return []
    lines = ["", "## The implicit pressure against the explicit one", "",
             "Each run with the default scheme's pressure advanced implicitly (solid/implicit_pressure.py; the step "
             "set by the shear waves) beside the same run with it explicit (the counterpart's own report, where it was "
             "validated). Moved: the answer's relative change. Wall times: each run's own host state (the column "
             "`threads, commit` above and the counterpart's report); compare them as orders, and the same-process "
             "ratio in docs/performance/BENCH.md.", "",
             "| run | explicit: answer, error | solid steps | wall [s] | implicit: answer, error | solid steps | "
             "wall [s] | moved | fewer steps | CG iterations per step |", "|---|---|---|---|---|---|---|---|---|---|"]
    for r in runs:
        new = summaries.get(r.key)
        old = None
        if r.counterpart:
            case, label = r.counterpart.split("/")
            path = Path(out_dir).parent / case / "runs" / case / label / "summary.json"
            old = json.loads(path.read_text()) if path.is_file() else None

        def cells(s):
            if s is None:
                return ["not run", "", ""]
            value, unit, scale = _answer(s)
            answer = "-" if value is None else f"{scale * value:.4g} {unit}"
            return [f"{answer}, {_error_text(s)}", f"{s['solid_steps']}", f"{s['wall_time_s']:.0f}"]

        moved = steps = "-"
        if new is not None and old is not None:
            a, b = _answer(old)[0], _answer(new)[0]
            if a and b is not None:
                moved = f"{100 * (b / a - 1.0):+.2f} %"
            if new["solid_steps"]:
                steps = f"{old['solid_steps'] / new['solid_steps']:.2f}x"
        solve = (new or {}).get("solid_pressure_solve") or {}
        iterations = fmt(solve.get("iterations_per_step"), ".1f")
        label = r.label if r.counterpart else f"{r.label} (no explicit run)"
        lines.append(f"| {label} | " + " | ".join(cells(old) + cells(new)) + f" | {moved} | {steps} | {iterations} |")
    return lines
