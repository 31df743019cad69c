"""Solid particle-steps per second of the elastic solid at about 10^3, 10^4 and 10^5 particles, per solid scheme.

The cantilever builder scaled up (a thicker, wider, longer beam at 1 mm spacing, swinging in its first mode),
so the numbers are those of real stepping: every pass, the neighbour rebuilds, the watchdog. The solids are the
named schemes (sph_fsi_core/solid/schemes.py; docs/method.md, "Solid schemes"): 'quadratic_plain' (three pair
passes per step), 'quadratic_gradient' (the default, with the strain-gradient terms and the fit's refreshes) and
'gray2001' (the paper's: Gray's SPH gradient with his artificial stress, the scheme the 1 M target was set against).
Run with `python -m bench.solid_throughput` (or `make bench`); do not run two benchmarks at once on a 2-core machine.
"""
import argparse
import json
import time

import numba
import numpy as np

from sph_fsi_core.scene import load_scene
from sph_fsi_core.simulation import Simulation

# (length, width, thickness) in m at 1 mm spacing; the clamp adds its layers on top of the beam count.
SIZES = {"1e3": (0.020, 0.006, 0.008), "1e4": (0.040, 0.016, 0.016), "1e5": (0.100, 0.032, 0.032)}


# the solids measured: the named schemes
SCHEMES = ("quadratic_plain", "quadratic_gradient", "gray2001")


def beam_spec(label, overrides=()):
    """The bench's beam of size `label` (SIZES) as a scene, with `overrides` ("key=value") on top."""
    length, width, thickness = SIZES[label]
    return load_scene("cantilever", [f"geometry.length={length}", f"geometry.width={width}",
                                     f"geometry.thickness={thickness}", "geometry.clamp_margin=1",
                                     "output.snapshot_interval=0", *overrides])


def measure(label, scheme="quadratic_plain", steps_target=2.0e7, min_seconds=5.0):
    sim = Simulation(beam_spec(label, [f"solid.scheme={scheme}"]))
    sim.step()  # compile and warm up
    n = sim.particle_count
    start_steps, start_time, t0 = sim.solid_phase.steps, sim.time, time.perf_counter()
    while True:
        sim.step()
        elapsed = time.perf_counter() - t0
        done = (sim.solid_phase.steps - start_steps) * n
        if done >= steps_target or elapsed >= min_seconds:
            break
    pairs = sim.solid_phase.solver.neighbours.pairs / n
    # what the same simulated time takes in steps of the explicit pressure's limit (the bulk sound speed): with the
    # implicit pressure fewer, costlier steps do the same work, and what counts is the time to the answer
    vmax = float(np.sqrt((sim.solid.vel ** 2).sum(axis=1).max()))
    explicit_dt = sim.spec["solid.cfl"] * sim.solid_h / (sim.solid_phase.solver.settings.sound_speed + vmax)
    equivalent = (sim.time - start_time) / explicit_dt * n
    return {"label": label, "scheme": scheme, "particles": n, "pairs_per_particle": round(pairs, 1),
            "steps": sim.solid_phase.steps - start_steps, "seconds": round(elapsed, 3),
            "particle_steps_per_second": done / elapsed, "threads": numba.get_num_threads(),
            "neighbour_builds": sim.solid_phase.solver.neighbour_builds, "pressure": sim.spec["solid.pressure"],
            "explicit_equivalent_per_second": equivalent / elapsed}


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--sizes", nargs="*", default=list(SIZES))
    parser.add_argument("--seconds", type=float, default=5.0)
    parser.add_argument("--schemes", nargs="*", default=list(SCHEMES), choices=list(SCHEMES),
                        help="solid schemes to measure (solid.scheme)")
    args = parser.parse_args(argv)
    results = []
    for label in args.sizes:
        for scheme in args.schemes:
            r = measure(label, scheme, min_seconds=args.seconds)
            results.append(r)
            print(f"solid {r['particles']:>7d} particles ({r['pairs_per_particle']:.0f} pairs each), "
                  f"{scheme:>18s}: "
                  f"{r['particle_steps_per_second'] / 1e6:6.3f} M particle-steps/s over {r['steps']} steps "
                  f"({r['explicit_equivalent_per_second'] / 1e6:.3f} M in explicit-pressure steps), "
                  f"{r['threads']} threads", flush=True)
    return results


if __name__ == "__main__":
    print(json.dumps(main(), indent=1))
