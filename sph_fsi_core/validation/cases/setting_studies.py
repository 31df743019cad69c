"""What the studies of one setting of the water share (pressure_tolerance.py, partial_iteration.py): the default
suite's rungs repeated under each setting, and their table, a row per run with the measure its base rung is judged
by and the cost."""
from dataclasses import replace

from ..report_tools import fmt


def setting_rungs(case, bases, settings):
    """Each base rung again under each of `settings` ((label, keys, what) each) that it names: `bases` is a list of
    (rung, the settings' labels)."""
    return [replace(base, case=case, label=f"{label}__{base.case}_{base.label}", overrides={**base.overrides, **keys},
                    quick=False, bound=None, counterpart="", note=f"{base.key}, {what}")
            for base, labels in bases for label, keys, what in settings if label in labels]


def setting_table(case, heading, doc, column, rungs, summaries, bases, cells, iterations=".1f", commit=False):
    """The study's section: `heading`, the module docstring `doc`'s text after its first paragraph, and a row per run
    of `case` among `rungs`: its base rung's key (`bases`: {key: rung}), its setting (the `column`), the
    measure and what is beside it (cells(base, summary)), the fluid steps, iterations per step (`iterations`:
    their format), the wall time, the threads and, with `commit`, the commit it was run at."""
    runs = [r for r in rungs if r.case == case]
    if not runs:
        return []
    tail = " commit |" if commit else ""
    lines = ["", heading, "", doc.split("\n\n", 1)[1].strip().replace("\n", " "), "",
             f"| rung | {column} | measure | beside | fluid steps | iterations / step | wall [s] | threads |{tail}",
             "|---|---|---|---|---|---|---|---|" + ("---|" if commit else "")]
    for r in runs:
        label = r.label.split("__", 1)[0]
        base = bases[r.note.split(",", 1)[0]]
        s = summaries.get(r.key)
        if s is None:
            lines.append(f"| {base.key} | {label} | not run | | | | | |" + (" |" if commit else ""))
            continue
        if s["stable"] or s.get("judges"):
            measure, beside = cells(base, s)
        else:   # stopped before it could be judged
            measure, beside = "-", f"{s['diverged']['check']} at {s['diverged']['time']:.4g} s"
        if not s["stable"]:
            measure += " (unstable)"
        machine = s.get("machine", {})
        lines.append(f"| {base.key} | {label} | {measure} | {beside} | {s.get('fluid_steps', 0)} | "
                     f"{fmt(s.get('fluid_iterations_per_step'), iterations)} | {s['wall_time_s']:.0f} | "
                     f"{machine.get('numba_threads', '-')} |" + (f" {machine.get('commit', '-')} |" if commit else ""))
    return lines


def rest_pressure_cells(s, digits):
    """The water at rest's cells: the end wall's swing (and the bulk's) over rho g H, to `digits` decimals of a per
    cent, and the wall's mean and its least reading beside."""
    wall, bulk, mean = s["judges"]["wall_swing"], s["judges"]["bulk_swing"], s["judges"]["wall_mean"]
    return (f"swing {100 * wall['error']:.{digits}f} % (bulk {100 * bulk['error']:.{digits}f} %)",
            f"wall mean {100 * mean['error_signed']:+.2f} %, min {wall['min']:.0f} Pa")


def spheric2_cells(s):
    """SPHERIC test 2's cells: the heights' RMS, and the pressures' peaks and P1's onset beside."""
    j = s["judges"]
    p1, p3 = j["P1"], j["P3"]
    return (f"H2 {j['H2']['rms']:.4f} m, H4 {j['H4']['rms']:.4f} m",
            f"P1 peak {p1['peak'] / 1e3:.2f} kPa ({p1['peak_measured'] / 1e3:.2f} measured), onset "
            f"{p1['onset_difference_s']:+.4f} s; P3 peak {p3['peak'] / 1e3:.2f} kPa ({p3['peak_measured'] / 1e3:.2f})")


def deflection_cells(s, value, swing, load_digits):
    """A solid at rest under water's cells: its error against FE, and beside it the swing of its deflection `value`
    (the summary's `swing` key) as a share of it and the water's load, to `load_digits` decimals of a per cent."""
    return (f"{100 * s['error_signed']:+.2f} %", f"swing {100 * s[swing] / abs(s[value]):.1f} % of it, load "
                                                  f"{100 * s['water_load_error']:+.{load_digits}f} %")


def jet_cells(s):
    """The plane jet on a wall's cells: the wall's force against the momentum flux, and the axis pressure's error and
    its swing over 1/2 rho U^2 beside."""
    j = s["judges"]
    return (f"force {100 * j['force']['error_signed']:+.2f} %",
            f"axis pressure {100 * j['axis_pressure']['error_signed']:+.2f} %, its swing "
            f"{100 * j['axis_swing']['error']:.1f} % of 1/2 rho U^2 (max {j['axis_swing']['max']:.0f} Pa)")
