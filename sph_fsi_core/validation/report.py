"""REPORT.md and PNG plots of `sph-fsi validate`, made from the rungs' summary.json files (no simulation here): the
headline table of every rung and the error against wall time; each case's own tables and plots come from its module
(validation/cases/)."""
import datetime
import re
import textwrap
from pathlib import Path

from . import cases
from .report_tools import fmt
from .rung import rung_error
# judges whose single measure a row shows against its reference (_judge_cells)
SCALAR_JUDGES = ("mean", "frequency", "swing", "decay", "impulse")


def measured_against(s, judge=""):
    """(measured, reference, error) of a run's summary as the report's cells: what the scene's evaluate measured,
    against what, and the error (signed where the sign says soft or stiff); with `judge` (a rung's Rung.judge),
    that judge's."""
    if judge:
        # a run that diverged was not judged (its row's stable cell says where it stopped)
        return _judge_cells(s["judges"][judge]) if judge in s.get("judges", {}) else ("-", "-", "-")
    measured = ref = "-"
    judge = next(iter(s["judges"].values())) if s.get("judges") else None    # the first judge: the summary's error
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
        ref = "Lobovsky et al. 2014, T >= 1" if s.get("scene") == "lobovsky_dam_break" else "Martin & Moyce 1952"
    elif s.get("tip_x_peak_m") is not None:
        measured = f"tip x peak {1e3 * s['tip_x_peak_m']:.1f} mm at {s['tip_x_peak_time_s']:.3f} s"
        ref = f"Antoci 2007: {1e3 * s['tip_x_exp_peak_m']:.1f} mm at {s['tip_x_exp_peak_time_s']:.3f} s"
    elif s.get("tip_dx_peak_m") is not None:
        measured = f"tip dx peak {1e3 * s['tip_dx_peak_m']:.2f} mm at {s['tip_dx_peak_time_s']:.3f} s"
        ref = "paper: peak at 0.06-0.08 s"
    elif judge is not None:
        if judge.get("kind") in SCALAR_JUDGES and judge.get("measured") is not None:
            measured, ref, _ = _judge_cells(judge)       # a scalar against an exact value or a scale
        else:
            measured = ", ".join(f"{name} {100 * j['error']:.1f} %" for name, j in s["judges"].items()
                                 if j.get("error") is not None)
            ref = "measured"
    err = f"{100 * s['error']:.2f} %" if s.get("error") is not None else "-"
    if judge is not None and judge.get("error_signed") is not None:
        err = f"{100 * judge['error_signed']:+.2f} %"
    if s.get("error_signed") is not None:
        err = f"{100 * s['error_signed']:+.2f} %"   # the sign says soft (+, deflects more) or stiff
    if s.get("frequency_hz") is not None and s.get("reference_hz") and s.get("error") is not None:
        err = f"{100 * (s['frequency_hz'] / s['reference_hz'] - 1.0):+.2f} %"   # the sign says stiff or soft
    return measured, ref, err


def _judge_cells(j):
    """A scalar judge's cells: a swing as its spread (and mean) against its scale, a decay as the amplitude lost
    per period (and the period) against the loss expected, an impulse as the water's gain (and its worst imbalance)
    against the walls' impulse, a frequency (and its period) or a mean against its exact value."""
    if j.get("measured") is None:
        return "-", f"{j['reference']:.4g}", "-"
    if j["kind"] == "swing":
        return (f"{j['column']} swing {j['measured']:.4g} (mean {j['mean']:.4g})", f"scale {j['reference']:.4g}",
                f"{100 * j['error']:.2f} %")
    if j["kind"] == "decay":
        return (f"{j['column']} loses {100 * j['measured']:.2f} % a period ({j['period_s']:.4g} s)",
                f"{100 * j['reference']:.2f} % a period", f"{100 * j['error_signed']:+.2f} %")
    if j["kind"] == "impulse":
        return (f"{j['column']} gains {j['measured']:.4g} N s (worst imbalance {j['largest_imbalance']:+.3g} N s at "
                f"{j['largest_imbalance_at_s']:.3g} s)", f"the walls' impulse {j['reference']:.4g} N s",
                f"{100 * j['error']:.2f} %")
    if j["kind"] == "frequency":
        return (f"{j['column']} {j['measured']:.4g} Hz (period {1 / j['measured']:.4g} s)",
                f"{j['reference']:.4g} Hz ({1 / j['reference']:.4g} s)", f"{100 * j['error_signed']:+.2f} %")
    return f"{j['column']} {j['measured']:.4g}", f"{j['reference']:.4g}", f"{100 * j['error_signed']:+.2f} %"


