"""What the default solid step would cost with a cheaper pressure solve: an upper bound on what any faster solve
(preconditioner, fewer iterations, a better warm start) can give, before one is built.

The solid bench's beam (bench/solid_throughput.py, SIZES) with the default scheme, stepped in one process in three
variants, interleaved round by round (the host's speed drifts between processes: docs/performance/BENCH.md):
- `default`: the implicit pressure as every scene runs it (conjugate gradients to solid.pressure_tolerance);
- `tolerance_1e-2`: the solve stopped at a residual 100x larger (solid.pressure_tolerance = 0.01);
- `no_solve`: solid.pressure = explicit, the pressure in the momentum pass (every pass of the step but the solve).
The answers of the last two are not the default's; only the cost of a step is compared, in particle-steps per second
(the explicit variant's smaller step does not matter here: the measure is per step). A variant that diverges is
reported so (a solve capped at one iteration does, in the first step: the pressure is then nearly explicit at a step
six times its explicit limit).

    python -m bench.solid_step_parts [--size 1e5] [--rounds 3] [--seconds 8]
"""
import argparse
import json
import statistics
import time

import numba

from sph_fsi_core.diagnostics import Diverged
from sph_fsi_core.simulation import Simulation

from .solid_throughput import SIZES, beam_spec

VARIANTS = {"default": [], "tolerance_1e-2": ["solid.pressure_tolerance=0.01"], "no_solve": ["solid.pressure=explicit"]}


def build(label, extra):
    """The bench's beam with the variant's overrides, stepped once (compiled and warm); None if it diverged."""
    sim = Simulation(beam_spec(label, extra))
    try:
        sim.step()   # compiled and warm
    except Diverged as stop:
        print(f"{' '.join(extra) or 'default'}: {stop}", flush=True)
        return None
    return sim


def time_round(sim, seconds):
    """Outer steps for about `seconds`: (solid steps, elapsed s)."""
    start, t0 = sim.solid_phase.steps, time.perf_counter()
    while time.perf_counter() - t0 < seconds:
        sim.step()
    return sim.solid_phase.steps - start, time.perf_counter() - t0


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--size", default="1e5", choices=list(SIZES))
    parser.add_argument("--rounds", type=int, default=3)
    parser.add_argument("--seconds", type=float, default=8.0, help="per variant and round")
    args = parser.parse_args(argv)
    sims = {name: build(args.size, extra) for name, extra in VARIANTS.items()}
    sims = {name: sim for name, sim in sims.items() if sim is not None}
    rates = {name: [] for name in sims}
    for _ in range(args.rounds):
        for name, sim in list(sims.items()):
            try:
                steps, elapsed = time_round(sim, args.seconds)
            except Diverged as stop:
                print(f"{name}: {stop}", flush=True)
                del sims[name], rates[name]
                continue
            rates[name].append(steps * sim.particle_count / elapsed)
    n = sims["default"].particle_count
    result = {"particles": n, "threads": numba.get_num_threads(), "rounds": args.rounds,
              "iterations_per_step": {name: sim.solid_phase.solver.pressure_solve_stats()["iterations_per_step"]
                                      for name, sim in sims.items() if sim.solid_phase.solver.pressure_solve_stats()}}
    base = statistics.median(rates["default"])
    for name, values in rates.items():
        rate = statistics.median(values)
        result[name] = {"particle_steps_per_second": rate, "over_default": rate / base,
                        "rounds": [round(v) for v in values]}
        print(f"{name:>14s}: {rate / 1e6:.3f} M particle-steps/s (median of {args.rounds}), {rate / base:.2f}x the "
              f"default", flush=True)
    solves = ", ".join(f"{name} {its:.2f}" for name, its in result["iterations_per_step"].items())
    print(f"{n} particles, {result['threads']} threads; the solve's iterations per step: {solves}", flush=True)
    return result


if __name__ == "__main__":
    print(json.dumps(main(), indent=1))
