"""`sph-fsi`: the command line (no ROS needed).

    sph-fsi run [SCENE] [--set KEY=VALUE ...] [--end-time T] [--out DIR]
                [--mcap FILE [--mcap-compression zstd|lz4|none]] [--rrd FILE] [--rerun-connect ADDR]
                [--record-interval T]
    sph-fsi replay FILE.mcap [--rate R] [--wait-for-subscribers N]
    sph-fsi scenes
    sph-fsi keys [SCENE] [--yaml]
    sph-fsi validate [CASE ...] [--quick] [--workers N] [--missing]
    sph-fsi stability [NAME ...] [--ci] [--out DIR]

Exit status: 0 on success; 2 on bad input (one line naming the key and the allowed range; nothing written); 3 when
the run diverged (one line naming the check that tripped, when and where); 4 when more water left the domain than
the scene's watchdog.max_fluid_lost allows (a stop it asked for, not a divergence); 130 when stopped by SIGINT or
SIGTERM.

SIGINT (Ctrl-C) and SIGTERM stop a run cleanly at the end of the current outer step: recordings get the state
at that step and are closed whole. A second signal while the recordings close is ignored (a third exits at once).
"""
import argparse
import os
import signal
import sys
from pathlib import Path

EXIT_BAD_INPUT = 2
EXIT_DIVERGED = 3
EXIT_WATER_LOST = 4
EXIT_INTERRUPTED = 130


def _cmd_scenes(_args):
    from sph_fsi_core.scene import builtin_scenes, load_scene
    from sph_fsi_core.scenes import DEFAULT_SCENE
    for name, path in builtin_scenes().items():
        spec = load_scene(str(path))
        mark = " (default)" if name == DEFAULT_SCENE else ""
        print(f"{name:14s} {', '.join(spec.phases):14s} {spec['scene.description']}{mark}")
    return 0


def _cmd_keys(args):
    from sph_fsi_core.scene import defaults_yaml, load_scene
    if args.yaml:
        sys.stdout.write(defaults_yaml())
        return 0
    from sph_fsi_core.geometry.parts import REQUIRED, reference
    spec = load_scene(args.scene)
    written = spec.expressions or {}
    for key, p in sorted(spec.schema.params.items()):
        value = spec.values[key]
        when = "at reset" if p.rebuild else "live"
        formula = f" (the file's {_expression_text(written[key])})" if key in written else ""
        print(f"{key:40s} = {value!s:14s} [{p.unit or '-'}] {p.range_text()}; {when}{formula}. {p.description}")
    if spec.derived:
        print("# the scene's derived quantities (its file's expressions in its parameters; not keys):")
        for key, (text, unit, description, value) in spec.derived.items():
            print(f"{key:40s} = {value!s:14s} [{unit or '-'}] = {text}. {description}")
    print("# the keys of a geometry scene's parts, probes and judges (scene.builder: geometry), by role, shape and "
          "kind:")
    for _, entries, params in reference():
        for p in params:
            value = "required" if p.default is REQUIRED else p.default
            print(f"{p.key:40s} = {value!s:14s} [{p.unit or '-'}] {p.range_text()}; {entries}. {p.description}")
    return 0


def _expression_text(raw):
    """A key's value as its scene file wrote it (expressions in its parameters), as text."""
    return "[" + ", ".join(str(v) for v in raw) + "]" if isinstance(raw, (list, tuple)) else str(raw)


def _check_out_dir(path):
    """`path` if a run can write there, proven by making it (and its parents) and a file in it, then removing what
    this made: the run makes the directory once its scene is built, so a refused scene leaves none."""
    from sph_fsi_core.run import make_writable_dir
    path = Path(path)
    made = [p for p in [path, *path.parents] if not p.exists()]
    try:
        make_writable_dir(path)
    except OSError as exc:
        raise ValueError(f"--out {str(path)!r}: not writable ({exc.strerror}); allowed: a writable directory")
    finally:
        for p in made:          # deepest first
            try:
                p.rmdir()
            except OSError:
                break
    return path


