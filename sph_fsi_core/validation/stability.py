"""`sph-fsi stability`: stiff and extreme inputs, each with its outcome.

Every case ends in one of three outcomes, and which one is part of the case's definition (CI asserts it):

- stable: the run reached its end; the report gives the time step chosen, the energy drift (period-averaged
  kinetic + strain energy, largest growth from one period to the next) and the frequency error where there is
  a reference;
- refused: the input was rejected before any computation, with the message the user sees;
- diverged: the watchdog stopped the run, naming the check, the time and the particles; the outputs hold no
  NaN (checked here for every diverged case).

Solid cases run a few of their own natural periods (beam theory's first frequency for the case's E, nu, rho),
not a fixed physical time, so a steel beam costs about what a rubber one does: the solid step scales as
h / c0 and the period as L^2 sqrt(rho / E), so the steps per period do not depend on E. They use a 20 mm beam
at the paper's spacing (816 particles) to keep the whole table to minutes.
"""
import csv
import json
import math
import os
import sys
import time
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from . import DEFAULT_OUT_DIR
from ..answers.references import beam_theory_frequency

BEAM_LENGTH = 0.02


@dataclass(frozen=True)
class Case:
    name: str
    scene: str
    overrides: dict
    expect: str                 # stable | refused | diverged | stops (stable or diverged, never NaN)
    periods: float = 2.0        # solid cases: natural periods of the case's beam
    end_time: float = 0.0       # or a fixed end time
    ci: bool = False            # part of the CI subset
    why: str = ""


def _beam(**overrides):
    base = {"geometry.length": BEAM_LENGTH}
    base.update(overrides)
    return base


def solid_cases():
    cases = []
    for e, rho, nu, ci in ((1e5, 1000.0, 0.49, True), (1.859e6, 1000.0, 0.49, False), (2e8, 1000.0, 0.49, False),
                           (2e11, 7850.0, 0.3, True)):
        cases.append(Case(f"cantilever E = {e:.3g} Pa", "cantilever",
                          _beam(**{"solid.young_modulus": e, "solid.density": rho, "solid.poisson_ratio": nu}),
                          "stable", ci=ci, why="rubber to steel; dt follows c0 = sqrt(K / rho)"))
    for nu, ci in ((0.0, True), (0.3, False), (0.45, False), (0.49, False), (0.499, False)):
        cases.append(Case(f"cantilever nu = {nu:g}", "cantilever", _beam(**{"solid.poisson_ratio": nu}), "stable",
                          ci=ci, why="nu -> 0.5 makes the bulk modulus and c0 grow, so the step shrinks"))
    for vf in (1.0, 3.0, 6.0):
        cases.append(Case(f"cantilever free-end speed {vf:g} m/s", "cantilever",
                          _beam(**{"geometry.tip_velocity": vf}), "stable",
                          why="large deflection: amplitude Vf / (2 pi f) is a large fraction of L"))
    cases.append(Case("cantilever free-end speed 6 m/s, plain nodal sum", "cantilever",
                      _beam(**{"geometry.tip_velocity": 6.0, "solid.scheme": "quadratic_plain"}), "stops",
                      why="without the strain-gradient terms nothing resists the cell-scale modes of a large swing "
                          "(it lost 34 % of its energy at 3 m/s)"))
    cases.append(Case("cantilever 3 m/s, paper's SPH gradient, artificial stress off", "cantilever",
                      _beam(**{"geometry.tip_velocity": 3.0, "solid.scheme": "gray2001",
                               "solid.artificial_stress_epsilon": 0.0, "solid.cfl": 0.25}),   # cfl: as it was run
                      "stops",
                      why="the tensile instability Gray's artificial stress is there to prevent (the paper's scheme)"))
    fine_stubby = {"geometry.length": 0.01, "numerics.spacing": 0.0005}
    cases.append(Case("cantilever H/dp = 8, nu = 0.49", "cantilever", _beam(**fine_stubby), "stable",
                      why="fine spacing, nearly incompressible: the quadratic fit without artificial stress"))
    cases.append(Case("cantilever H/dp = 8, nu = 0.49, artificial stress 0.3", "cantilever",
                      _beam(**fine_stubby, **{"solid.artificial_stress_epsilon": 0.3}), "stops",
                      why="Gray's artificial stress is not paired with the strain rate: with the quadratic fit and "
                          "the plain nodal sum it feeds a growing mode (docs/method.md), which the strain-gradient "
                          "terms hold"))
    cases.append(Case("cantilever H/dp = 8, nu = 0.49, artificial stress 0.3, plain nodal sum", "cantilever",
                      _beam(**fine_stubby, **{"solid.scheme": "quadratic_plain",
                                              "solid.artificial_stress_epsilon": 0.3}), "stops",
                      why="the growing mode of the artificial stress with the quadratic fit and the plain sum"))
    for ratio in (1.0, 2.0):
        cases.append(Case(f"cantilever, the solid's h / dp {ratio:g}", "cantilever",
                          _beam(**{"geometry.tip_velocity": 1.0, "solid.smoothing_ratio": ratio}), "stable",
                          why="the ends of solid.smoothing_ratio's range, swinging at 1 m/s: at 1 the kernel reaches "
                              "the nearest 26 lattice neighbours, at 2 the nearest 250"))
    cases.append(Case("cantilever, forced dt 10x the stable limit", "cantilever",
                      _beam(**{"solid.time_step": 1.1e-4}), "refused", ci=True,
                      why="a step above the stable limit is refused, never silently used"))
    cases.append(Case("cantilever nu = 0.5", "cantilever", _beam(**{"solid.poisson_ratio": 0.5}), "refused",
                      ci=True, why="incompressible: K and c0 are infinite"))
    cases.append(Case("cantilever E = 0", "cantilever", _beam(**{"solid.young_modulus": 0.0}), "refused", ci=True,
                      why="no stiffness"))
    cases.append(Case("cantilever spacing larger than the beam", "cantilever",
                      _beam(**{"numerics.spacing": 0.005}), "refused", ci=True,
                      why="fewer than two particle layers through the thickness"))
    return cases


