"""The paper's gate on 2 Numba threads with one core taken by another busy process, at GNU OpenMP's default spin
and at the simulator's (`GOMP_SPINCOUNT`, sph_fsi_core/__init__.py): `python -m bench.shared_host [--rounds 2]`.

A thread that waits between parallel regions spins before it sleeps; the default's 300,000 spins hold the core the
working thread needs when another process runs on it, and every region then waits for the scheduler. Each
measurement is a process of its own (libgomp reads the count when it loads) that builds the gate, takes one outer
step and times the next `--steps`; the two counts alternate, with the busy process (a pure-Python loop) running and
without it. Nothing else should run on the host meanwhile.
"""
import argparse
import json
import os
import subprocess
import sys

SIMULATOR_SPINCOUNT = "1000"    # sph_fsi_core/__init__.py's
DEFAULT_SPINCOUNT = "300000"    # libgomp's with OMP_WAIT_POLICY unset
GATE = ["numerics.spacing=0.001", "geometry.span=0.036"]   # across the paper's 36 mm, as its BENCH.md rows were made

_MEASURE = """
import json, sys, time
from sph_fsi_core.scene import load_scene
from sph_fsi_core.simulation import Simulation
sim = Simulation(load_scene("elastic_gate", json.loads(sys.argv[1])))
sim.step()
started, steps0 = time.perf_counter(), sim.solid_phase.steps
for _ in range(int(sys.argv[2])):
    sim.step()
print(json.dumps({"seconds_per_outer_step": (time.perf_counter() - started) / int(sys.argv[2]),
                  "solid_steps": sim.solid_phase.steps - steps0}))
"""


def measure(spincount, steps, busy):
    """(seconds per outer step, solid sub-steps) of the gate on 2 threads at `spincount`, with a busy process."""
    env = dict(os.environ, GOMP_SPINCOUNT=spincount, NUMBA_NUM_THREADS="2")
    hog = subprocess.Popen([sys.executable, "-c", "while True: pass"]) if busy else None
    try:
        out = subprocess.run([sys.executable, "-c", _MEASURE, json.dumps(GATE), str(steps)], env=env,
                             capture_output=True, text=True, timeout=3600)
    finally:
        if hog is not None:
            hog.kill()
            hog.wait()
    if out.returncode != 0:
        raise RuntimeError(f"gate run failed: {out.stderr.strip()[-400:]}")
    return json.loads(out.stdout.strip().splitlines()[-1])


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--rounds", type=int, default=1)
    parser.add_argument("--steps", type=int, default=5, help="outer steps timed per measurement")
    args = parser.parse_args(argv)
    rows = []
    for r in range(args.rounds):
        for busy in (False, True):
            counts = (SIMULATOR_SPINCOUNT, DEFAULT_SPINCOUNT) if r % 2 == 0 else (DEFAULT_SPINCOUNT,
                                                                                SIMULATOR_SPINCOUNT)
            for spincount in counts:
                # the default spin on a shared host steps tens of times slower: fewer steps keep it to minutes
                steps = 1 if busy and spincount == DEFAULT_SPINCOUNT else args.steps
                result = measure(spincount, steps, busy)
                rows.append({"round": r + 1, "busy_process": busy, "spincount": spincount, "steps": steps, **result})
                print(f"round {r + 1}, {'one core busy' if busy else 'quiet'}, GOMP_SPINCOUNT={spincount}: "
                      f"{result['seconds_per_outer_step']:.3f} s per outer step", flush=True)
    return {"rows": rows, "load_average": os.getloadavg()[0]}


def markdown(result):
    lines = ["The paper's gate at 1 mm on 2 Numba threads, each measurement a process of its own (the build and one "
             "outer step, then the outer steps timed), with and without another busy process (a Python loop) on one "
             "of the 2 cores; GNU OpenMP's spin before a waiting thread sleeps at the simulator's count "
             f"({SIMULATOR_SPINCOUNT}) and at the default ({DEFAULT_SPINCOUNT}). Load average after: "
             f"{result['load_average']:.1f}.", "",
             "| round | another busy process | GOMP_SPINCOUNT | outer steps timed | s per outer step | solid sub-steps |",
             "|---|---|---|---|---|---|"]
    lines += [f"| {r['round']} | {'yes' if r['busy_process'] else 'no'} | {r['spincount']} | {r['steps']} | "
              f"{r['seconds_per_outer_step']:.3f} | {r['solid_steps']} |" for r in result["rows"]]
    return "\n".join(lines)


if __name__ == "__main__":
    print(markdown(main()))
