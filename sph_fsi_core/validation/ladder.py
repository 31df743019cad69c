"""`sph-fsi validate`: error against run time over resolution ladders, for every reference case.

Each case is a list of rungs (a scene plus overrides and an end time). A rung runs headless (run.run_scene)
into OUT/runs/CASE/RUNG/ and leaves its summary.json there: measured value, reference, error, wall time, steps,
particle-steps/s, stable. The report (OUT/REPORT.md and PNG plots) is made from those summaries, so it can be
rebuilt without rerunning (`--report-only`). `--quick` runs only the coarse rungs and asserts each error under
the bound stated with the rung; it is part of CI.
"""
import json
import shutil
import sys
import time
from pathlib import Path

from . import DEFAULT_OUT_DIR
from .cases import CASE_GROUPS, all_rungs
from .cases.cantilever import cantilever_end_time
from .rung import rung_error
from .tasks import map_runs


def rung_dir(out_dir, rung):
    return Path(out_dir) / "runs" / rung.case / rung.label


def run_rung(args):
    """Run one rung (in a worker process when --workers > 1); returns its summary."""
    rung, out_dir = args
    from ..run import run_scene
    from ..scene import load_scene
    overrides = dict(rung.overrides)
    end = rung.end_time or cantilever_end_time(overrides, rung.periods)
    overrides.update({"scene.end_time": end, "output.snapshot_interval": rung.snapshot_interval})
    spec = load_scene(rung.scene, list(overrides.items()))
    t0 = time.perf_counter()
    summary = run_scene(spec, rung_dir(out_dir, rung), progress=False)
    print(f"  {rung.key}: error {rung_error(rung, summary)}, wall {time.perf_counter() - t0:.1f} s, "
          f"stable {summary['stable']}", flush=True)
    return summary


def same_run(rung):
    """Rungs with the same scene, overrides and duration are one run (the sweep's L = 40 mm is the ladder's
    H/dp = 4)."""
    from ..scene import load_scene
    values = load_scene(rung.scene, list(rung.overrides.items())).values   # overrides equal to defaults count alike
    return rung.scene, repr(sorted(values.items())), rung.periods, rung.end_time


def run_rungs(rungs, out_dir, workers=1, scheduler=None):
    first = {}
    for r in rungs:
        first.setdefault(same_run(r), r)
    repeats = [r for r in rungs if first[same_run(r)] is not r]
    summaries = _run_distinct([r for r in rungs if r not in repeats], out_dir, workers, scheduler)
    for r in repeats:
        source = rung_dir(out_dir, first[same_run(r)])
        target = rung_dir(out_dir, r)
        shutil.rmtree(target, ignore_errors=True)
        shutil.copytree(source, target)
        print(f"  {r.key}: the same run as {first[same_run(r)].key}", flush=True)
    return summaries


def _run_distinct(rungs, out_dir, workers, scheduler=None):
    """Rungs are independent: tasks on a Dask cluster (validation/tasks.py) with more than one worker or a
    scheduler, else one after the other here."""
    return map_runs(run_rung, [(r, out_dir) for r in rungs], workers, scheduler)


def load_summaries(out_dir, rungs):
    found = {}
    for r in rungs:
        p = rung_dir(out_dir, r) / "summary.json"
        if p.is_file():
            found[r.key] = json.loads(p.read_text())
            kept = p.parent / "bits_unchanged.json"     # a run kept from an older commit (report._commit_cell)
            if kept.is_file():
                found[r.key]["bits_unchanged"] = json.loads(kept.read_text())
    return found


def main(cases=(), quick=False, workers=1, out_dir=DEFAULT_OUT_DIR, report_only=False, missing=False,
         scheduler=None):
    """`sph-fsi validate`: run the cases' rungs (`missing`: only those without a summary.json in out_dir yet),
    write the report, and return 0, or 1 if a rung did not finish stably (or, with `quick`, is above its bound)."""
    cases = tuple(c for name in cases for c in CASE_GROUPS.get(name, (name,)))
    rungs = [r for r in all_rungs(studies=bool(cases)) if (not cases or r.case in cases) and (r.quick or not quick)]
    if not rungs:
        known = sorted({r.case for r in all_rungs(studies=True)})
        print(f"sph-fsi validate: no such case {list(cases)}; allowed: {', '.join(known)}", file=sys.stderr)
        return 2
    if not report_only:
        todo = [r for r in rungs if not (missing and (rung_dir(out_dir, r) / "summary.json").exists())]
        print(f"sph-fsi validate: {len(todo)} run(s) into {out_dir}/runs/"
              + (f" ({len(rungs) - len(todo)} already there)" if missing else ""), flush=True)
        run_rungs(todo, out_dir, workers, scheduler)
    from .report import write_default_report, write_report
    # The report covers the cases asked for (all of them by default), so a fluid-only report does not list the
    # cantilever's rungs as "not run".
    reported = [r for r in all_rungs(studies=bool(cases)) if not cases or r.case in cases]
    summaries = load_summaries(out_dir, reported)
    (write_report if cases else write_default_report)(out_dir, reported, summaries)
    failed = []
    for r in rungs:
        s = summaries.get(r.key)
        if s is None:
            failed.append(f"{r.key}: not run (no summary.json in {rung_dir(out_dir, r)})")
        elif not s["stable"]:
            failed.append(f"{r.key}: did not finish stably")
        elif r.bound is not None and quick and (rung_error(r, s) is None or rung_error(r, s) > r.bound):
            failed.append(f"{r.key}: error {rung_error(r, s)} above the bound {r.bound}")
    for line in failed:
        print(f"sph-fsi validate: FAILED {line}", file=sys.stderr)
    return 1 if failed else 0
