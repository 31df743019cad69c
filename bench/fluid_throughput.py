"""Fluid particle-iterations per second of the density-correction fluid at about 10^4 and 10^5 fluid particles.

Two real scenes, scaled by the number of particle layers across their periodic slab:
- `dam_break`: Martin & Moyce's column collapsing (a few correction iterations per step, so the per-step work,
  neighbour-list rebuilds above all, weighs in);
- `tank`: the hydrostatic tank settling at a fixed step (tens of iterations per step: the correction loop itself).
Every step's passes, rebuilds, viscosity and the watchdog are timed; the first outer step (compilation, first
build) is not. A particle-iteration is one fluid particle through one correction iteration (density pass,
pressure, wall pressure, position correction); a particle-step one particle through one whole fluid step.
Run with `python -m bench.fluid_throughput` (or `make bench`); do not run two benchmarks at once on 2 cores.
"""
import argparse
import json
import os
import time

# GNU OpenMP threads spin between parallel regions; the correction loop runs four regions per iteration. On a
# shared machine (load above the core count) spinning threads that lose their core stall every region (measured
# 0.10 M particle-iterations/s spinning against 0.48 passive at load 4.3 on 2 cores), but on a quiet one passive
# waiting costs the tank at 10^5 particles 1.7x (both code versions). sph_fsi_core shortens the spin to 1000
# (GOMP_SPINCOUNT, its __init__.py): as fast as the default on a quiet host, 3x faster than it on this dam break with
# one other busy process in one hour (docs/method.md, "Performance design"). The benchmark measures what the command
# line and the node run; the table records the policy and the spin count.

import numba  # noqa: E402

from sph_fsi_core.scene import load_scene  # noqa: E402
from sph_fsi_core.simulation import Simulation  # noqa: E402

A = 0.05715
# (scene, overrides) per case and size; fluid particle counts in the comments.
CASES = {
    ("dam_break", "1e4"): ["numerics.spacing=%r" % (A / 20), "geometry.span_layers=12"],       # 20 x 40 x 12 = 9,600
    ("dam_break", "1e5"): ["numerics.spacing=%r" % (A / 40), "geometry.span_layers=31"],       # 40 x 80 x 31 = 99,200
    ("tank", "1e4"): ["numerics.spacing=0.0025", "geometry.span_layers=12", "fluid.time_step=0.002",
                      "output.timeseries_interval=0.002"],                                      # 20 x 40 x 12 = 9,600
    ("tank", "1e5"): ["numerics.spacing=0.00125", "geometry.span_layers=31", "fluid.time_step=0.001",
                      "output.timeseries_interval=0.001"],                                      # 40 x 80 x 31 = 99,200
}
SCENES = {"dam_break": "dam_break", "tank": "hydrostatic"}


def measure(case, size, min_seconds=10.0):
    spec = load_scene(SCENES[case], CASES[(case, size)] + ["output.snapshot_interval=0"])
    sim = Simulation(spec)
    sim.step()  # compile and warm up
    n = sim.fluid.count
    steps0, its0, builds0 = sim.fluid_phase.steps, sim.fluid_phase.iterations, sim.fluid_phase.solver.builds
    t0 = time.perf_counter()
    while True:
        sim.step()
        elapsed = time.perf_counter() - t0
        if elapsed >= min_seconds:
            break
    steps, its = sim.fluid_phase.steps - steps0, sim.fluid_phase.iterations - its0
    return {"case": case, "label": size, "fluid_particles": n, "wall_particles": sim.walls.count,
            "pairs_per_particle": round(sim.fluid_phase.solver.fluid_neighbours.pairs / n, 1), "steps": steps,
            "iterations_per_step": round(its / steps, 2), "seconds": round(elapsed, 3),
            "neighbour_builds": sim.fluid_phase.solver.builds - builds0,
            "particle_iterations_per_second": n * its / elapsed, "particle_steps_per_second": n * steps / elapsed,
            "threads": numba.get_num_threads(), "load_average": os.getloadavg()[0],
            "omp_wait_policy": os.environ.get("OMP_WAIT_POLICY", ""), "gomp_spincount": os.environ.get("GOMP_SPINCOUNT", "")}


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--cases", nargs="*", default=["dam_break", "tank"])
    parser.add_argument("--sizes", nargs="*", default=["1e4", "1e5"])
    parser.add_argument("--seconds", type=float, default=10.0)
    args = parser.parse_args(argv)
    results = []
    for case in args.cases:
        for size in args.sizes:
            r = measure(case, size, min_seconds=args.seconds)
            results.append(r)
            print(f"fluid {case:9s} {r['fluid_particles']:>7d} particles ({r['pairs_per_particle']:.0f} pairs each), "
                  f"{r['iterations_per_step']:.1f} iterations/step: "
                  f"{r['particle_iterations_per_second'] / 1e6:6.3f} M particle-iterations/s, "
                  f"{r['particle_steps_per_second'] / 1e6:6.3f} M particle-steps/s over {r['steps']} steps, "
                  f"{r['threads']} threads, load {r['load_average']:.1f}", flush=True)
    return results


if __name__ == "__main__":
    print(json.dumps(main(), indent=1))
