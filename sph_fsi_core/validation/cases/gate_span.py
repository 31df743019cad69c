"""The paper's gate on the narrowest periodic slab beside the same run across the paper's 36 mm
(scenes/elastic_gate.py, judged by its evaluate): the counterparts' kept runs read from their own reports; a table and
a plot."""
import csv
import json
from pathlib import Path

from ..report_tools import fmt, save_panels, series_rows
from ..rung import Rung
from .gate import PAPER_GATE_LADDER


# The paper's gate on the narrowest periodic slab (the scene's span: 6 layers at 1 mm) beside the same run
# across the paper's 36 mm (each counterpart's kept run): whether the width of a slab uniform across y moves the answer
# (the main job's cost: docs/validation/OPEN.md 5). The default scheme and Gray's, at 3, 4 and 6 particles through.
def rungs():
    rungs = [Rung("gate_span", "default_dp1mm", "elastic_gate", {"numerics.spacing": 0.001}, end_time=0.14,
                  note="the paper's gate at 1 mm on the narrowest slab, the default scheme (the main job)",
                  counterpart="solid_pressure/gate_default_elastic_gate_dp1mm"),
             Rung("gate_span", "gray2001_dp1mm", "elastic_gate",
                  {"numerics.spacing": 0.001, "coupling.model": "pressure", "solid.scheme": "gray2001"}, end_time=0.14,
                  note="the paper's gate at 1 mm on the narrowest slab with the paper's scheme, solid.scheme = "
                       "gray2001",
                  counterpart="elastic_gate/pressure_dp1mm")]
    for dp, label, through in PAPER_GATE_LADDER:
        rungs.append(Rung("gate_span", f"default_{label}", "elastic_gate", {"numerics.spacing": dp}, end_time=0.14,
                          note=f"dp = {dp * 1e3:.3g} mm ({through} particles through the gate) on the narrowest slab, "
                               f"the default scheme", counterpart=f"solid_pressure/gate_default_elastic_gate_{label}"))
        rungs.append(Rung("gate_span", f"gray2001_{label}", "elastic_gate",
                          {"numerics.spacing": dp, "coupling.model": "pressure", "solid.scheme": "gray2001"},
                          end_time=0.14, note=f"dp = {dp * 1e3:.3g} mm ({through} particles through the gate) on the "
                                              f"narrowest slab, solid.scheme = gray2001",
                          counterpart=f"elastic_gate/pressure_{label}"))
    return rungs


def _counterpart_run(out_dir, key):
    """The kept run (summary, timeseries rows) of rung `key` ("case/label") in the report directory next to this one
    (OUT/../CASE/runs/CASE/LABEL), in the schemes' study beside it (OUT/../schemes/runs/CASE/LABEL: the older
    schemes' gate runs) or in this one's parent's runs (OUT/../runs/CASE/LABEL); (None, None) if none holds it."""
    case, label = key.split("/")
    parent = Path(out_dir).parent
    for run in (parent / case / "runs" / case / label, parent / "schemes" / "runs" / case / label,
                parent / "runs" / case / label):
        if (run / "summary.json").is_file():
            rows = None
            if (run / "timeseries.csv").is_file():
                with (run / "timeseries.csv").open() as fh:
                    rows = list(csv.DictReader(fh))
            return json.loads((run / "summary.json").read_text()), rows
    return None, None


def _free_end_gap(rows_a, rows_b):
    """[(t, dx_a - dx_b)] of the free end at the sample times both runs have (m; empty without both)."""
    if not rows_a or not rows_b:
        return []
    b = {round(float(r["time"]), 9): float(r["tip_dx"]) for r in rows_b}
    return [(float(r["time"]), float(r["tip_dx"]) - b[round(float(r["time"]), 9)]) for r in rows_a
            if round(float(r["time"]), 9) in b]


def _free_end_difference(rows_a, rows_b, until):
    """Largest |dx_a - dx_b| of the free end over the samples both runs have at t <= until, m (None without both)."""
    diffs = [abs(d) for t, d in _free_end_gap(rows_a, rows_b) if t <= until + 1e-12]
    return max(diffs) if diffs else None


