"""`sph-fsi`: the command line (no ROS needed).

    sph-fsi run [SCENE] [--set KEY=VALUE ...] [--end-time T] [--out DIR]
    sph-fsi scenes
    sph-fsi keys [SCENE] [--yaml]
    sph-fsi validate [CASE ...] [--quick] [--workers N]

Exit status: 0 on success; 2 on bad input (one line naming the key and the allowed range); 3 when the run
diverged (one line naming the check that tripped, when and where).
"""
import argparse
import json
import sys
from pathlib import Path

EXIT_BAD_INPUT = 2
EXIT_DIVERGED = 3


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
    spec = load_scene(args.scene)
    for key, p in sorted(spec.schema.params.items()):
        value = spec.values[key]
        when = "at reset" if p.rebuild else "live"
        print(f"{key:40s} = {value!s:14s} [{p.unit or '-'}] {p.range_text()}; {when}. {p.description}")
    return 0


def _check_out_dir(path):
    out = Path(path)
    try:
        out.mkdir(parents=True, exist_ok=True)
        probe = out / ".write_test"
        probe.write_text("")
        probe.unlink()
    except OSError as exc:
        raise ValueError(f"--out {str(out)!r}: not writable ({exc.strerror}); allowed: a writable directory")
    return out


def _cmd_run(args):
    from sph_fsi_core.run import run_scene
    from sph_fsi_core.scene import load_scene
    spec = load_scene(args.scene, args.set or [])
    if args.end_time is not None:
        spec = spec.with_overrides({"scene.end_time": args.end_time})
    out = _check_out_dir(args.out or Path("runs") / spec.name)
    print(f"sph-fsi: running '{spec.name}' ({', '.join(spec.phases)}) to t = {spec['scene.end_time']:g} s "
          f"into {out}/", file=sys.stderr)
    summary = run_scene(spec, out)
    _print_summary(summary, out)
    if not summary["stable"]:
        d = summary["diverged"]
        print(f"sph-fsi: diverged: {d['check']} at t = {d['time']:.6g} s: {d['detail']}", file=sys.stderr)
        return EXIT_DIVERGED
    return 0


def _print_summary(s, out):
    print(f"particles: {s['particles']}  solid steps: {s['solid_steps']}  wall time: {s['wall_time_s']:.1f} s  "
          f"particle-steps/s: {s['particle_steps_per_second'] or 0:,.0f}")
    if s.get("frequency_hz") is not None:
        print(f"frequency: {s['frequency_hz']:.4f} +- {s['frequency_uncertainty_hz']:.4f} Hz over "
              f"{s['periods']:.1f} periods; reference {s['reference_hz']:.4f} Hz ({s['judged_against']}); "
              f"error {100 * s['error']:.2f} %; damping ratio {s['damping_ratio']:.4f}")
        print(f"  vs Euler-Bernoulli {s['euler_bernoulli_hz']:.3f} Hz: {s['error_vs_euler_bernoulli_percent']:+.2f} %; "
              f"vs eq. (15) {s['eq15_hz']:.3f} Hz: {s['error_vs_eq15_percent']:+.2f} %")
    print(f"outputs: {out}/timeseries.csv, {out}/summary.json, {out}/snapshots/")


def _cmd_validate(args):
    from sph_fsi_core.validation import main as validate_main
    return validate_main(args.cases, quick=args.quick, workers=args.workers, out_dir=args.out,
                         report_only=args.report_only)


def build_parser():
    parser = argparse.ArgumentParser(prog="sph-fsi", description="3D SPH fluid-structure simulator (Satake et al.)")
    sub = parser.add_subparsers(dest="command", required=True)
    p = sub.add_parser("run", help="run a scene headless and write its outputs")
    p.add_argument("scene", nargs="?", default=None, help="built-in scene name or YAML file (default scene if omitted)")
    p.add_argument("--set", action="append", metavar="KEY=VALUE", help="override a scene key (repeatable)")
    p.add_argument("--end-time", type=float, default=None, help="simulated end time [s]")
    p.add_argument("--out", default=None, help="output directory (default runs/SCENE)")
    p.set_defaults(func=_cmd_run)
    p = sub.add_parser("scenes", help="list the built-in scenes")
    p.set_defaults(func=_cmd_scenes)
    p = sub.add_parser("keys", help="list a scene's keys with units, ranges and values")
    p.add_argument("scene", nargs="?", default=None)
    p.add_argument("--yaml", action="store_true", help="print config/defaults.yaml (every key of every phase)")
    p.set_defaults(func=_cmd_keys)
    p = sub.add_parser("validate", help="accuracy study: error against run time over resolution ladders")
    p.add_argument("cases", nargs="*", help="cases to run (default: all)")
    p.add_argument("--quick", action="store_true", help="coarse rungs only, asserting error bounds (CI)")
    p.add_argument("--workers", type=int, default=1, help="cases run in parallel processes")
    p.add_argument("--out", default="docs/validation", help="where REPORT.md and plots go")
    p.add_argument("--report-only", action="store_true", help="rebuild REPORT.md and plots from earlier runs")
    p.set_defaults(func=_cmd_validate)
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
