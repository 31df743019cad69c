"""A study of Antoci's gate (not a validation case): is its 20 % short opening the gate too stiff, or the water's
load falling too fast?

The default scheme at 1.25 mm (4 particles through the gate) with the published E = 12 MPa, and softer, 8.4 and
6 MPa (nu 0.4 throughout), and the published material with the clamp line 3 mm higher (a longer free length, the
clamp's top kept). For each: the free end's x peak and its time, and the water's level at the back wall and just
behind the gate (config/antoci_gate.yaml's level probes) against time. A gate alone would peak later as sqrt(m / k):
t_peak ~ 1 / sqrt(E) at a given load; a peak that rises with 1 / E but keeps its time is set by the load instead.
The scene keeps the published material: this is a sensitivity study, reported as one.
"""
from pathlib import Path

import numpy as np

from ...answers.references import antoci_gate_tip
from ..report_tools import save_panels, series_rows
from ..rung import Rung

CASE = "antoci_stiffness"
SCENE = "antoci_gate"
SPACING = 0.00125
END_TIME = 0.3               # s: past the measured peak (0.16 s) and the softest gate's
PUBLISHED_E = 12.0e6         # Pa (config/antoci_gate.yaml)
SOFTER_E = (8.4e6, 6.0e6)
CLAMP_RAISED_BY = 0.003      # m


def rungs():
    out = [Rung(CASE, f"E{e / 1e6:.3g}MPa", SCENE, {"numerics.spacing": SPACING, "solid.young_modulus": e},
                end_time=END_TIME, note=f"E = {e / 1e6:.3g} MPa, nu = 0.4")
           for e in (PUBLISHED_E,) + SOFTER_E]
    out.append(Rung(CASE, "E12MPa_clamp_3mm_higher", SCENE,
                    {"numerics.spacing": SPACING, "geometry.gate_length": 0.079 + CLAMP_RAISED_BY,
                     "geometry.gate_clamp_height": 0.0685 - CLAMP_RAISED_BY},
                    end_time=END_TIME, note="E = 12 MPa, the clamp line 3 mm higher (its top kept)"))
    return out


def _series(out_dir, rung):
    rows = series_rows(out_dir, rung)
    if rows is None:
        return None
    return {k: np.array([float(r[k]) for r in rows]) for k in ("time", "tip_dx", "level_back", "level_gate")}


def _peak(t, x):
    i = int(np.argmax(x))
    return float(x[i]), float(t[i])


def table(out_dir, rungs, summaries):
    mine = [r for r in rungs if r.case == CASE]
    if not mine:
        return []
    measured = antoci_gate_tip("x")
    k = int(np.argmax(measured[1]))
    lines = ["", "## Antoci's gate: the gate's stiffness against the water's load (a study)", "",
             f"The default scheme at {SPACING * 1e3:g} mm to {END_TIME:g} s. Measured (Antoci et al. 2007): the free "
             f"end's x peak {measured[1][k] * 1e3:.1f} mm at {measured[0][k]:.3f} s. 'sqrt(E) scaling': the peak's "
             "time the published material's would move to if the gate alone set it, t_12 sqrt(12 MPa / E). Levels: "
             "the water's height 10 mm from the back wall and 10 mm behind the gate's wet face, at the peak's time.",
             "", "| run | E [MPa] | free length [mm] | peak x [mm] | its time [s] | sqrt(E) scaling [s] | "
             "peak against measured | level behind the gate [mm] | level at the back wall [mm] | wall [s] |",
             "|---|---|---|---|---|---|---|---|---|---|"]
    base_time = None
    for r in mine:
        s = summaries.get(r.key)
        series = _series(out_dir, r) if s is not None else None
        if series is None:
            lines.append(f"| {r.label} | not run |" + " |" * 8)
            continue
        e = s["settings"]["solid.young_modulus"]
        peak, when = _peak(series["time"], series["tip_dx"])
        if r.label == f"E{PUBLISHED_E / 1e6:.3g}MPa":
            base_time = when
        scaled = base_time * np.sqrt(PUBLISHED_E / e) if base_time is not None else float("nan")
        i = int(np.argmin(np.abs(series["time"] - when)))
        free = s.get("geometry_effective", {}).get("gate_free_length_m", float("nan"))
        lines.append(f"| {r.label} | {e / 1e6:.3g} | {free * 1e3:.2f} | {peak * 1e3:.2f} | {when:.3f} | "
                     f"{scaled:.3f} | {peak / measured[1][k] - 1.0:+.1%} | {series['level_gate'][i] * 1e3:.1f} | "
                     f"{series['level_back'][i] * 1e3:.1f} | {s['wall_time_s']:.0f} |")
    return lines


def plot(out_dir, rungs, summaries, plt):
    """antoci_stiffness.png: the free end's x against time beside the measurement, and the two water levels."""
    runs = [(r, _series(out_dir, r)) for r in rungs if r.case == CASE and r.key in summaries]
    runs = [(r, s) for r, s in runs if s is not None]
    if not runs:
        return []
    measured = antoci_gate_tip("x")
    fig, axes = plt.subplots(1, 3, figsize=(15, 4.5))
    axes[0].plot(measured[0], measured[1] * 1e3, "ko", ms=4, label="Antoci et al. 2007")
    for r, s in runs:
        axes[0].plot(s["time"], s["tip_dx"] * 1e3, lw=1.0, label=r.label)
        axes[1].plot(s["time"], s["level_gate"] * 1e3, lw=1.0, label=r.label)
        axes[2].plot(s["time"], s["level_back"] * 1e3, lw=1.0, label=r.label)
    for ax, label in zip(axes, ("free end x [mm]", "level 10 mm behind the gate [mm]",
                                "level 10 mm from the back wall [mm]")):
        ax.set_xlabel("t [s]")
        ax.set_ylabel(label)
    fig.suptitle(f"Antoci's gate at {SPACING * 1e3:g} mm: stiffness against load (a study)")
    return [save_panels(plt, fig, axes, Path(out_dir) / "antoci_stiffness.png", legend_size=7)]
