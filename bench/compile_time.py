"""The cold compile of a coupled scene, in the run's process alone against its kernels compiled in two processes at once
(sph_fsi_core/precompile.py): `python -m bench.compile_time [--scene elastic_gate] [--rounds 1]`.

Each measurement is a fresh `sph-fsi run SCENE --end-time T` with an empty NUMBA_CACHE_DIR of its own (so nothing is
shared between them and the project's cache is left alone), timed by the run's own line "compiled and took the
first step in N s"; the two ways alternate, and their order flips from round to round, so a drift of the host's
speed falls on both. Nothing else should run on the host meanwhile: two compiling processes need both cores.
"""
import argparse
import os
import re
import subprocess
import sys
import tempfile
import time
from pathlib import Path

WAYS = {"one process": "0", "two processes": "1"}
_COMPILED = re.compile(r"compiled and took the first step in (\d+) s")


def cold_run(scene, end_time, parallel, workdir):
    """Seconds from start to the end of the first step of a cold run (the run's own line), and the wall seconds."""
    cache = Path(tempfile.mkdtemp(prefix="numba_cache_", dir=workdir))
    env = dict(os.environ, NUMBA_CACHE_DIR=str(cache), SPH_FSI_PARALLEL_COMPILE=parallel)
    started = time.perf_counter()
    out = subprocess.run([sys.executable, "-m", "sph_fsi.cli", "run", scene, "--end-time", str(end_time), "--out",
                          str(cache / "run")], env=env, capture_output=True, text=True)
    wall = time.perf_counter() - started
    found = _COMPILED.search(out.stderr)
    if out.returncode != 0 or not found:
        raise RuntimeError(f"cold run of {scene} failed (exit {out.returncode}): {out.stderr.strip()[-400:]}")
    return int(found.group(1)), wall


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--scene", default="elastic_gate")
    parser.add_argument("--end-time", type=float, default=0.001, help="s: one outer step of the default scene")
    parser.add_argument("--rounds", type=int, default=1, help="pairs of cold runs (the order flips each round)")
    args = parser.parse_args(argv)
    rows = []
    with tempfile.TemporaryDirectory(prefix="compile_time_") as workdir:
        for r in range(args.rounds):
            order = list(WAYS) if r % 2 == 0 else list(WAYS)[::-1]
            for way in order:
                compiled, wall = cold_run(args.scene, args.end_time, WAYS[way], workdir)
                rows.append({"round": r + 1, "way": way, "compiled_s": compiled, "wall_s": round(wall, 1)})
                print(f"round {r + 1}, {way}: compiled and took the first step in {compiled} s", flush=True)
    load = os.getloadavg()[0]
    return {"scene": args.scene, "end_time": args.end_time, "rows": rows, "load_average": load}


def markdown(result):
    lines = [f"A cold `sph-fsi run {result['scene']} --end-time {result['end_time']:g}` (an empty NUMBA_CACHE_DIR each), to the end of "
             f"its first step (the run's own line), in the run's process alone (`SPH_FSI_PARALLEL_COMPILE=0`) and "
             f"with the solid's and the fluid's kernels compiled in two processes at once (sph_fsi_core/"
             f"precompile.py); load average after: {result['load_average']:.1f}.", "",
             "| round | way | compiled and took the first step [s] | wall [s] |", "|---|---|---|---|"]
    lines += [f"| {r['round']} | {r['way']} | {r['compiled_s']} | {r['wall_s']} |" for r in result["rows"]]
    return "\n".join(lines)


if __name__ == "__main__":
    print(markdown(main()))