def table(out_dir, rungs, summaries):
    """The paper's gate on the narrowest periodic slab beside the same run across the paper's 36 mm (gate_span)."""
    runs = [r for r in rungs if r.case == "gate_span"]
    if not runs:
        return []
    lines = ["", "## The paper's gate: the narrowest periodic slab against the paper's 36 mm", "",
             "Each run on the slab the scene builds since 2026-12-05 (6 layers across y) beside the same run across "
             "the paper's 36 mm (the counterpart's kept run, in its own report). The flow is uniform across y, so "
             "the slab's width should not move the answer: the free end's largest difference up to 0.06 s (the rise "
             "to the peak) and over the whole run, against the size of the deflection; the strain energy's peak for "
             "the paper's 36 mm gate (the energy goes as the span). Wall times: each run's own threads and host "
             "state (the `threads, commit` column above and the counterpart's report).", "",
             "| run | particles: 36 mm / narrow | dx peak [mm] at [s]: 36 mm / narrow | spring-back | strain energy "
             "peak, 36 mm gate [mJ] | free end's largest difference to 0.06 s / over the run [mm] | checks passed | "
             "wall [s]: 36 mm / narrow | threads |", "|---|---|---|---|---|---|---|---|---|"]

    def count(s):
        p = s["particles"]
        return p["solid"] + p["fluid"] + p["walls"]

    def energy(s):
        return s.get("strain_energy_peak_paper_width_j", s["strain_energy_peak_j"])

    def checks(s):
        return sum(bool(s.get(k)) for k in ("check_peak_in_paper_window", "check_springs_back",
                                            "check_energy_rises_and_falls"))

    for r in runs:
        new, new_rows = summaries.get(r.key), series_rows(out_dir, r)
        old, old_rows = _counterpart_run(out_dir, r.counterpart)
        if new is None or old is None:
            lines.append(f"| {r.label} | {'not run' if new is None else 'narrow run only'}; counterpart "
                         f"{r.counterpart}{' not kept' if old is None else ''} | | | | | | | |")
            continue
        early = _free_end_difference(new_rows, old_rows, 0.06)
        whole = _free_end_difference(new_rows, old_rows, new["simulated_time_s"])
        lines.append(
            f"| {r.label} | {count(old):,} / {count(new):,} | {1e3 * old['tip_dx_peak_m']:.4f} at "
            f"{old['tip_dx_peak_time_s']:.3f} / {1e3 * new['tip_dx_peak_m']:.4f} at {new['tip_dx_peak_time_s']:.3f} | "
            f"{100 * old['spring_back_fraction']:.1f} / {100 * new['spring_back_fraction']:.1f} % | "
            f"{1e3 * energy(old):.4f} / {1e3 * energy(new):.4f} | "
            f"{fmt(None if early is None else 1e3 * early, '.2g')} / "
            f"{fmt(None if whole is None else 1e3 * whole, '.2g')} | "
            f"{checks(old)} / {checks(new)} of 3 | {old['wall_time_s']:.0f} / {new['wall_time_s']:.0f} | "
            f"{old['machine'].get('numba_threads')} / {new['machine'].get('numba_threads')} |")
    return lines


def plot(out_dir, rungs, summaries, plt):
    """Each gate_span run's free end beside its 36 mm counterpart's, and their difference."""
    pairs = []
    for r in rungs:
        if r.case == "gate_span" and r.key in summaries:
            rows = series_rows(out_dir, r)
            _, old_rows = _counterpart_run(out_dir, r.counterpart)
            if rows and old_rows:
                pairs.append((r, rows, old_rows))
    if not pairs:
        return []
    fig, axes = plt.subplots(2, 1, figsize=(7, 6.5), sharex=True)
    for i, (r, rows, old_rows) in enumerate(pairs):
        for series, style, label in ((rows, "-", f"{r.label}, narrowest slab"),
                                     (old_rows, "--", f"{r.counterpart}, 36 mm")):
            axes[0].plot([float(x["time"]) for x in series], [1e3 * float(x["tip_dx"]) for x in series], style,
                         color=f"C{i}", label=label)
        gap = _free_end_gap(rows, old_rows)
        axes[1].plot([t for t, _ in gap], [1e3 * d for _, d in gap], "-", color=f"C{i}", label=r.label)
    axes[0].set_ylabel("free-end x displacement [mm]")
    axes[0].set_title("The paper's gate: the narrowest periodic slab against the paper's 36 mm")
    axes[1].set_ylabel("narrowest minus 36 mm [mm]")
    axes[1].set_xlabel("t [s]")
    return [save_panels(plt, fig, axes, Path(out_dir) / "gate_span_free_end.png", legend_size=7)]