class _Signals:
    """SIGINT/SIGTERM -> a flag checked between outer steps; the run then ends cleanly (exit status 130).

    The flag is first checked once the scene is built (after the first Numba compile). A second signal before
    then raises KeyboardInterrupt. While recordings close, a second signal is ignored; a third exits at once."""

    def __init__(self):
        self.signum = None
        self.count = 0
        self.closing = False
        self._old = {}

    def __enter__(self):
        for sig in (signal.SIGINT, signal.SIGTERM):
            self._old[sig] = signal.signal(sig, self._handle)
        return self

    def __exit__(self, *exc):
        for sig, old in self._old.items():
            signal.signal(sig, old)

    def _handle(self, signum, _frame):
        self.count += 1
        if self.signum is None:
            self.signum = signum
        if self.closing:
            if self.count >= 3:
                os.write(2, b"sph-fsi: third signal while closing recordings: exiting now\n")
                os._exit(130)
            os.write(2, b"sph-fsi: closing the recordings, please wait (signal again to abandon them)\n")
            return
        if self.count >= 2:
            raise KeyboardInterrupt

    def check(self):
        if self.signum is not None and not self.closing:
            from sph_fsi_core.run import Interrupted
            raise Interrupted()


def _check_writable_file(option, path):
    if path is None:
        return None
    p = Path(path)
    parent = p.parent if str(p.parent) else Path(".")
    if not parent.is_dir():
        raise ValueError(f"{option} {str(p)!r}: directory {str(parent)!r} does not exist; allowed: a file in an "
                         f"existing writable directory")
    if not os.access(parent, os.W_OK) or (p.exists() and not os.access(p, os.W_OK)):
        raise ValueError(f"{option} {str(p)!r}: not writable; allowed: a file in an existing writable directory")
    return p


