"""`sph-fsi sweep SCENE --vary KEY=V1,V2,... [--vary ...]`: a parameter study, one headless run per combination
of the varied values (their Cartesian product), as tasks (validation/tasks.py: here, a local Dask cluster with
--workers N, or any cluster with --scheduler ADDRESS), and one table of their summaries.

Each run goes into OUT/runs/<key>=<value>,.../ with its summary.json and timeseries.csv; OUT/sweep.csv has one row
per run: the varied keys, then the summary's scalars (status, stable, simulated time, wall time, steps, error and
whatever the scene measures). Every combination is validated before anything runs, so a bad value stops the sweep
at once with one line naming the key.
"""
import csv
import itertools
import sys
from pathlib import Path

from ..scene import load_scene, parse_override
from ..schema import SceneError
from .tasks import map_runs

__all__ = ["parse_vary", "run_sweep", "main"]

LEADING = ("status", "stable", "simulated_time_s", "wall_time_s", "error")


def parse_vary(text):
    """'solid.young_modulus=1e6,2e6' -> ('solid.young_modulus', [1000000.0, 2000000.0]), each value as YAML."""
    if "=" not in text:
        raise SceneError(f"--vary {text!r}: expected KEY=V1,V2,...")
    key, raw = text.split("=", 1)
    values = [parse_override(f"{key}={v.strip()}")[1] for v in raw.split(",") if v.strip()]
    if not values:
        raise SceneError(f"--vary {text!r}: no values; expected KEY=V1,V2,...")
    return parse_override(f"{key}={raw.split(',')[0].strip()}")[0], values


def _label(combo):
    return ",".join(f"{k}={v}" for k, v in combo)


def _run_point(job):
    scene, overrides, combo, end_time, out_dir = job
    from ..run import run_scene
    spec = load_scene(scene, list(overrides) + list(combo))
    return run_scene(spec, Path(out_dir) / "runs" / _label(combo), progress=False, end_time=end_time)


def run_sweep(scene, varies, overrides=(), end_time=None, out_dir="runs/sweep", workers=1, scheduler=None):
    """Run every combination; returns [(combo, summary)] in the order of the product and writes sweep.csv."""
    keys = [k for k, _ in varies]
    if len(set(keys)) != len(keys):
        raise SceneError(f"--vary: a key given twice ({', '.join(keys)}); allowed: each key once")
    combos = [tuple(zip(keys, values)) for values in itertools.product(*(v for _, v in varies))]
    for combo in combos:   # every point must be a valid scene before any runs
        load_scene(scene, list(overrides) + list(combo))
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    summaries = map_runs(_run_point, [(scene, tuple(overrides), combo, end_time, str(out)) for combo in combos],
                         workers, scheduler)
    rows = []
    for combo, s in zip(combos, summaries):
        row = dict(combo)
        row.update({k: s.get(k) for k in LEADING})
        row.update({k: v for k, v in s.items() if k not in row and isinstance(v, (int, float, str, bool))
                    and k not in ("scene", "builder", "source")})
        rows.append(row)
    columns = list(dict.fromkeys(c for row in rows for c in row))
    with open(out / "sweep.csv", "w", newline="") as f:
        writer = csv.DictWriter(f, fieldnames=columns)
        writer.writeheader()
        writer.writerows(rows)
    return list(zip(combos, summaries))


def main(args):
    """The CLI's `sweep` (sph_fsi/cli.py parses the arguments)."""
    varies = [parse_vary(v) for v in args.vary]
    overrides = [parse_override(s) for s in (args.set or [])]
    n = 1
    for _, values in varies:
        n *= len(values)
    print(f"sph-fsi sweep: {n} run(s) of '{args.scene}' into {args.out}/runs/"
          + (f" on {args.scheduler}" if args.scheduler else f" ({args.workers} worker(s))"), file=sys.stderr)
    results = run_sweep(args.scene, varies, overrides, args.end_time, args.out, args.workers, args.scheduler)
    for combo, s in results:
        error = s.get("error")
        print(f"  {_label(combo)}: {s['status']}, t = {s['simulated_time_s']:.6g} s, wall {s['wall_time_s']:.1f} s"
              + (f", error {error:.4g}" if isinstance(error, float) else ""), file=sys.stderr)
    print(f"sph-fsi sweep: table in {Path(args.out) / 'sweep.csv'}", file=sys.stderr)
    return 0 if all(s["stable"] for _, s in results) else 1
