"""What recording costs the simulator: throughput with MCAP on, Rerun on, both on, against off; per-frame costs.

Two scenes:
- `elastic_gate`: the paper's gate case at 1 mm across the paper's 36 mm (`geometry.span=0.036`, not the scene's
  narrowest slab: 59,760 particles, 27,648 fluid, 6,192 solid, 25,920 wall; the paper's 80,064 has a longer tank),
  a frame every outer step (1 ms of simulated time: one fluid step and ~540 solid sub-steps), five times denser
  than the default record interval (0.005 s).
- `cantilever_1e5`: the cantilever scaled to ~1e5 particles (0.100 x 0.032 x 0.032 m at 1 mm, clamp margin 1:
  106,752 particles, 102,400 moving), a worst case on purpose: a frame every `--steps-per-frame` solid steps
  (1 = every solid step), where a real run records every 0.005 s of simulated time (~2,700 solid steps).
Each configuration steps the same simulation on, in rounds, forward then backward, so a drift (a shared
machine, the gate's flow developing) hits every configuration alike.
The time of a configuration runs from its first step to the end of Recorder.close(), so writing out the queue
is paid for.

Per-frame costs are measured apart, on the calling thread: capture (the copies made on the simulation thread),
and the write of one frame by each sink (MCAP per compression, Rerun to an .rrd), with the bytes per frame.

    python -m bench.recording_cost [--scene elastic_gate|cantilever_1e5] [--steps-per-frame 1 10] [--frames 10]
                                   [--rounds 2] [--configs ...]
"""
import argparse
import json
import os
import statistics
import tempfile
import time
from pathlib import Path

import numba

from sph_fsi.recording import Recorder
from sph_fsi.recording.frame import capture, capture_static
from sph_fsi.recording.mcap_sink import McapSink
from sph_fsi.recording.rerun_sink import RerunSink
from sph_fsi.points import moving_particles, topic_plan
from sph_fsi_core.scene import load_scene
from sph_fsi_core.simulation import Simulation

SCENES = {"elastic_gate": ("elastic_gate", ["geometry.span=0.036", "output.snapshot_interval=0"]),
          "cantilever_1e5": ("cantilever", ["geometry.length=0.100", "geometry.width=0.032",
                                            "geometry.thickness=0.032", "geometry.clamp_margin=1",
                                            "output.snapshot_interval=0"])}
CONFIGS = {"off": {}, "mcap zstd": {"mcap": "zstd"}, "mcap lz4": {"mcap": "lz4"}, "rerun": {"rrd": True},
           "mcap zstd + rerun": {"mcap": "zstd", "rrd": True}}


def build(scene):
    name, overrides = SCENES[scene]
    sim = Simulation(load_scene(name, overrides))
    sim.step()   # compile, warm up
    return sim


def set_steps_per_frame(sim, n):
    """One outer step = n solid steps (0.98: stays n while the stable step shrinks a little with speed)."""
    sim.apply({"output.timeseries_interval": 0.98 * n * sim.solid_phase.solver.stable_dt()})


def run_config(sim, name, frames, tmp):
    cfg = CONFIGS[name]
    rec = None
    if cfg:
        rec = Recorder(sim, mcap_path=tmp / "b.mcap" if cfg.get("mcap") else None,
                       mcap_compression=cfg.get("mcap", "zstd"), rrd_path=tmp / "b.rrd" if cfg.get("rrd") else None,
                       interval=0.0)
    sim0, t0 = sim.time, time.perf_counter()
    for _ in range(frames):
        sim.step()
        if rec is not None:
            rec.maybe_record(sim)
    stats = rec.close(sim) if rec is not None else {"waits": 0, "wait_seconds": 0.0}
    elapsed = time.perf_counter() - t0
    return {"seconds": elapsed, "throughput": (sim.time - sim0) / elapsed,
            "queue_waits": stats["waits"], "wait_seconds": stats["wait_seconds"]}