def _cmd_run(args):
    import time
    from sph_fsi_core.jit_cache import COMPILING_LINE, scene_kernels_cached
    from sph_fsi_core.precompile import compile_cold_scene
    from sph_fsi_core.run import Interrupted, run_scene
    from sph_fsi_core.memory_guard import MAX_PARTICLES_ENV
    from sph_fsi_core.scene import SceneError, load_scene, naming_the_file
    if args.max_particles is not None:
        if args.max_particles < 1:
            raise ValueError(f"--max-particles {args.max_particles}: allowed: a positive integer")
        os.environ[MAX_PARTICLES_ENV] = str(args.max_particles)
    if args.checkpoint_interval is not None and args.checkpoint_interval < 0:
        raise ValueError(f"--checkpoint-interval {args.checkpoint_interval:g}: allowed: >= 0 s (0: only when "
                         f"stopped by a signal)")
    restart = None
    if args.restart:
        from sph_fsi_core.checkpoint import read_checkpoint
        if args.scene or args.set:
            raise ValueError("--restart continues the checkpoint's own scene and settings: allowed without a "
                             "scene and without --set (--end-time may extend it)")
        restart = read_checkpoint(args.restart)
        spec = restart["sim"].spec
    else:
        spec = load_scene(args.scene, args.set or [])
    if args.end_time is not None:
        spec = spec.with_overrides({"scene.end_time": args.end_time})
        if restart is not None:
            restart["sim"].spec = spec
    commands = None
    if args.commands:
        from sph_fsi.recording.commands import check_parts, read_commands
        commands = read_commands(args.commands)
        check_parts(commands, spec.values, f"--commands {args.commands}")
    if args.checkpoint:
        _check_writable_file("--checkpoint", args.checkpoint)
    mcap = _check_writable_file("--mcap", args.mcap)
    rrd = _check_writable_file("--rrd", args.rrd)
    if args.record_interval is not None and args.record_interval < 0:
        raise ValueError(f"--record-interval {args.record_interval:g}: allowed: >= 0 s (0 = every outer step)")
    out = _check_out_dir(args.out or Path("runs") / spec.name)
    checkpoint = Path(args.checkpoint) if args.checkpoint else out / "checkpoint.ckpt"
    recording = bool(mcap or rrd or args.rerun_connect)
    state = {"rec": None, "sim": None, "stats": None, "samples": 0, "said": 0}
    started = time.perf_counter()
    cold = restart is None and scene_kernels_cached(spec) is False
    if cold:    # the scene built and checked first (cheap), so a refusal does not wait for the compilation
        spec.build()
        print(f"sph-fsi: {COMPILING_LINE}", file=sys.stderr)
        compile_cold_scene(spec, lambda line: print(f"sph-fsi: {line}", file=sys.stderr),
                           lambda line: print(f"sph-fsi: warning: {line}", file=sys.stderr))
    if not restart and "fluid" in spec.phases and spec["fluid.settle_time"] > 0.0:
        print(f"sph-fsi: the water first settles at rest for fluid.settle_time = {spec['fluid.settle_time']:g} s "
              f"before t = 0", file=sys.stderr)

    def announce(sim):
        """Once the scene is built and checked: what runs where, what the build says, its warnings so far."""
        print(f"sph-fsi: running '{spec.name}' ({', '.join(spec.phases)}) "
              + (f"from its checkpoint at t = {sim.time:.6g} s " if restart else "")
              + f"to t = {spec['scene.end_time']:g} s into {out}/", file=sys.stderr)
        for note in getattr(sim, "notes", []):
            print(f"sph-fsi: {note}", file=sys.stderr)
        for warning in sim.warnings:
            print(f"sph-fsi: warning: {warning}", file=sys.stderr)
        state["said"] = len(sim.warnings)

    with _Signals() as signals:
        def on_sample(sim, row):
            state["sim"] = sim
            state["samples"] += 1
            if state["samples"] == 1:
                announce(sim)
                if commands is not None:
                    from sph_fsi.recording.commands import queue_commands
                    queue_commands(sim, commands, f"--commands {args.commands}")
            if cold and state["samples"] == 2:   # the first call is the initial state, the second the first step
                print(f"sph-fsi: compiled and took the first step in {time.perf_counter() - started:.0f} s",
                      file=sys.stderr)
            signals.check()

        class ClosingRecorder:
            """The run's recorder; a second signal while it closes is ignored (see _Signals)."""

            def __init__(self, sim):
                from sph_fsi.recording import DEFAULT_INTERVAL, Recorder
                interval = DEFAULT_INTERVAL if args.record_interval is None else args.record_interval
                self.rec = Recorder(sim, mcap_path=mcap, mcap_compression=args.mcap_compression, rrd_path=rrd,
                                    rerun_connect=args.rerun_connect, interval=interval)
                state["rec"] = self.rec

            def maybe_record(self, sim, row=None):
                return self.rec.maybe_record(sim, row)

            def close(self, sim=None, **kwargs):
                signals.closing = True
                state["stats"] = self.rec.close(sim, **kwargs)
                return state["stats"]

        status, detail, summary = "failed", None, None
        try:
            summary = run_scene(spec, out, on_sample=on_sample, recorder=ClosingRecorder if recording else None,
                                restart=restart, checkpoint=checkpoint,
                                checkpoint_interval=args.checkpoint_interval or 0.0)
            status = summary["status"]
            d = summary["diverged"] or summary.get("stopped")
            if d:
                detail = f"{d['check']} at t = {d['time']:.6g} s: {d['detail']}"
        except SceneError as exc:   # refused while building: before anything was announced or written
            raise naming_the_file(exc, spec.source, spec.file_keys) from None
        except (Interrupted, KeyboardInterrupt):
            status = "interrupted"
        finally:
            signals.closing = True
            rec, stats = state["rec"], state["stats"]
            if rec is not None and stats is not None:
                written = [str(p) for p in (mcap, rrd) if p]
                print(f"sph-fsi: recorded {rec.frames} frames ({rec.interval:g} s apart) to "
                      f"{', '.join(written + ([args.rerun_connect] if args.rerun_connect else []))}"
                      + (f"; the simulator waited {stats['waits']} times ({stats['wait_seconds']:.2f} s) for "
                         f"the recorder" if stats["waits"] else "")
                      + (f"; errors: {'; '.join(stats['errors'])}" if stats["errors"] else ""), file=sys.stderr)
    if status == "interrupted":
        name = signal.Signals(signals.signum).name if signals.signum else "SIGINT"
        print(f"sph-fsi: stopped by {name} at t = {state['sim'].time if state['sim'] else 0.0:.6g} s"
              + (f"; the run so far (not judged) is in {out}/timeseries.csv, {out}/summary.json"
                 if (out / "summary.json").exists() else ""), file=sys.stderr)
        if checkpoint.exists() and state["sim"] is not None:
            print(f"sph-fsi: checkpoint at t = {state['sim'].time:.6g} s in {checkpoint}; continue with "
                  f"sph-fsi run --restart {checkpoint}", file=sys.stderr)
        return EXIT_INTERRUPTED
    _print_summary(summary, out, state["said"])
    if status == "diverged":
        print(f"sph-fsi: diverged: {detail}", file=sys.stderr)
        return EXIT_DIVERGED
    if status == "water_lost":
        print(f"sph-fsi: stopped, water lost (watchdog.max_fluid_lost): {detail}", file=sys.stderr)
        return EXIT_WATER_LOST
    return 0


