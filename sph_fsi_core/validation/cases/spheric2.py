"""SPHERIC test 2 (config/spheric2_dam_break.yaml: MARIN's 3D dam break onto a box, Kleefsman et al. 2005) as a
validation case: its rungs, its table and its plot, in one place.

The scene judges itself (answers/judges.py): the water heights H2 and H4 by their RMS difference from the
measurement over 0-6 s (goal 0.03 m, no time shift), the pressures P1 and P3 on the box's face by their impact's onset
(the first time each 5 ms-averaged series reaches 1 kPa; goal within 0.01 s of the measured) and their peak after it
(goal within 20 %). The rungs take 20, 25 and 30 particles through the column's 0.55 m depth, the 0.55 m a whole
number of spacings at each.
"""
from pathlib import Path

import numpy as np

from ..report_tools import save_panels, series_rows
from ..rung import Rung

CASE = "spheric2"
SCENE = "spheric2_dam_break"
DEPTH = 0.55                      # m, the column (reference_data/spheric2_geometry.csv)
LADDER = (20, 25, 30)             # particles through the depth (40: about an hour on 2 cores, not run yet)
JUDGED = ("H2", "H4", "P1", "P3")
# What the default suite's headline reports, and against what (its first judge's error; every judge in the table)
MEASURES = {CASE: ("water height H2 in front of the box: RMS over 0-6 s, over the measured range",
                   "MARIN's measurement (Kleefsman et al. 2005; reference_data/spheric2_exp_water_height.csv)")}


def rungs():
    return [Rung(CASE, f"H_over_dp_{n}", SCENE, {"numerics.spacing": DEPTH / n}, end_time=6.0, resolution=f"H/dp {n}",
                 note=f"dp = {DEPTH / n * 1e3:.3g} mm, {n} particles through the column; H2, H4, P1, P3 against "
                      f"MARIN's measurements") for n in LADDER]


def _cell(x, spec=".3g", scale=1.0, unit=""):
    return "-" if x is None else f"{x * scale:{spec}}{unit}"


def table(out_dir, rungs, summaries):
    """The case's section of the report: a row per rung, its cost and each judge's measures."""
    mine = [r for r in rungs if r.case == CASE]
    if not mine:
        return []
    lines = ["", "## SPHERIC test 2: 3D dam break onto a box (MARIN, Kleefsman et al. 2005)", "",
             "Water heights H2 (in front of the box) and H4 (in the reservoir): RMS difference from the measurement "
             "over 0-6 s (goal 0.03 m) and the time shift that would minimise it. Pressures P1 and P3 on the box's "
             "face, both series averaged over the same centred 5 ms window: the impact's onset (first time at 1 kPa; "
             "measured 0.394 s for P1; goal within 0.01 s) and the peak after it (goal within 20 %). Walls: the "
             "tank's and the box's (3 layers each). The headline table's error is H2's RMS over the measured range "
             "(0.34 m). The run's commit: the headline table; the summaries' judges were evaluated again from the "
             "stored time series when a series judge's error became relative (the same RMS, onsets and peaks).", "",
             "| run | dp [mm] | water | walls | fluid steps | wall [s] | H2 RMS [m] (shift [s]) | H4 RMS [m] "
             "(shift [s]) | P1 onset diff [s] | P1 peak [kPa] (measured) | P3 onset diff [s] | P3 peak [kPa] "
             "(measured) | stable |",
             "|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
    for r in mine:
        s = summaries.get(r.key)
        if s is None:
            lines.append(f"| {r.label} | {r.overrides['numerics.spacing'] * 1e3:.3g} | not run |" + " |" * 10)
            continue
        j = s.get("judges", {})
        h2, h4, p1, p3 = (j.get(k, {}) for k in JUDGED)
        lines.append(
            f"| {r.label} | {s['settings']['numerics.spacing'] * 1e3:.3g} | {s['particles'].get('fluid', 0):,} | "
            f"{s['particles'].get('walls', 0):,} | {s.get('fluid_steps', 0):,} | {s['wall_time_s']:.0f} | "
            f"{_cell(h2.get('rms'), '.4f')} ({_cell(h2.get('best_time_shift_s'), '+.3f')}) | "
            f"{_cell(h4.get('rms'), '.4f')} ({_cell(h4.get('best_time_shift_s'), '+.3f')}) | "
            f"{_cell(p1.get('onset_difference_s'), '+.4f')} | {_cell(p1.get('peak'), '.2f', 1e-3)} "
            f"({_cell(p1.get('peak_measured'), '.2f', 1e-3)}) | {_cell(p3.get('onset_difference_s'), '+.4f')} | "
            f"{_cell(p3.get('peak'), '.2f', 1e-3)} ({_cell(p3.get('peak_measured'), '.2f', 1e-3)}) | "
            f"{'yes' if s.get('stable') else 'NO'} |")
    return lines


def plot(out_dir, rungs, summaries, plt):
    """spheric2.png: each rung's H2, H4, P1 and P3 beside the measurement (the pressures 5 ms-averaged, as judged,
    over the first impact; the heights over 0-6 s)."""
    from ...answers.judges import centred_mean, read_measurement
    runs = [(r, series_rows(out_dir, r)) for r in rungs if r.case == CASE and r.key in summaries]
    runs = [(r, rows) for r, rows in runs if rows is not None]
    if not runs:
        return []
    heights = read_measurement("reference_data:spheric2_exp_water_height.csv", "")
    pressures = read_measurement("reference_data:spheric2_exp_pressure.csv", "")
    fig, axes = plt.subplots(2, 2, figsize=(13, 8))
    panels = (("H2", heights, "H2_m", 1.0, "water height H2 [m]", (0.0, 6.0)),
              ("H4", heights, "H4_m", 1.0, "water height H4 [m]", (0.0, 6.0)),
              ("P1", pressures, "P1_Pa", 1e-3, "pressure P1 [kPa], 5 ms average", (0.3, 1.2)),
              ("P3", pressures, "P3_Pa", 1e-3, "pressure P3 [kPa], 5 ms average", (0.3, 1.2)))
    for ax, (column, data, file_column, scale, label, window) in zip(axes.flat, panels):
        t_exp = data["time_s"]
        y_exp = data[file_column]
        if column.startswith("P"):
            y_exp = centred_mean(t_exp, y_exp, 0.005)
        ax.plot(t_exp, y_exp * scale, "k-", lw=0.8, label="MARIN (Kleefsman et al. 2005)")
        for r, rows in runs:
            t = np.array([float(x["time"]) for x in rows])
            y = np.array([float(x[column]) for x in rows])
            if column.startswith("P"):
                y = centred_mean(t, y, 0.005)
            ax.plot(t, y * scale, lw=1.0, label=f"{r.label} (dp = {r.overrides['numerics.spacing'] * 1e3:.3g} mm)")
        ax.set_xlim(*window)
        ax.set_xlabel("t [s]")
        ax.set_ylabel(label)
    fig.suptitle("SPHERIC test 2: 3D dam break onto a box")
    return [save_panels(plt, fig, axes.flat, Path(out_dir) / "spheric2.png", legend_size=7)]