def per_frame_costs(sim, tmp, repeats=5):
    out = {}
    t = time.perf_counter()
    for _ in range(repeats):
        frame = capture(sim)
    out["capture_ms"] = 1e3 * (time.perf_counter() - t) / repeats
    t = time.perf_counter()
    for _ in range(repeats):
        frame.forget_parts()
        frame.parts
    out["moving_and_von_mises_ms"] = 1e3 * (time.perf_counter() - t) / repeats
    static = capture_static(sim)
    for comp in ("zstd", "lz4", "none"):
        path = tmp / f"f_{comp}.mcap"
        sink = McapSink(path, topic_plan(sim), compression=comp)
        sink.write(static)
        size0 = path.stat().st_size
        t = time.perf_counter()
        for _ in range(repeats):
            frame.forget_parts()    # each write pays for masking and von Mises, as the first sink of a frame does
            sink.write(frame)
        sink.close()
        out[f"mcap_{comp}_ms"] = 1e3 * (time.perf_counter() - t) / repeats   # close (last chunk) included
        out[f"mcap_{comp}_bytes_per_frame"] = (path.stat().st_size - size0) / repeats
    path = tmp / "f.rrd"
    sink = RerunSink(rrd_path=path)
    sink.write(static)
    t = time.perf_counter()
    for _ in range(repeats):
        frame.forget_parts()
        sink.write(frame)
    sink.close()
    out["rerun_ms"] = 1e3 * (time.perf_counter() - t) / repeats
    out["rerun_bytes_per_frame"] = path.stat().st_size / repeats
    return out


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--scene", default="elastic_gate", choices=list(SCENES))
    parser.add_argument("--steps-per-frame", type=int, nargs="*", default=[1, 10],
                        help="cantilever_1e5 only (the gate records every outer step)")
    parser.add_argument("--frames", type=int, default=10, help="recorded frames per configuration and round")
    parser.add_argument("--rounds", type=int, default=2)
    parser.add_argument("--configs", nargs="*", default=list(CONFIGS), choices=list(CONFIGS))
    args = parser.parse_args(argv)
    configs = ["off"] + [c for c in args.configs if c != "off"]
    sim = build(args.scene)
    moving = sum(len(p[1]) for p in moving_particles(sim))
    result = {"scene": args.scene, "particles": sim.particle_count, "moving": moving, "threads": numba.get_num_threads(),
              "cpus": os.cpu_count(), "by_steps_per_frame": {}, "load_average_before": os.getloadavg()[0]}
    with tempfile.TemporaryDirectory() as d:
        tmp = Path(d)
        result["per_frame"] = per_frame_costs(sim, tmp)
        print(json.dumps(result["per_frame"]), flush=True)
        for spf in (args.steps_per_frame if args.scene == "cantilever_1e5" else ["outer step"]):
            if spf != "outer step":
                set_steps_per_frame(sim, spf)
            runs = {name: [] for name in configs}
            for rnd in range(args.rounds):
                # forward, then backward: a steady drift of the step cost (the gate's flow develops) cancels
                for name in (configs if rnd % 2 == 0 else configs[::-1]):
                    r = run_config(sim, name, args.frames, tmp)
                    runs[name].append(r)
                    print(f"{spf} steps/frame  {name:18s} {r['throughput'] * 1e3:.4g} ms simulated per wall s  "
                          f"({r['seconds']:.2f} s, queue waits {r['queue_waits']})", flush=True)
            off = statistics.median(r["throughput"] for r in runs["off"])
            rows = {}
            for name, rs in runs.items():
                pss = statistics.median(r["throughput"] for r in rs)
                rows[name] = {"sim_seconds_per_wall_second": pss, "cost_percent": 100.0 * (off / pss - 1.0),
                              "spread": [min(r["throughput"] for r in rs), max(r["throughput"] for r in rs)],
                              "frame_seconds": statistics.median(r["seconds"] for r in rs) / args.frames,
                              "queue_waits": sum(r["queue_waits"] for r in rs)}
            result["by_steps_per_frame"][spf] = rows
    result["load_average_after"] = os.getloadavg()[0]
    return result


def markdown(result):
    pf = result["per_frame"]
    lines = [f"Scene `{result['scene']}`, {result['particles']:,} particles ({result['moving']:,} moving, the points "
             f"of a frame), {result['threads']} Numba threads on {result['cpus']} "
             f"CPUs shared with the recorder's thread; load average {result['load_average_before']:.1f} before, "
             f"{result['load_average_after']:.1f} after (other work on the machine). "
             f"Made by `python -m bench.recording_cost`.", "",
             "Per frame (measured on one thread):", "",
             "| what | ms per frame | bytes per frame |", "|---|---|---|",
             f"| capture (copies on the simulation thread) | {pf['capture_ms']:.1f} | |",
             f"| moving particles and von Mises (recorder thread, once per frame) | "
             f"{pf['moving_and_von_mises_ms']:.1f} | |"]
    for comp in ("zstd", "lz4", "none"):
        lines.append(f"| MCAP, {comp} (including the line above) | {pf[f'mcap_{comp}_ms']:.1f} | {pf[f'mcap_{comp}_bytes_per_frame']:,.0f} |")
    lines += [f"| Rerun to .rrd (including the line above) | {pf['rerun_ms']:.1f} | {pf['rerun_bytes_per_frame']:,.0f} |", "",
              "Throughput with a frame every N solid steps or every outer step (median of the rounds; "
              "cost = off / on - 1):", "",
              "| N | recording | simulated ms per wall s (median, min-max) | cost | wall s per frame | queue waits |",
              "|---|---|---|---|---|---|"]
    for spf, rows in result["by_steps_per_frame"].items():
        for name, r in rows.items():
            lo, hi = r["spread"]
            lines.append(f"| {spf} | {name} | {r['sim_seconds_per_wall_second'] * 1e3:.4g} ({lo * 1e3:.4g}-{hi * 1e3:.4g}) | "
                         f"{r['cost_percent']:+.1f} % | {r['frame_seconds']:.3f} | {r['queue_waits']} |")
    return "\n".join(lines) + "\n"


if __name__ == "__main__":
    res = main()
    print(json.dumps(res, indent=1))
    print(markdown(res))
