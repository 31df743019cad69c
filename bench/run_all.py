"""`make bench`: every benchmark, one after the other (never two at once on a 2-core machine), results written to
runs/bench/BENCH.md (`--out docs/performance/BENCH.md` publishes them) with the machine and commit they ran on."""
import argparse
import datetime
from pathlib import Path

from sph_fsi_core.run import machine_info

from . import (compile_time, fluid_throughput, main_job, publishing_cost, recording_cost, shared_host, solid_throughput,
               thread_scaling)


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--out", default="runs/bench/BENCH.md",
                        help="where BENCH.md goes (--out docs/performance/BENCH.md publishes the project's)")
    parser.add_argument("--seconds", type=float, default=10.0, help="minimum measuring time per size")
    args = parser.parse_args(argv)
    solid = solid_throughput.main(["--seconds", str(args.seconds)])
    fluid = fluid_throughput.main(["--seconds", str(args.seconds)])
    m = machine_info()
    lines = ["# Benchmarks", "",
             "Made by `make bench ARGS=\"--out docs/performance/BENCH.md\"` (`python -m bench.run_all`).", "",
             f"Machine: {m['cpus']} CPUs, {m['numba_threads']} Numba threads, {m['platform']}, Python {m['python']}, "
             f"Numba {m['numba']}, NumPy {m['numpy']}; commit {m['commit']}; {datetime.date.today().isoformat()}.", "",
             "## Elastic solid (Gray 2001), particle-steps per second", "",
             "A cantilever scaled up at 1 mm spacing, swinging in its first mode; every solid step's passes, "
             "neighbour rebuilds and the watchdog included. Pairs: the half list (each pair once) within 2h + skin.", "",
             "Solid: the named schemes (`solid.scheme`; docs/method.md, \"Solid schemes\"): 'quadratic_plain' "
             "(three pair passes per step), 'quadratic_gradient' (the default: a fourth pair pass, a heavier momentum "
             "pass and the fit refreshed as the beam turns) and 'gray2001' (the paper's: Gray's SPH gradient and "
             "artificial stress, epsilon 0.15, solid.cfl 0.5).", "",
             "The pressure: 'implicit' (the default scheme's: a step set by the shear waves, 6x longer at nu = 0.49, "
             "each costlier) or 'explicit'. Equivalent: the particle-steps the same simulated time takes in steps of "
             "the explicit pressure's limit, per second: the measure of time to the answer across the two.", "",
             "| particles | solid | pressure | pairs per particle | steps | seconds | M particle-steps/s | "
             "M equivalent explicit particle-steps/s |",
             "|---|---|---|---|---|---|---|---|"]
    for r in solid:
        lines.append(f"| {r['particles']} | {r['scheme']} | {r['pressure']} | {r['pairs_per_particle']} | "
                     f"{r['steps']} | {r['seconds']} | {r['particle_steps_per_second'] / 1e6:.3f} | "
                     f"{r['explicit_equivalent_per_second'] / 1e6:.3f} |")
    lines += ["", "## Fluid (Okaji density correction), particle-iterations per second", "",
              "Two scenes scaled by their periodic slab's thickness: the dam break (a few correction iterations per "
              "step, so neighbour-list rebuilds weigh in) and the hydrostatic tank at a fixed step (tens of "
              "iterations per step). A particle-iteration is one fluid particle through one correction iteration "
              "(density, pressure, wall pressure, position correction); the time is that of whole steps "
              "(rebuilds, viscosity, watchdog included). Load: the machine's 1-minute load average during the run "
              "(2 cores; above 2 means the run shared them).", "",
              "| case | fluid particles | wall particles | pairs per particle (each once) | steps | "
              "iterations / step | seconds | M particle-iterations/s | M particle-steps/s | threads | load |",
              "|---|---|---|---|---|---|---|---|---|---|---|"]
    for r in fluid:
        lines.append(f"| {r['case']} | {r['fluid_particles']} | {r['wall_particles']} | {r['pairs_per_particle']} | "
                     f"{r['steps']} | "
                     f"{r['iterations_per_step']} | {r['seconds']} | {r['particle_iterations_per_second'] / 1e6:.3f} | "
                     f"{r['particle_steps_per_second'] / 1e6:.3f} | {r['threads']} | {r['load_average']:.1f} |")
    scaling = thread_scaling.main(["--cases", "host", "fluid", "solid"])
    lines += ["", "## Two threads, pass by pass", "", thread_scaling.markdown(scaling)]
    job = main_job.main(["--full"])
    lines += ["", "## The main job: the paper's gate at 1 mm", "", main_job.markdown(job["ref"], job["result"], job["full"])]
    rec = recording_cost.main([])
    lines += ["", "## Recording cost (MCAP, Rerun)", "", recording_cost.markdown(rec)]
    pub = publishing_cost.main([])
    lines += ["", "## Publishing cost (the node's frame)", "", publishing_cost.markdown(pub)]
    compiled = compile_time.main([])
    lines += ["", "## Compile time (a cold cache)", "", compile_time.markdown(compiled)]
    shared = shared_host.main([])
    lines += ["", "## A shared host (GNU OpenMP's spin)", "", shared_host.markdown(shared)]
    out = Path(args.out)
    out.parent.mkdir(parents=True, exist_ok=True)
    out.write_text("\n".join(lines) + "\n")
    print(f"wrote {out}")


if __name__ == "__main__":
    main()
