"""`sph-fsi validate`: error against run time over resolution ladders, for every reference case.

Each case is a list of rungs (a scene plus overrides and an end time). A rung runs headless (run.run_scene)
into OUT/runs/CASE/RUNG/ and leaves its summary.json there: measured value, reference, error, wall time, steps,
particle-steps/s, stable. The report (OUT/REPORT.md and PNG plots) is made from those summaries, so it can be
rebuilt without rerunning (`--report-only`). `--quick` runs only the coarse rungs and asserts each error under
the bound stated with the rung; it is part of CI.
"""
import json
import multiprocessing
import os
import shutil
import sys
import time
from dataclasses import dataclass
from pathlib import Path


@dataclass(frozen=True)
class Rung:
    case: str
    label: str
    scene: str
    overrides: dict
    periods: float = 0.0        # cantilever rungs: run this many periods of the reference frequency
    end_time: float = 0.0       # or a fixed end time
    quick: bool = False         # part of --quick (CI)
    bound: float = None         # --quick asserts error <= bound
    note: str = ""
    snapshot_interval: float = 0.0   # particle snapshots (0: none), for the frame plots

    @property
    def key(self):
        return f"{self.case}/{self.label}"


def _cantilever_end_time(overrides, periods):
    from .references import cantilever_references
    length = overrides.get("geometry.length", 0.04)
    refs = cantilever_references(length, 0.004, 0.006, 1.859e6, 0.49, 1000.0)
    return periods / refs["reference_hz"]


def _cantilever_rungs():
    rungs = []
    # The scene's scheme: the quadratic fit with the strain-gradient nodal integration (config/cantilever.yaml).
    # Resolution ladder H/dp = 4, 6, 8 (2.25 periods of the reference each: the zero-crossing fit and the damping
    # ratio need two full periods of the tip). CI runs H/dp = 4 (the paper's spacing), bound 3 %.
    for ratio, quick in ((4, True), (6, False), (8, False)):
        dp = 0.004 / ratio
        rungs.append(Rung("cantilever_ladder", f"H_over_dp_{ratio}", "cantilever",
                          {"numerics.spacing": dp}, periods=2.25, quick=quick, bound=0.03,
                          note=f"dp = {dp * 1e3:.3f} mm"))
    # Length sweep at dp = 1 mm, as the paper's Fig. 5 (2.25 periods, as the ladder; shorter records let the
    # free end's higher modes bias the frequency). The cost grows as L^3 (particles x period).
    rungs += [Rung("cantilever_length", f"L{length_mm}", "cantilever", {"geometry.length": length_mm * 1e-3},
                   periods=2.25, note=f"L = {length_mm} mm, dp = 1 mm") for length_mm in (40, 60, 80, 100, 120)]
    # The paper's beam at the paper's spacing, 10 periods: frequency, damping, energy, sideways mode.
    rungs.append(Rung("cantilever", "L40_dp1.0_10periods", "cantilever", {}, periods=10.0,
                      note="the paper's beam, 10 periods"))
    # The same beams with the plain nodal integration (each particle's strain at its centre, the scheme before
    # the gradient integration; a 4-layer beam's EI 6 % short, docs/method.md).
    plain = {"solid.nodal_integration": "plain"}
    for ratio in (4, 6, 8):
        dp = 0.004 / ratio
        rungs.append(Rung("cantilever_plain_ladder", f"H_over_dp_{ratio}", "cantilever",
                          {"numerics.spacing": dp, **plain}, periods=2.25,
                          note=f"dp = {dp * 1e3:.3f} mm, solid.nodal_integration = plain"))
    rungs += [Rung("cantilever_plain_length", f"L{length_mm}", "cantilever",
                   {"geometry.length": length_mm * 1e-3, **plain}, periods=2.25,
                   note=f"L = {length_mm} mm, dp = 1 mm, solid.nodal_integration = plain")
              for length_mm in (40, 60, 80, 100, 120)]
    rungs.append(Rung("cantilever_plain", "L40_dp1.0_10periods", "cantilever", plain, periods=10.0,
                      note="the paper's beam, 10 periods, solid.nodal_integration = plain"))
    # The paper's own scheme (Gray's SPH gradient, plain sum) on the same beams: close at L = 40 mm, too stiff
    # beyond.
    for length_mm in (40, 60, 80):
        rungs.append(Rung("cantilever_paper_scheme", f"L{length_mm}", "cantilever",
                          {"geometry.length": length_mm * 1e-3, "solid.velocity_gradient": "sph", **plain},
                          periods=2.25, note=f"L = {length_mm} mm, dp = 1 mm, solid.velocity_gradient = sph"))
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
    return rungs