def _cmd_compile(args):
    from sph_fsi_core.jit_cache import scene_kernels_cached
    from sph_fsi_core.precompile import compile_scene
    from sph_fsi_core.scene import load_scene
    spec = load_scene(args.scene, args.set or [])

    def say(line):
        print(f"sph-fsi: {line}", file=sys.stderr, flush=True)

    if scene_kernels_cached(spec) is not True:
        say(f"compiling the kernels of '{spec.name}' into Numba's cache, once (about a minute on 2 "
            f"cores; its runs then start stepping at once)")
    seconds = compile_scene(spec, say, lambda line: say(f"warning: {line}"))
    say(f"'{spec.name}' compiled and cached ({seconds:.0f} s)")
    return 0


def _cmd_replay(args):
    from sph_fsi.replay import replay
    return replay(args.file, rate=args.rate, wait_for_subscribers=args.wait_for_subscribers,
                  wait_timeout=args.wait_timeout)


def _print_summary(s, out, said=0):
    """The run's summary in a few lines; its warnings after the first `said` (those printed when it started)."""
    from sph_fsi_core.fluid.lost_water import lost_line
    from sph_fsi_core.run import solid_share_of_stepping
    steps = []
    if s.get("solid_steps"):
        steps.append(f"solid steps: {s['solid_steps']}")
        if s.get("solid_pressure_solve"):
            steps[-1] += f" ({s['solid_pressure_solve']['iterations_per_step']:.1f} pressure iterations per step)"
    if s.get("fluid_steps"):
        steps.append(f"fluid steps: {s['fluid_steps']} ({s['fluid_iterations_per_step']:.1f} correction iterations "
                     f"per step)")
    counts = {k: v for k, v in s["particles"].items() if v and k != "solid_moving"}
    solid_share = solid_share_of_stepping(s)
    share = f" (the solid's steps {100 * solid_share:.0f} %)" if solid_share is not None else ""
    print(f"particles: {sum(counts.values()):,} ({', '.join(f'{k} {v:,}' for k, v in counts.items())})  "
          f"{'  '.join(steps)}  wall time: {s['wall_time_s']:.1f} s{share}  "
          f"particle-steps/s: {s['particle_steps_per_second'] or 0:,.0f}")
    if s.get("settling"):
        st = s["settling"]
        print(f"settled: {st['settle_time_s']:g} s of water at rest before t = 0 in {st['wall_time_s']:.1f} s "
              f"({st['fluid_steps']} steps, {st['iterations_mean']:.1f} iterations per step, {st['capped_steps']} "
              f"capped; max compression {100 * st['density_error_max']:.2f} %, speed left "
              f"{st['residual_max_speed_m_s']:.3g} m/s)")
    if s.get("error") is not None and s.get("frequency_hz") is None:
        print(f"error: {100 * s['error']:.2f} % ({s.get('error_metric', 'against the scene reference')})")
    later = s.get("warnings", [])[said:]
    for warning in later[:5]:
        print(f"warning: {warning}", file=sys.stderr)
    if len(later) > 5:
        print(f"warning: ... {len(later) - 5} more in summary.json", file=sys.stderr)
    lost = lost_line(s.get("fluid_lost"))
    if lost:
        print(f"water lost: {lost}")
    if s.get("frequency_hz") is not None and s.get("error") is not None:
        print(f"frequency: {s['frequency_hz']:.4f} +- {s['frequency_uncertainty_hz']:.4f} Hz over "
              f"{s['periods']:.1f} periods; reference {s['reference_hz']:.4f} Hz ({s['judged_against']}); "
              f"error {100 * s['error']:.2f} %; damping ratio {s['damping_ratio']:.4f}")
        print(f"  vs Euler-Bernoulli {s['euler_bernoulli_hz']:.3f} Hz: {s['error_vs_euler_bernoulli_percent']:+.2f} %; "
              f"vs eq. (15) {s['eq15_hz']:.3f} Hz: {s['error_vs_eq15_percent']:+.2f} %")
    if s.get("frequency_note"):
        print(f"frequency: {s['frequency_note']}")
    print(f"outputs: {out}/timeseries.csv, {out}/summary.json" + (f", {out}/snapshots/" if s.get("snapshots") else ""))


