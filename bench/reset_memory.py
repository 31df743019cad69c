"""The node's resident memory over 200 ~/resets, without and with recordings (issue: resets that do not leak).

The node's simulation thread (sph_fsi.runner.Runner) with its outputs to a fake (no ROS), the cantilever as the
built-in scene has it, paused: each reset rebuilds the scene and publishes its t = 0 frame. With recordings, each
run is stepped one publish period (4 frames recorded, MCAP and Rerun) before it is reset, so every recording has
data to close. Resident memory (psutil RSS) after resets 1, 20, 40, 80, 120, 160 and 200; the goal: flat within
5 % from the 20th to the 200th. `--no-fix` measures the runner without return_freed_memory and with Rerun in the
node's own process (what the issue measured), for comparison.

    python -m bench.reset_memory [--resets 200] [--no-fix] [--out docs/performance/RESET_MEMORY.md]
"""
import argparse
import datetime
import tempfile
import threading
import time
from pathlib import Path

import psutil

import sph_fsi.recording as recording
import sph_fsi.runner as runner_module
from sph_fsi.parameters import node_defaults
from sph_fsi_core.run import machine_info
from sph_fsi_core.scene import load_scene

SAMPLES = (1, 20, 40, 80, 120, 160, 200)
PERIOD = 0.001


class _Out:
    """The node's outputs, counted only."""

    def __init__(self):
        self.lock = threading.Lock()
        self.frames = []

    def ok(self):
        return True

    def publish_frame(self, sim, frame_id):
        with self.lock:
            self.frames.append(sim.time)
        return True

    def __getattr__(self, name):     # sync_topics, publish_walls, publish_diagnostics, scene_changed, ...
        return lambda *args, **kwargs: None


class _Log:
    def __init__(self):
        self.lines = []

    def info(self, msg):
        self.lines.append(msg)

    warning = error = info


def _wait(predicate, timeout=300.0):
    deadline = time.monotonic() + timeout
    while not predicate():
        if time.monotonic() > deadline:
            raise TimeoutError("the runner did not answer")
        time.sleep(0.002)


def measure(resets, record, directory):
    settings = dict(node_defaults(), publish_period=PERIOD, out_dir="")
    if record:
        settings.update(mcap_path=str(Path(directory) / "r.mcap"), rrd_path=str(Path(directory) / "r.rrd"),
                        record_interval=0.0)
    out = _Out()
    r = runner_module.Runner(load_scene("cantilever"), settings, out, _Log())
    r.pause(True)
    r.start()
    _wait(lambda: len(out.frames) == 1)
    proc = psutil.Process()
    rss, started = {}, time.perf_counter()
    try:
        for i in range(1, resets + 1):
            if record:
                n = len(out.frames)
                r.request_step()
                _wait(lambda: len(out.frames) == n + 1)
            n = len(out.frames)
            r.request_reset()
            _wait(lambda: len(out.frames) == n + 1)
            if i in SAMPLES:
                rss[i] = proc.memory_info().rss / 2 ** 20
    finally:
        r.stop()
    return {"record": record, "rss_mb": rss, "seconds": time.perf_counter() - started}


def markdown(results, fixed):
    lines = ["| recordings | " + " | ".join(f"after {i}" for i in SAMPLES) + " | 20th to last | seconds |",
             "|---|" + "---|" * (len(SAMPLES) + 2)]
    for res in results:
        rss = res["rss_mb"]
        last = max(rss)
        change = rss[last] / rss[20] - 1.0 if 20 in rss else float("nan")
        lines.append(f"| {'MCAP + Rerun' if res['record'] else 'none'} | "
                     + " | ".join(f"{rss[i]:.1f}" if i in rss else "" for i in SAMPLES)
                     + f" | {100 * change:+.1f} % | {res['seconds']:.0f} |")
    return "\n".join(lines) + ("" if fixed else "\n\n(--no-fix: without return_freed_memory, Rerun in-process)")


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--resets", type=int, default=200)
    parser.add_argument("--no-fix", action="store_true")
    parser.add_argument("--out", default=None, help="write the table (with the machine) to this Markdown file")
    args = parser.parse_args(argv)
    if args.no_fix:
        runner_module.return_freed_memory = lambda: None
        original = recording.Recorder.__init__

        def in_process(self, *a, **kw):
            kw["rerun_process"] = False
            original(self, *a, **kw)
        recording.Recorder.__init__ = in_process
    results = []
    for record in (False, True):
        with tempfile.TemporaryDirectory() as d:
            results.append(measure(args.resets, record, d))
        print(markdown(results, not args.no_fix), flush=True)
    table = markdown(results, not args.no_fix)
    if args.out:
        m = machine_info()
        Path(args.out).write_text(
            "# Resident memory over resets\n\n" + f"Made by `python -m bench.reset_memory --out {args.out}`"
            + (" --no-fix" if args.no_fix else "") + f"; {datetime.date.today().isoformat()}, commit {m['commit']}, "
            f"{m['cpus']} CPUs. Resident memory in MB after each numbered reset (bench/reset_memory.py).\n\n"
            + table + "\n")
    return results


if __name__ == "__main__":
    main()