def _stable(s):
    d = s["diverged"]
    return "yes" if s["stable"] else f"no: {d['check']} at {d['time']:.4g} s"


def _cost(s):
    """(particles, steps) of a run: the solid's (its stepped clamp included) and the water's, not the walls."""
    return (s["particles"].get("solid", 0) + s["particles"].get("fluid", 0),
            s["solid_steps"] + s.get("fluid_steps", 0))


def _row(rung, s):
    """A rung's row of a study's headline table: its cost, what it measured against what, the error."""
    if s is None:
        return f"| {rung.case} | {rung.label} | not run | | | | | | | | | |"
    stable = _stable(s)
    measured, ref, err = measured_against(s, rung.judge)
    m = s.get("machine", {})
    moving, steps = _cost(s)
    return (f"| {rung.case} | {rung.label} | {s['settings']['numerics.spacing'] * 1e3:.3g} | "
            f"{moving} | {steps} | {s['wall_time_s']:.1f} | "
            f"{fmt(s['particle_steps_per_second'] / 1e6, '.3f')} | {measured} | {ref} | {err} | {stable} | "
            f"{m.get('numba_threads', '-')}, {m.get('commit', '-')} |")


def _plots(out_dir, rungs, summaries):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    # Error against wall time, one series per case (the Pareto view).
    series = {case: [(summaries[r.key]["wall_time_s"], rung_error(r, summaries[r.key]), r.label) for r in rungs
                     if r.case == case and r.key in summaries and rung_error(r, summaries[r.key])]
              for case in sorted({r.case for r in rungs})}
    made = [error_figure(plt, Path(out_dir) / "error_vs_walltime.png", series, "Error against run time",
                         "wall time on this machine [s]", "relative error against the reference")]
    for case in cases.SECTIONS:
        if hasattr(case, "plot"):
            made += case.plot(out_dir, rungs, summaries, plt)
    return made


def error_figure(plt, path, series, title, xlabel, ylabel, styles=None, size=(6, 4.5), label_size=7,
                 legend=None):
    """Error against wall time, log-log: `series` {name: [(wall s, error, point label)]}, a line per name (empty
    ones left out); `styles` {name: plot keywords} (default "o-" in the colour cycle); the PNG's name."""
    fig, ax = plt.subplots(figsize=size)
    for name, pts in series.items():
        if pts:
            x, y, _ = zip(*pts)
            if styles:
                ax.loglog(x, y, label=name, **styles[name])
            else:
                ax.loglog(x, y, "o-", label=name)
            for xi, yi, lab in pts:
                ax.annotate(lab, (xi, yi), fontsize=label_size, xytext=(3, 3), textcoords="offset points")
    ax.set_xlabel(xlabel)
    ax.set_ylabel(ylabel)
    ax.set_title(title)
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(**(legend or {"fontsize": 8}))
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)
    return Path(path).name


def made_by(out, rungs):
    """The command that makes this report: `sph-fsi validate [CASES] --out OUT` (no case names: all of them; OUT
    relative to the working directory when it lies inside it)."""
    reported = list(dict.fromkeys(r.case for r in rungs))
    every = cases.default_case_names()
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


def _wrapped(lines, width=120):
    """Prose lines and list items wrapped at `width` (docs keep their lines short); tables and headings as they are."""
    out = []
    for line in lines:
        if len(line) <= width or line.startswith(("|", "#", "!")):
            out.append(line)
        elif line.startswith("- "):
            out += textwrap.wrap(line, width, subsequent_indent="  ", break_long_words=False,
                                 break_on_hyphens=False)
        else:
            out += textwrap.wrap(line, width, break_long_words=False, break_on_hyphens=False)
    return out