def _cmd_validate(args):
    from sph_fsi_core.validation.ladder import main as validate_main
    _check_workers(args)
    return validate_main(args.cases, quick=args.quick, workers=args.workers, out_dir=args.out,
                         report_only=args.report_only, missing=args.missing, scheduler=args.scheduler)


def _check_workers(args):
    if args.workers < 1:
        raise ValueError(f"--workers {args.workers}: allowed: at least 1")


def _cmd_sweep(args):
    from sph_fsi_core.validation.sweep import main as sweep_main
    _check_workers(args)
    return sweep_main(args)


def _cmd_stability(args):
    from sph_fsi_core.validation.stability import main as stability_main
    return stability_main(ci=args.ci, out_dir=args.out, names=args.names)


def _add_task_options(p):
    """--workers and --scheduler of the commands that run many runs (validate, sweep)."""
    p.add_argument("--workers", type=int, default=1,
                   help="runs at once, as tasks on a local Dask cluster of this many processes (default 1: here)")
    p.add_argument("--scheduler", default=None, metavar="ADDRESS",
                   help="run on an existing Dask cluster (tcp://host:8786; see sph_fsi_core/validation/tasks.py)")


def build_parser():
    from sph_fsi_core.validation import DEFAULT_OUT_DIR
    parser = argparse.ArgumentParser(prog="sph-fsi", description="3D SPH fluid-structure simulator (Satake et al.)")
    sub = parser.add_subparsers(dest="command", required=True)
    p = sub.add_parser("run", help="run a scene headless and write its outputs")
    p.add_argument("scene", nargs="?", default=None, help="built-in scene name or YAML file (default scene if omitted)")
    p.add_argument("--set", action="append", metavar="KEY=VALUE", help="override a scene key (repeatable)")
    p.add_argument("--end-time", type=float, default=None, help="simulated end time [s]")
    p.add_argument("--out", default=None, help="output directory (default runs/SCENE)")
    p.add_argument("--mcap", default=None, metavar="FILE", help="record the node's topics to an MCAP file (ROS 2)")
    p.add_argument("--mcap-compression", default="zstd", choices=("zstd", "lz4", "none"),
                   help="MCAP chunk compression (default zstd)")
    p.add_argument("--rrd", default=None, metavar="FILE", help="record to a Rerun .rrd file")
    p.add_argument("--rerun-connect", default=None, metavar="ADDR",
                   help="stream live to a Rerun viewer (host:port or rerun+http://host:port/proxy)")
    p.add_argument("--record-interval", type=float, default=None, metavar="T",
                   help="simulated seconds between recorded frames (default 0.005; 0 = every outer step)")
    p.add_argument("--max-particles", type=int, default=None, metavar="N",
                   help="refuse scenes with more particles than N (default: refuse what would not fit in the "
                        "memory available now, as estimated from the geometry and the spacing)")
    p.add_argument("--checkpoint-interval", type=float, default=None, metavar="T",
                   help="write a checkpoint every T simulated seconds (a signal always writes one before exiting)")
    p.add_argument("--checkpoint", default=None, metavar="FILE",
                   help="where checkpoints go (default OUT/checkpoint.ckpt; each replaces the last)")
    p.add_argument("--restart", default=None, metavar="FILE",
                   help="continue the run a checkpoint holds (its scene and settings), to the bit")
    p.add_argument("--commands", default=None, metavar="FILE",
                   help="give the scene's commanded walls (motion: ros) the commands a recorded run applied (its "
                        "MCAP file), each at the step it applied at: the recorded run again, to the bit")
    p.set_defaults(func=_cmd_run)
    p = sub.add_parser("compile", help="compile and cache a scene's kernels now, so that its runs start stepping at "
                                       "once (make install does it for the main job)")
    p.add_argument("scene", nargs="?", default=None, help="built-in scene name or YAML file (default scene if omitted)")
    p.add_argument("--set", action="append", metavar="KEY=VALUE", help="override a scene key (repeatable)")
    p.set_defaults(func=_cmd_compile)
    p = sub.add_parser("replay", help="republish an MCAP recording onto ROS 2 topics (needs rclpy)")
    p.add_argument("file", help="an .mcap written by sph-fsi run --mcap or the node's mcap_path")
    p.add_argument("--rate", type=float, default=1.0,
                   help="playback speed: simulated seconds per wall second (default 1; 0 = as fast as possible)")
    p.add_argument("--wait-for-subscribers", type=int, default=0, metavar="N",
                   help="before playing, wait until every topic has N subscribers (default 0: do not wait)")
    p.add_argument("--wait-timeout", type=float, default=30.0, help="the longest wait for subscribers [s]")
    p.set_defaults(func=_cmd_replay)
    p = sub.add_parser("scenes", help="list the built-in scenes")
    p.set_defaults(func=_cmd_scenes)
    p = sub.add_parser("keys", help="list a scene's keys with units, ranges and values")
    p.add_argument("scene", nargs="?", default=None)
    p.add_argument("--yaml", action="store_true", help="print config/defaults.yaml (every key of every phase)")
    p.set_defaults(func=_cmd_keys)
    p = sub.add_parser("validate", help="accuracy study: error against run time over resolution ladders")
    p.add_argument("cases", nargs="*", help="cases to run (default: all)")
    p.add_argument("--quick", action="store_true", help="coarse rungs only, asserting error bounds (CI)")
    _add_task_options(p)
    p.add_argument("--out", default=DEFAULT_OUT_DIR,
                   help=f"where REPORT.md, plots and runs go (default {DEFAULT_OUT_DIR}; --out docs/validation "
                        f"publishes into the project's committed report)")
    p.add_argument("--report-only", action="store_true", help="rebuild REPORT.md and plots from earlier runs")
    p.add_argument("--missing", action="store_true",
                   help="run only the rungs that have no summary.json in --out yet (finish a stopped ladder)")
    p.set_defaults(func=_cmd_validate)
    p = sub.add_parser("sweep", help="parameter study: one run per combination of --vary values, one table")
    p.add_argument("scene", help="built-in scene name or YAML file")
    p.add_argument("--vary", action="append", required=True, metavar="KEY=V1,V2,...",
                   help="a scene key and its values (repeatable: every combination runs)")
    p.add_argument("--set", action="append", metavar="KEY=VALUE", help="override a scene key for every run")
    p.add_argument("--end-time", type=float, default=None, help="simulated end time of every run [s]")
    p.add_argument("--out", default="runs/sweep", help="where runs/ and sweep.csv go (default runs/sweep)")
    _add_task_options(p)
    p.set_defaults(func=_cmd_sweep)
    p = sub.add_parser("stability", help="stiff and extreme cases: the outcome of each (stable, refused, diverged)")
    p.add_argument("names", nargs="*", help="run only cases whose name contains one of these")
    p.add_argument("--ci", action="store_true", help="the CI subset only")
    p.add_argument("--out", default=DEFAULT_OUT_DIR,
                   help=f"where STABILITY.md and runs go (default {DEFAULT_OUT_DIR}; --out docs/validation "
                        f"publishes into the project's committed report)")
    p.set_defaults(func=_cmd_stability)
    return parser


def main(argv=None):
    from sph_fsi_core.schema import SceneError
    args = build_parser().parse_args(argv)
    try:
        return args.func(args)
    except (SceneError, ValueError) as exc:
        print(f"sph-fsi: {exc}", file=sys.stderr)
        return EXIT_BAD_INPUT
    except KeyboardInterrupt:
        print("sph-fsi: interrupted", file=sys.stderr)
        return 130


if __name__ == "__main__":
    sys.exit(main())