def _gate_rungs():
    """The coupled cases (issue 4), both coupling models at two resolutions each.

    antoci_gate: Antoci et al. 2007's measured free end over 0-0.4 s at dp = 2.5 mm (2 particles through the 5 mm
    gate) and 5/3 mm (3) with Gray's SPH gradient, and at 5/3 and 1.25 mm (4) with the quadratic fit (the scene's
    solid since session 3). elastic_gate: the paper's case to t = 0.14 s at 2 mm and at the paper's 1 mm (80k-particle
    class runs: the 1 mm rungs are the long ones). CI runs shorter versions (test/validation/test_gate_quick.py).
    """
    rungs = []
    for dp, label in ((0.0025, "dp2.5mm"), (0.005 / 3, "dp1.67mm")):
        for model in ("pressure", "seed"):
            rungs.append(Rung("antoci_gate", f"{model}_{label}", "antoci_gate",
                              {"numerics.spacing": dp, "coupling.model": model, "solid.velocity_gradient": "sph"},
                              end_time=0.4, note=f"dp = {dp * 1e3:.3g} mm, coupling {model}, Gray's SPH gradient; "
                                                 f"free end vs Antoci et al. 2007"))
    # With three layers through the 5 mm gate the default quadratic-fit solid is determined; the scene pins Gray's
    # SPH gradient (its runs' scheme), which is too stiff at this gate's L/H = 16 (FINDINGS.md).
    for dp, label in ((0.005 / 3, "dp1.67mm"), (0.00125, "dp1.25mm")):
        rungs.append(Rung("antoci_gate", f"pressure_quadratic_{label}", "antoci_gate",
                          {"numerics.spacing": dp, "coupling.model": "pressure",
                           "solid.velocity_gradient": "quadratic"}, end_time=0.4,
                          note=f"dp = {dp * 1e3:.3g} mm, coupling pressure, solid.velocity_gradient = quadratic"))
    # The scene keeps Gray's artificial stress (eps = 0.15, its runs above); the quadratic fit needs none, and at
    # nu = 0.49 it feeds a growing mode (docs/method.md): the same run without it.
    rungs.append(Rung("antoci_gate", "pressure_quadratic_eps0_dp1.67mm", "antoci_gate",
                      {"numerics.spacing": 0.005 / 3, "coupling.model": "pressure",
                       "solid.velocity_gradient": "quadratic", "solid.artificial_stress_epsilon": 0.0}, end_time=0.4,
                      note="dp = 1.67 mm, coupling pressure, quadratic fit, no artificial stress"))
    # Three layers through the gate sum z^2 = 2 dp^2 where the section has H^3 / 12 = 2.25 dp^2: the plain nodal sum
    # leaves the gate 11 % soft in bending; the strain-gradient nodal integration puts it back (docs/method.md).
    rungs.append(Rung("antoci_gate", "pressure_gradient_eps0_dp1.67mm", "antoci_gate",
                      {"numerics.spacing": 0.005 / 3, "coupling.model": "pressure",
                       "solid.velocity_gradient": "quadratic", "solid.artificial_stress_epsilon": 0.0,
                       "solid.nodal_integration": "gradient"}, end_time=0.4,
                      note="dp = 1.67 mm, coupling pressure, quadratic fit, strain-gradient nodal integration"))
    for dp, label, extra in ((0.002, "dp2mm", {"geometry.gate_clamp_height": 0.004}), (0.001, "dp1mm", {})):
        for model in ("seed", "pressure"):
            rungs.append(Rung("elastic_gate", f"{model}_{label}", "elastic_gate",
                              {"numerics.spacing": dp, "coupling.model": model, **extra}, end_time=0.14,
                              snapshot_interval=0.02,
                              note=f"dp = {dp * 1e3:g} mm, coupling {model}; the paper's Figs. 6-8 (qualitative)"))
    # At 1 mm the paper's gate is 4 particles thick, enough for the quadratic-fit solid (the scene pins Gray's
    # gradient for its 2 mm runs, where the gate is 2 particles thick and the fit falls back to linear).
    rungs.append(Rung("elastic_gate", "pressure_quadratic_dp1mm", "elastic_gate",
                      {"numerics.spacing": 0.001, "coupling.model": "pressure", "solid.velocity_gradient": "quadratic",
                       "solid.artificial_stress_epsilon": 0.0,
                       "solid.cfl": 0.25},   # as it was validated: the scene's 0.5 suits Gray's gradient, not the fit
                      end_time=0.14, snapshot_interval=0.02,
                      note="dp = 1 mm, coupling pressure, quadratic-fit solid without artificial stress"))
    return rungs


CANTILEVER_CASES = ("cantilever", "cantilever_ladder", "cantilever_length", "cantilever_plain",
                    "cantilever_plain_ladder", "cantilever_plain_length", "cantilever_paper_scheme")