def fluid_cases():
    """Cases of the fluid scenes that exist (the fluid may be absent from an older checkout)."""
    from ..scene import builtin_scenes
    cases = []
    if "dam_break" in builtin_scenes():
        cases += [
            Case("dam break, tolerance 0.1 %", "dam_break", {"fluid.density_tolerance": 0.001}, "stops",
                 end_time=0.05, why="a very tight density criterion: more iterations, capped and reported"),
            Case("dam break, tolerance 20 %", "dam_break", {"fluid.density_tolerance": 0.2}, "stable",
                 end_time=0.05, ci=True, why="a very loose criterion: compressible, but it must not blow up"),
        ]
    return cases


def gate_cases():
    """The coupled gate (the paper's, at 2 mm, with the load-carrying 'pressure' coupling) under the same extremes, and
    Antoci's gate with a solid step above its limit.

    A fixed 0.04 s: the fluid sets the time scale here (the water reaches the gate's free end and pushes it), not
    the gate's own period; the solid sub-steps follow the solid's sound speed, so steel costs ~50x rubber.
    """
    from ..scene import builtin_scenes
    scenes = builtin_scenes()
    if "elastic_gate" not in scenes:
        return []
    # at 2 mm the gate is two particles thick, too few for the default scheme's quadratic fit (the gate's case
    # refuses it: scenes/cases/gate.py): these cases run the paper's scheme, as they were run before it became the default
    base = {"numerics.spacing": 0.002, "geometry.gate_clamp_height": 0.004, "coupling.model": "pressure",
            "solid.scheme": "gray2001"}
    cases = []
    for e, rho, nu, expect, ci in ((1e5, 1000.0, 0.49, "stable", True), (2e11, 7850.0, 0.3, "stable", False)):
        cases.append(Case(f"gate E = {e:.3g} Pa", "elastic_gate",
                          {**base, "solid.young_modulus": e, "solid.density": rho, "solid.poisson_ratio": nu},
                          expect, end_time=0.04, ci=ci,
                          why="rubber to steel in the coupled case: the solid sub-step ratio follows the stiffness"))
    cases.append(Case("gate with no gap", "elastic_gate", {**base, "geometry.gate_clearance": 0.0}, "stable",
                      end_time=0.04, ci=True,
                      why="the gate stands on the floor: no flow under it, the whole column leans on the plate"))
    cases.append(Case("gate under Wendland's water at h / dp 2, the solid at its own 1.3", "elastic_gate",
                      {**base, "fluid.kernel": "wendland_c2", "numerics.smoothing_ratio": 2.0,
                       "geometry.wall_layers": 4, "solid.smoothing_ratio": 1.3}, "stable", end_time=0.04,
                      why="a water kernel twice as wide as the solid's: the coupling's pairs reach 2h of the water's "
                          "into a gate two layers thick"))
    if "antoci_gate" in scenes:
        cases.append(Case("Antoci's gate, solid.cfl 0.6 (a runaway solid)", "antoci_gate",
                          {"numerics.spacing": 0.005 / 3, "solid.cfl": 0.6}, "diverged", end_time=0.05,
                          why="a solid step above its stable limit (the scheme's cfl is 0.25; 0.35 is marginal here: "
                              "docs/validation/OPEN.md 5): the solid blows up within the first outer steps and the "
                              "watchdog stops it with a diagnosis; a slower runaway, whose stable step falls as its "
                              "speed grows, is stopped before its sub-steps (test/test_coupling.py)"))
    return cases


