"""REPORT.md and PNG plots of `sph-fsi validate`, made from the rungs' summary.json files (no simulation here): the
headline table of every rung and the error against wall time; each case's own tables and plots come from its module
(validation/cases/)."""
import datetime
from pathlib import Path

from . import cases
from .report_tools import fmt


def _row(rung, s):
    """A rung's row of the headline table: its cost, what it measured against what, the error."""
    if s is None:
        return f"| {rung.case} | {rung.label} | not run | | | | | | | | | |"
    d = s["diverged"]
    stable = "yes" if s["stable"] else f"no: {d['check']} at {d['time']:.4g} s"
    measured = ref = "-"
    if s.get("frequency_hz") is not None:
        measured = f"{s['frequency_hz']:.3f} ± {s['frequency_uncertainty_hz']:.3f} Hz"
        ref = f"{s['reference_hz']:.3f} Hz ({s['fe3d_source']})"
    elif s.get("midspan_deflection_m") is not None:
        measured = f"mid-span {1e6 * s['midspan_deflection_m']:.2f} um"
        ref = f"FE {1e6 * s['reference_midspan_deflection_m']:.2f} um"
    elif s.get("free_end_deflection_m") is not None:
        measured = f"free end {1e6 * s['free_end_deflection_m']:.2f} um"
        ref = f"FE {1e6 * s['reference_free_end_deflection_m']:.2f} um" if s.get("reference_free_end_deflection_m") \
            else "-"
    elif s.get("elastica_deflection_m") is not None:
        measured = f"free end {1e3 * s['tip_deflection_m']:.3f} mm down"
        ref = f"elastica {1e3 * s['elastica_deflection_m']:.3f} mm"
    elif s.get("tip_deflection_m") is not None:
        measured = f"free end {1e3 * s['tip_deflection_m']:.3f} mm"
        ref = f"FE {1e3 * s['reference_tip_deflection_m']:.3f} mm" if s.get("reference_tip_deflection_m") else "-"
    elif s.get("floor_pressure_pa") is not None:
        measured = f"floor p {s['floor_pressure_pa']:.1f} Pa"
        ref = f"rho g H = {s['reference_floor_pressure_pa']:.1f} Pa"
    elif s.get("front_rms_relative_error") is not None:
        measured = f"front RMS {100 * s['front_rms_relative_error']:.1f} %"
        ref = "Lobovsky et al. 2014, T >= 1" if s.get("builder") == "lobovsky_dam_break" else "Martin & Moyce 1952"
    elif s.get("tip_x_peak_m") is not None:
        measured = f"tip x peak {1e3 * s['tip_x_peak_m']:.1f} mm at {s['tip_x_peak_time_s']:.3f} s"
        ref = f"Antoci 2007: {1e3 * s['tip_x_exp_peak_m']:.1f} mm at {s['tip_x_exp_peak_time_s']:.3f} s"
    elif s.get("tip_dx_peak_m") is not None:
        measured = f"tip dx peak {1e3 * s['tip_dx_peak_m']:.2f} mm at {s['tip_dx_peak_time_s']:.3f} s"
        ref = "paper: peak at 0.06-0.08 s"
    err = f"{100 * s['error']:.2f} %" if s.get("error") is not None else "-"
    if s.get("error_signed") is not None:
        err = f"{100 * s['error_signed']:+.2f} %"   # the sign says soft (+, deflects more) or stiff
    if s.get("frequency_hz") is not None and s.get("reference_hz") and s.get("error") is not None:
        err = f"{100 * (s['frequency_hz'] / s['reference_hz'] - 1.0):+.2f} %"   # the sign says stiff or soft
    m = s.get("machine", {})
    moving = s["particles"].get("solid", 0) + s["particles"].get("fluid", 0)
    steps = s["solid_steps"] + s.get("fluid_steps", 0)
    return (f"| {rung.case} | {rung.label} | {s['settings']['numerics.spacing'] * 1e3:.3g} | "
            f"{moving} | {steps} | {s['wall_time_s']:.1f} | "
            f"{fmt(s['particle_steps_per_second'] / 1e6, '.3f')} | {measured} | {ref} | {err} | {stable} | "
            f"{m.get('numba_threads', '-')}, {m.get('commit', '-')} |")


