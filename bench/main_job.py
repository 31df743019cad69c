"""The main job's speed: the paper's gate at 1 mm (`make run`), simulated time per wall second, this checkout against
another commit in the same process, and this checkout's whole run.

    python -m bench.main_job [--ref 9a465fb] [--window 0.02] [--full]

Both versions build the scene `elastic_gate` as each one's defaults have it (the reference commit's own solid scheme:
at 9a465fb Gray's, the paper's; here the default scheme; at 9a465fb across the paper's 36 mm, here the narrowest
periodic slab, which gives the same answer: docs/validation/studies/gate_span), step to t = 2 ms
(compiling and the first load), then alternate one outer step (1 ms) each until `--window` of simulated time is done,
timing each step: the ratio of simulated seconds per wall second (not particle-steps: the versions take steps of
different sizes, and different numbers of particles for the same answer). The gate's first
20 ms are its slow start (the water pushes, the gate has barely moved): the fit's refreshes and the neighbour
rebuilds grow as it swings, so `--full` also times this checkout's whole run to 0.14 s.
On this 2-core VM a process can run at half speed for its whole life (docs/performance/BENCH.md): only the ratio in
one process compares versions; the absolute times carry the host's load.
"""
import argparse
import os
import sys
import tempfile
import time
from pathlib import Path


from .compare_versions import export, import_version

SCENE = "elastic_gate"
WARMUP = 0.002   # s simulated before timing


def _load(package, cache_dir=None):
    scene = import_version(package, "scene", cache_dir)
    simulation = import_version(package, "simulation", cache_dir)
    return simulation.Simulation(scene.load_scene(SCENE, ["output.snapshot_interval=0"]))


def _tip_dx(sim):
    probe = sim.probe_displacements()
    return float(next(iter(probe.values()))[0]) if probe else float("nan")


def compare(ref, window):
    """{version: {...}} for the reference commit and this checkout over `window` s of simulated time after WARMUP."""
    with tempfile.TemporaryDirectory() as tmp:
        sys.path.insert(0, str(export(ref, Path(tmp))))
        sims = {ref: _load("ref_core", Path(tmp) / "numba"), "this checkout": _load("sph_fsi_core")}
        for sim in sims.values():
            while sim.time < WARMUP - 1e-12:
                sim.step()
        wall = {name: 0.0 for name in sims}
        start = {name: (sim.time, sim.solid_phase.steps, sim.fluid_phase.steps) for name, sim in sims.items()}
        while min(sim.time for sim in sims.values()) < WARMUP + window - 1e-12:
            for name, sim in sims.items():
                t0 = time.perf_counter()
                sim.step()
                wall[name] += time.perf_counter() - t0
        out = {}
        for name, sim in sims.items():
            t0, solid0, fluid0 = start[name]
            simulated = sim.time - t0
            out[name] = {"simulated_s": simulated, "wall_s": wall[name], "rate": simulated / wall[name],
                         "solid_steps": sim.solid_phase.steps - solid0, "fluid_steps": sim.fluid_phase.steps - fluid0,
                         "scheme": sim.spec.values.get("solid.scheme", sim.spec.values.get("solid.velocity_gradient")),
                         "particles": sim.particle_count,
                         "tip_dx_m": _tip_dx(sim)}
        sys.path.pop(0)
        return out


def full_run():
    """This checkout's whole main job, stepping only (the build and the first step's compiling left out)."""
    sim = _load("sph_fsi_core")
    sim.step()
    t0 = time.perf_counter()
    end = sim.spec["scene.end_time"]
    while sim.time < end - 1e-12:
        sim.step()
    return {"stepping_s": time.perf_counter() - t0, "simulated_s": sim.time, "solid_steps": sim.solid_phase.steps,
            "fluid_steps": sim.fluid_phase.steps, "pressure": sim.solid_phase.solver.pressure_solve_stats()}


def markdown(ref, result, full=None):
    this = result["this checkout"]
    old = result[ref]
    lines = [f"The paper's gate at 1 mm, each version's own defaults, simulated t = "
             f"{1e3 * WARMUP:g}-{1e3 * (WARMUP + this['simulated_s']):g} ms alternating outer steps in one process "
             f"(`python -m bench.main_job --ref {ref}`):", "",
             "| version | solid scheme | particles | solid steps | fluid steps | wall [s] | simulated ms per wall s | "
             "free end dx [mm] |", "|---|---|---|---|---|---|---|---|"]
    for name, r in result.items():
        lines.append(f"| {name} | {r['scheme']} | {r['particles']:,} | {r['solid_steps']} | {r['fluid_steps']} | "
                     f"{r['wall_s']:.1f} | "
                     f"{1e3 * r['rate']:.3f} | {1e3 * r['tip_dx_m']:.4f} |")
    lines += ["", f"Speed-up of this checkout over {ref}: **{this['rate'] / old['rate']:.2f}x** in simulated time per "
                  f"wall second."]
    if full:
        lines += ["", f"This checkout's whole run to {full['simulated_s']:.3g} s: {full['stepping_s']:.0f} s of "
                      f"stepping ({full['solid_steps']} solid steps, {full['fluid_steps']} fluid steps; implicit "
                      f"pressure {full['pressure']['iterations_per_step']:.1f} iterations per step)"
                  if full.get("pressure") else
                  f"This checkout's whole run to {full['simulated_s']:.3g} s: {full['stepping_s']:.0f} s of stepping."]
    return "\n".join(lines)


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--ref", default="9a465fb", help="the commit to compare with (default: 9a465fb, the gate before the default scheme)")
    parser.add_argument("--window", type=float, default=0.02, help="simulated seconds timed after the warm-up")
    parser.add_argument("--full", action="store_true", help="also time this checkout's whole run")
    args = parser.parse_args(argv)
    result = compare(args.ref, args.window)
    full = full_run() if args.full else None
    print(markdown(args.ref, result, full))
    print(f"load average over the last minute: {os.getloadavg()[0]:.2f}")
    return {"ref": args.ref, "result": result, "full": full}


if __name__ == "__main__":
    main()