# ---- the default suite's page (docs/validation/REPORT.md) ---------------------------------------------------------

def _commit_cell(s):
    """The commit a run ran on; for a run kept from an older commit, the commit its bits were checked against
    (bits_unchanged.json beside its summary, written when bench.compare_versions showed them the same)."""
    commit = s.get("machine", {}).get("commit", "-")
    kept = s.get("bits_unchanged")
    if kept:
        return f"{commit}; same bits at {kept['same_bits_at']} ({kept['checked']})"
    return commit


def _case_error(rung, s, summaries):
    """(error as a number, its cell) of a rung of the default suite: the scene's own, or the case's derived one."""
    for case in cases.CASES:
        derived = getattr(case, "derived_error", None)
        found = derived(rung, summaries) if derived else None
        if found is not None:
            return found[0], f"{100 * found[0]:.2f} % (against {found[1]})"
    _, _, cell = measured_against(s, rung.judge)
    return rung_error(rung, s), cell


def _measures(case_name):
    for case in cases.CASES:
        if case_name in getattr(case, "MEASURES", {}):
            return case.MEASURES[case_name]
    return None


def _headline(rungs, summaries):
    """The default suite's table: a row per rung, the case's measure and reference on its first row."""
    lines = ["| case | measured | against (source) | run | dp [mm] | particles | steps | wall [s] | threads | "
             "value | reference value | error | commit |", "|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
    shown = set()
    for r in rungs:
        s = summaries.get(r.key)
        first = r.case not in shown
        shown.add(r.case)
        what, against = (_measures(r.case) or ((s or {}).get("error_metric", "-"), "")) if first else ("", "")
        name = f"**{r.case}**" if first else ""
        run = r.resolution or r.label
        if s is None:
            lines.append(f"| {name} | {what} | {against} | {run} | not run yet | | | | | | | | |")
            continue
        measured, ref, _ = measured_against(s, r.judge)
        _, err = _case_error(r, s, summaries)
        if not s["stable"]:
            err = f"{err}; unstable: {_stable(s)}"
        moving, steps = _cost(s)
        m = s.get("machine", {})
        lines.append(f"| {name} | {what} | {against} | {run} | {s['settings']['numerics.spacing'] * 1e3:.3g} | "
                     f"{moving} | {steps} | {s['wall_time_s']:.0f} | {m.get('numba_threads', '-')} | {measured} | "
                     f"{ref} | {err} | {_commit_cell(s)} |")
    return lines


def _error_figure(out_dir, rungs, summaries, plt):
    """Error against wall time, log-log, a line per case's ladder (points unjoined where the rungs are shapes or
    loads, not resolutions: a module's NOT_LADDERS)."""
    unjoined = {name for case in cases.CASES for name in getattr(case, "NOT_LADDERS", ())}
    markers = "osD^v<>phX*P"
    names = list(dict.fromkeys(r.case for r in rungs))
    series, styles = {}, {}
    for i, name in enumerate(names):
        series[name] = []
        for r in rungs:
            s = summaries.get(r.key)
            if r.case != name or s is None:
                continue
            err, _ = _case_error(r, s, summaries)
            if err:
                series[name].append((s["wall_time_s"], err, r.resolution or r.label))
        styles[name] = {"marker": markers[i % len(markers)], "linestyle": "none" if name in unjoined else "-",
                        "color": plt.cm.tab20(i % 20)}
    return error_figure(plt, Path(out_dir) / "error_vs_walltime.png", series,
                        "The default scheme: error against run time, a line per case",
                        "wall time [s] (threads in the table)", "|error| against the reference", styles=styles,
                        size=(7.5, 5.5), label_size=6, legend={"fontsize": 7, "ncol": 2})


# Study pages that no one module makes: what each shows
_OTHER_STUDIES = {"schemes": "the solid schemes and coupling models compared, as run up to 2026-12-01 (Gray's "
                             "scheme, the quadratic fit without the strain gradient, the explicit pressure).",
                  "lobovsky": "Lobovsky's dam break by release, start, density tolerance and step (the fluid "
                              "study's rungs of that case)."}


def _study_summary(name):
    """The first sentence of the study module's docstring (cases/NAME.py), or _OTHER_STUDIES's line."""
    for case in cases.STUDIES:
        if case.__name__.rsplit(".", 1)[-1] == name and case.__doc__:
            text = " ".join(case.__doc__.split())
            return re.split(r"(?<! al)\. ", text)[0].rstrip(".") + "."
    return _OTHER_STUDIES.get(name, "")


def _studies(out):
    """Links to the study pages under out/studies/, each with what it shows."""
    return [f"- [{page.parent.name}](studies/{page.parent.name}/REPORT.md): {_study_summary(page.parent.name)}"
            for page in sorted((out / "studies").glob("*/REPORT.md"))]


def write_default_report(out_dir, rungs, summaries):
    """docs/validation/REPORT.md: the default suite's headline table, its error-against-wall-time figure, the peers
    beside ours, and the links to the studies."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    figure = _error_figure(out, rungs, summaries, plt)
    command = made_by(out, rungs)
    machine = next((s["machine"] for s in summaries.values()), {})
    lines = [
        "# Validation: the default scheme's error against run time", "",
        f"Made by `{command}`; rebuilt from the stored runs by `{command} --report-only`. Every row is one headless "
        "run of today's default (every scene's `solid.scheme: quadratic_gradient`, the mirrored clamp, the implicit "
        "pressure, the pressure coupling) with only the case's own lengths, material and resolution set "
        "(validation/cases/default_*.py, spheric2.py); its outputs (summary.json, timeseries.csv) are under "
        "`runs/CASE/RUN/`. Each scene judges its own run (scenes/*.py, `evaluate`).", "",
        f"Machine: {machine.get('cpus')} CPUs, Python {machine.get('python')}, Numba {machine.get('numba')}, NumPy "
        f"{machine.get('numpy')}; {len(summaries)} of {len(rungs)} runs made; page written "
        f"{datetime.date.today().isoformat()}. Wall time includes the scene's build (Numba's kernels from the on-disk "
        "cache); runs made two at once, each on the threads its row gives (this host's speed drifts by up to 2x: "
        "docs/performance/BENCH.md). Particles: the solid's (its stepped clamp included) and the water's, not the "
        "walls; steps: the solid's and the water's. A run kept from an older commit says which commit's bits it was "
        "checked against (`python -m bench.compare_versions`).", "",
        *_headline(rungs, summaries), "",
        f"![error against wall time]({figure})", "",
        "Errors: the frequency's and the deflections' signed (+: softer than the reference), the fronts' and "
        "Antoci's gate's an RMS over the record, SPHERIC test 2's the first judge's (H2's RMS over 0-6 s, in m "
        "over the measured range), the standing wave's frequency signed (+: faster than linear theory) and its "
        "loss the fraction of its amplitude lost a period; the paper's gate has no measurement, so its rungs are "
        "held to the finest one.",
    ]
    for case in cases.CASES:
        if hasattr(case, "table"):
            lines += case.table(out, rungs, summaries)
        if hasattr(case, "plot"):
            lines += [""] + [f"![{p}]({p})" for p in case.plot(out, rungs, summaries, plt)]
    lines += ["", "## Studies", "", "Other schemes and options, and the default's sensitivity, each on its own page "
              "(`sph-fsi validate CASE --out docs/validation/studies/CASE`):", "", *_studies(out),
              "", "Verification of the parts: [linear_modes](linear_modes/REPORT.md) (the solid schemes' linear "
              "stability), [STABILITY.md](STABILITY.md) (stiff and extreme inputs), [OPEN.md](OPEN.md) (what is "
              "still wrong)."]
    (out / "REPORT.md").write_text("\n".join(_wrapped(lines)) + "\n")
    return out / "REPORT.md"