def all_rungs():
    return _cantilever_rungs() + _fluid_rungs() + _gate_rungs()


def _rung_dir(out_dir, rung):
    return Path(out_dir) / "runs" / rung.case / rung.label


def run_rung(args):
    """Run one rung (in a worker process when --workers > 1); returns its summary."""
    rung, out_dir = args
    from .run import run_scene
    from .scene import load_scene
    overrides = dict(rung.overrides)
    end = rung.end_time or _cantilever_end_time(overrides, rung.periods)
    overrides.update({"scene.end_time": end, "output.snapshot_interval": rung.snapshot_interval})
    spec = load_scene(rung.scene, list(overrides.items()))
    t0 = time.perf_counter()
    summary = run_scene(spec, _rung_dir(out_dir, rung), progress=False)
    print(f"  {rung.key}: error {summary.get('error')}, wall {time.perf_counter() - t0:.1f} s, "
          f"stable {summary['stable']}", flush=True)
    return summary


def _same_run(rung):
    """Rungs with the same scene, overrides and duration are one run (the sweep's L = 40 mm is the ladder's H/dp = 4)."""
    from .scene import load_scene
    values = load_scene(rung.scene, list(rung.overrides.items())).values   # overrides equal to defaults count alike
    return rung.scene, repr(sorted(values.items())), rung.periods, rung.end_time


def run_rungs(rungs, out_dir, workers=1):
    first = {}
    for r in rungs:
        first.setdefault(_same_run(r), r)
    repeats = [r for r in rungs if first[_same_run(r)] is not r]
    summaries = _run_distinct([r for r in rungs if r not in repeats], out_dir, workers)
    for r in repeats:
        source = _rung_dir(out_dir, first[_same_run(r)])
        target = _rung_dir(out_dir, r)
        shutil.rmtree(target, ignore_errors=True)
        shutil.copytree(source, target)
        print(f"  {r.key}: the same run as {first[_same_run(r)].key}", flush=True)
    return summaries


def _run_distinct(rungs, out_dir, workers):
    jobs = [(r, out_dir) for r in rungs]
    if workers > 1:
        # Rungs are independent. Each worker gets cores / workers Numba threads: more threads than cores makes
        # OpenMP's spinning threads wait on each other and runs several times slower, not a little.
        threads = max(1, (os.cpu_count() or 1) // workers)
        saved = os.environ.get("NUMBA_NUM_THREADS")
        os.environ["NUMBA_NUM_THREADS"] = str(threads)     # spawned workers inherit the environment
        try:
            with multiprocessing.get_context("spawn").Pool(workers) as pool:
                return pool.map(run_rung, jobs, chunksize=1)
        finally:
            if saved is None:
                os.environ.pop("NUMBA_NUM_THREADS", None)
            else:
                os.environ["NUMBA_NUM_THREADS"] = saved
    return [run_rung(j) for j in jobs]


def load_summaries(out_dir, rungs):
    found = {}
    for r in rungs:
        p = _rung_dir(out_dir, r) / "summary.json"
        if p.is_file():
            found[r.key] = json.loads(p.read_text())
    return found


# Names that select several cases at once.
CASE_GROUPS = {"gate": ("antoci_gate", "elastic_gate")}


def main(cases=(), quick=False, workers=1, out_dir="docs/validation", report_only=False):
    cases = tuple(c for name in cases for c in CASE_GROUPS.get(name, (name,)))
    rungs = [r for r in all_rungs() if (not cases or r.case in cases) and (r.quick or not quick)]
    if not rungs:
        known = sorted({r.case for r in all_rungs()})
        print(f"sph-fsi validate: no such case {list(cases)}; allowed: {', '.join(known)}", file=sys.stderr)
        return 2
    if not report_only:
        print(f"sph-fsi validate: {len(rungs)} run(s) into {out_dir}/runs/", flush=True)
        run_rungs(rungs, out_dir, workers)
    from .validation_report import write_report
    # The report covers the cases asked for (all of them by default), so a fluid-only report does not list the
    # cantilever's rungs as "not run".
    reported = [r for r in all_rungs() if not cases or r.case in cases]
    summaries = load_summaries(out_dir, reported)
    write_report(out_dir, reported, summaries)
    failed = []
    for r in rungs:
        s = summaries.get(r.key)
        if s is None or not s["stable"]:
            failed.append(f"{r.key}: did not finish stably")
        elif r.bound is not None and quick and (s.get("error") is None or s["error"] > r.bound):
            failed.append(f"{r.key}: error {s.get('error')} above the bound {r.bound}")
    for line in failed:
        print(f"sph-fsi validate: FAILED {line}", file=sys.stderr)
    return 1 if failed else 0