def _plots(out_dir, rungs, summaries):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    made = []
    # Error against wall time, one series per case (the Pareto view).
    fig, ax = plt.subplots(figsize=(6, 4.5))
    for case in sorted({r.case for r in rungs}):
        pts = [(summaries[r.key]["wall_time_s"], summaries[r.key]["error"], r.label) for r in rungs
               if r.case == case and r.key in summaries and summaries[r.key].get("error")]
        if pts:
            x, y, labels = zip(*pts)
            ax.loglog(x, y, "o-", label=case)
            for xi, yi, lab in pts:
                ax.annotate(lab, (xi, yi), fontsize=7, xytext=(3, 3), textcoords="offset points")
    ax.set_xlabel("wall time on this machine [s]")
    ax.set_ylabel("relative error against the reference")
    ax.set_title("Error against run time")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(Path(out_dir) / "error_vs_walltime.png", dpi=120)
    plt.close(fig)
    made.append("error_vs_walltime.png")
    for case in cases.SECTIONS:
        if hasattr(case, "plot"):
            made += case.plot(out_dir, rungs, summaries, plt)
    return made


def made_by(out, rungs):
    """The command that makes this report: `sph-fsi validate [CASES] --out OUT` (no case names: all of them; OUT
    relative to the working directory when it lies inside it)."""
    reported = list(dict.fromkeys(r.case for r in rungs))
    every = list(dict.fromkeys(r.case for r in cases.all_rungs()))
    try:
        shown = out.resolve().relative_to(Path.cwd().resolve())
    except ValueError:
        shown = out
    names = "" if reported == every else " " + " ".join(reported)
    return f"sph-fsi validate{names} --out {shown.as_posix()}"


def write_report(out_dir, rungs, summaries):
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    plots = _plots(out, rungs, summaries)
    machine = next((s["machine"] for s in summaries.values()), {})
    command = made_by(out, rungs)
    lines = [
        "# Validation: error against run time", "",
        f"Made by `{command}`; rebuild this page from the stored runs with `{command} --report-only`. Each row is one "
        "headless run; its full outputs (summary.json, timeseries.csv) are under `runs/CASE/RUN/`.", "",
        f"Machine: {machine.get('cpus')} CPUs, Python {machine.get('python')}, Numba {machine.get('numba')}, "
        f"NumPy {machine.get('numpy')}; report written {datetime.date.today().isoformat()}. Each run's Numba threads "
        f"and the commit it ran on are in its row (runs are kept and reported until rerun).", "",
        "Wall time includes setup (scene build, first force evaluation; Numba functions come from the on-disk "
        "cache). Particles: the moving ones' phases plus the solid's clamp (not the fluid's walls); steps: solid + "
        "fluid steps. Particle-steps/s counts every solid particle (clamp included) per solid step and every fluid "
        "particle per fluid step, over stepping "
        "time only; a value well below the benchmark's (`docs/performance/BENCH.md`) means the run shared the "
        "2 cores with other work and its wall time is inflated by the same factor.", "",
        "| case | run | dp [mm] | particles | steps | wall [s] | M particle-steps/s | measured | reference | "
        "error | stable | threads, commit |",
        "|---|---|---|---|---|---|---|---|---|---|---|---|",
    ]
    for r in rungs:
        lines.append(_row(r, summaries.get(r.key)))
    for case in cases.SECTIONS:
        if hasattr(case, "table"):
            lines += case.table(out, rungs, summaries)
    lines += ["", "## Plots", ""] + [f"![{p}]({p})" for p in plots]
    (out / "REPORT.md").write_text("\n".join(lines) + "\n")
    return out / "REPORT.md"