def tall_column_cases():
    from ..scene import builtin_scenes
    if "dam_break" not in builtin_scenes():
        return []
    a = 0.05715
    return [Case("dam break, 10x taller column", "dam_break",
                 {"geometry.column_height": 20 * a, "geometry.wall_height": 1.2, "numerics.spacing": a / 10},
                 "stable", end_time=0.3, ci=True,
                 why="10x the head: ~3x the collapse speed and 10x the floor pressure; the step follows the speed")]


def all_cases():
    return solid_cases() + fluid_cases() + gate_cases() + tall_column_cases()


def _timing(case, spec):
    """{end time, sampling interval}: solid cases run `periods` of their own beam and sample 50 times a period."""
    if case.end_time:
        return {"scene.end_time": case.end_time}
    v = spec.values
    f = beam_theory_frequency(v["geometry.length"], v["geometry.thickness"], v["solid.young_modulus"],
                              v["solid.density"])
    return {"scene.end_time": case.periods / f, "output.timeseries_interval": 1.0 / (50.0 * f)}


def run_case(case, out_dir):
    """Run one case; returns its result row (dict)."""
    from ..run import run_scene
    from ..scene import load_scene
    from ..schema import SceneError
    row = {"case": case.name, "scene": case.scene, "expect": case.expect, "why": case.why,
           "overrides": {k: v for k, v in case.overrides.items()}}
    t0 = time.perf_counter()
    run_dir = Path(out_dir) / "runs" / _slug(case.name)
    try:
        spec = load_scene(case.scene, list(case.overrides.items()))
        spec = spec.with_overrides({**_timing(case, spec), "output.snapshot_interval": 0.0})
        # refusals that need the built state (e.g. a forced step above the limit) come from the build, before
        # the first step
        summary = run_scene(spec, run_dir, progress=False)
    except SceneError as exc:
        row.update(outcome="refused", detail=str(exc), wall_time_s=time.perf_counter() - t0)
        return row
    row["wall_time_s"] = time.perf_counter() - t0
    row["end_time_s"] = spec["scene.end_time"]
    row["solid_dt_s"] = summary.get("solid_dt_s")
    row["fluid_dt_s"] = summary.get("fluid_dt_s")
    row["warnings"] = summary.get("warnings", [])
    row["fluid_capped_steps"] = summary.get("fluid_capped_steps", 0)
    row["outputs_finite"] = _outputs_finite(run_dir)
    if summary["stable"]:
        row["outcome"] = "stable"
        parts = []
        if summary.get("solid_dt_s"):
            parts.append(f"solid dt {summary['solid_dt_s']:.3g} s")
        drift = _energy_drift(run_dir) if _conservative(case.scene) else None
        if drift is not None:
            row["energy_drift"] = drift
            parts.append(f"energy drift {100 * drift:+.2f} % (last quarter vs first quarter of the run)")
        error = summary.get("error_vs_euler_bernoulli_percent")
        if error is not None and math.isfinite(error):
            row["frequency_error"] = error
            parts.append(f"f = {summary['frequency_hz']:.4g} Hz ({error:+.1f} % vs beam theory)")
        gate = _gate_response(run_dir)
        if gate:
            row.update(gate)
            parts.append(f"free end's largest x displacement {1e3 * gate['tip_dx_peak_m']:+.3g} mm at "
                         f"{gate['tip_dx_peak_time_s']:.3g} s, {100 * gate['water_past_gate']:.1f} % of the water "
                         f"past the gate at the end")
        if summary.get("fluid_steps"):
            parts.append(f"fluid dt {summary['fluid_dt_s']:.3g} s, {summary['fluid_steps']} steps, "
                         f"{summary['fluid_iterations_per_step']:.1f} correction iterations per step, "
                         f"{summary['fluid_capped_steps']} steps at the iteration cap (reported as warnings)")
        row["detail"] = "; ".join(parts)
    else:
        d = summary["diverged"]
        row["outcome"] = "diverged"
        row["detail"] = f"{d['check']} at t = {d['time']:.4g} s: {d['detail']}"
    return row


def _slug(name):
    return "".join(c if c.isalnum() else "_" for c in name).strip("_")


def _series(run_dir):
    """The run's timeseries.csv as a list of {column: text} rows ([] when the run wrote none)."""
    path = Path(run_dir) / "timeseries.csv"
    if not path.is_file():
        return []
    with open(path) as fh:
        return list(csv.DictReader(fh))


def _energy_drift(run_dir):
    """Kinetic + strain energy averaged over the run's last quarter over that of its first quarter, minus 1."""
    rows = _series(run_dir)
    if len(rows) < 8 or "strain_energy" not in rows[0]:
        return None
    energy = np.array([float(r["kinetic_energy"]) + float(r["strain_energy"]) for r in rows])
    quarter = len(energy) // 4
    first = energy[:quarter].mean()
    return float(energy[-quarter:].mean() / first - 1.0) if first > 0 else None


def _conservative(scene):
    """Energy drift means something only where nothing feeds energy in (no gravity work, no inflow)."""
    from ..scene import load_scene
    from ..scenes import interface
    spec = load_scene(scene)
    return interface(spec.builder, spec.values).conservative


def _gate_response(run_dir):
    """Coupled scenes: the free end's largest x displacement and its time, and the water past the gate at the end."""
    rows = _series(run_dir)
    if not rows or "water_past_gate" not in rows[0]:
        return {}
    dx = np.array([float(r["tip_dx"]) for r in rows])
    i = int(np.argmax(np.abs(dx)))
    return {"tip_dx_peak_m": float(dx[i]), "tip_dx_peak_time_s": float(rows[i]["time"]),
            "water_past_gate": float(rows[-1]["water_past_gate"])}


def _outputs_finite(run_dir):
    """No NaN or inf in timeseries.csv: a diverged run stops before anything non-finite is written."""
    return all(math.isfinite(float(x)) for r in _series(run_dir) for x in r.values())


def outcome_ok(row):
    if row["outcome"] == "diverged" and not row.get("outputs_finite", True):
        return False
    if row["expect"] == "stops":
        return row["outcome"] in ("stable", "diverged")
    return row["outcome"] == row["expect"]


NOTES_HEADING = "## Reading the table"   # hand-written notes below this heading survive a rerun


def write_report(out_dir, rows, machine):
    out = Path(out_dir)
    page = out / "STABILITY.md"
    notes = ""
    if page.is_file():
        text = page.read_text()
        notes = text[text.find(NOTES_HEADING):] if NOTES_HEADING in text else ""
    lines = ["# Stability on stiff and extreme cases", "",
             "Made by `sph-fsi stability --out docs/validation` (`make stability ARGS=\"--out docs/validation\"`); "
             "every case, its expected and actual outcome. "
             "'stops' means: stable or stopped by the watchdog with a diagnosis, never a NaN.", "",
             f"Machine: {machine.get('cpus')} cores, {machine.get('numba_threads')} Numba threads, "
             f"commit {machine.get('commit')}; written {time.strftime('%Y-%m-%d')}, load average "
             f"{os.getloadavg()[0]:.1f} (wall times scale with the load).", "",
             "| case | expected | outcome | ok | wall [s] | detail |", "|---|---|---|---|---|---|"]
    for r in rows:
        detail = r.get("detail", "").replace("|", "/")
        lines.append(f"| {r['case']} | {r['expect']} | {r['outcome']} | {'yes' if outcome_ok(r) else '**NO**'} "
                     f"| {r.get('wall_time_s', 0):.1f} | {detail} |")
    lines += ["", "Why each case is there:", ""]
    lines += [f"- {r['case']}: {r['why']}" for r in rows]
    page.write_text("\n".join(lines) + "\n" + ("\n" + notes if notes else ""))
    (out / "stability.json").write_text(json.dumps(rows, indent=1, default=str) + "\n")


def _merged_with_earlier(out_dir, rows):
    """A rerun of some cases replaces their rows in the earlier table and keeps the others, in the table's order;
    rows of cases that no longer exist (renamed or removed) go."""
    path = Path(out_dir) / "stability.json"
    order = [c.name for c in all_cases()]
    earlier = {r["case"]: r for r in json.loads(path.read_text()) if r["case"] in order} if path.is_file() else {}
    earlier.update({r["case"]: r for r in rows})
    return sorted(earlier.values(), key=lambda r: order.index(r["case"]))


def main(ci=False, out_dir=DEFAULT_OUT_DIR, names=()):
    from ..run import machine_info
    cases = [c for c in all_cases() if (c.ci or not ci) and (not names or any(n in c.name for n in names))]
    Path(out_dir).mkdir(parents=True, exist_ok=True)
    rows = []
    for case in cases:
        row = run_case(case, out_dir)
        rows.append(row)
        print(f"  {case.name}: {row['outcome']} (expected {case.expect}) {row.get('detail', '')[:160]}", flush=True)
    write_report(out_dir, _merged_with_earlier(out_dir, rows) if names and not ci else rows, machine_info())
    bad = [r for r in rows if not outcome_ok(r)]
    for r in bad:
        print(f"sph-fsi stability: FAILED {r['case']}: expected {r['expect']}, got {r['outcome']}", file=sys.stderr)
    return 1 if bad else 0
