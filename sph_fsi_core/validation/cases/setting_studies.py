"""What the studies of one setting of the water share (pressure_tolerance.py, partial_iteration.py): the default
suite's rungs repeated under each setting, and their table, a row per run with the measure its base rung is judged
by and the cost."""
from dataclasses import replace

import numpy as np

from ..report_tools import fmt, series_rows
from ..rung import rung_error


def setting_rungs(case, bases, settings):
    """Each base rung again under each of `settings` ((label, keys, what) each) that it names: `bases` is a list of
    (rung, the settings' labels)."""
    return [replace(base, case=case, label=f"{label}__{base.case}_{base.label}", overrides={**base.overrides, **keys},
                    quick=False, bound=None, counterpart="", note=f"{base.key}, {what}")
            for base, labels in bases for label, keys, what in settings if label in labels]


def bases_by_key(pool, bases):
    """(rung, the settings' labels) for each (key, labels) of `bases`, the rung the one of `pool` with that key."""
    every = {r.key: r for r in pool}
    return [(every[key], labels) for key, labels in bases]


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


# the steel gate's window for its ringing: after the water's front has reached the gate's free end (about 10 ms)
STEEL_WINDOW_S = (0.02, 0.04)


def steel_ringing(out_dir, rung):
    """The steel gate's free end over STEEL_WINDOW_S from the run's time series: the mean and standard deviation of
    its x displacement, the mean push on the gate, and the static deflection that push gives spread evenly over the
    gate (beam theory, F L^3 / 8 E I, I = w T^3 / 12 across the slab's width w); None if it was not run."""
    rows = series_rows(out_dir, rung)
    if not rows:
        return None
    t = np.array([float(r["time"]) for r in rows])
    inside = (t > STEEL_WINDOW_S[0] - 1e-9) & (t < STEEL_WINDOW_S[1] + 1e-9)
    dx = np.array([float(r["tip_dx"]) for r in rows])[inside]
    push = np.array([float(r["coupling_force_x"]) for r in rows])[inside].mean()
    return {"mean_m": float(dx.mean()), "std_m": float(dx.std()), "push_n": float(push)}


def with_steel_ringing(out_dir, rungs, summaries):
    """`summaries` with each steel gate run's `ringing` (steel_ringing) added, for steel_gate_cells."""
    out = dict(summaries)
    for r in rungs:
        if "steel_gate" in r.label and r.key in out:
            out[r.key] = {**out[r.key], "ringing": steel_ringing(out_dir, r)}
    return out


def steel_gate_cells(s):
    """The steel gate's cells: its free end's swing over STEEL_WINDOW_S (standard deviation) as a share of its mean
    there, and beside it the mean, the static deflection of the mean push spread evenly over the gate (beam theory,
    F L^3 / 8 E I, I = w T^3 / 12 across the slab's width w; the sizes from the run's settings) and the push
    (with_steel_ringing's `ringing`)."""
    ringing, settings = s.get("ringing"), s["settings"]
    if ringing is None:
        return "-", "-"
    width, thick, free = settings["geometry.slab"], settings["geometry.thick"], settings["geometry.free"]
    stiffness = 8.0 * settings["solid.young_modulus"] * width * thick ** 3 / 12.0 / free ** 3
    static = abs(ringing["push_n"]) / stiffness
    return (f"swing {1e6 * ringing['std_m']:.3f} um, {100 * ringing['std_m'] / abs(ringing['mean_m']):.0f} % of "
            f"its mean", f"mean {1e6 * ringing['mean_m']:+.3f} um (the mean push {ringing['push_n']:+.3f} N spread "
            f"evenly: {1e6 * static:.3f} um), {STEEL_WINDOW_S[0]:g}-{STEEL_WINDOW_S[1]:g} s")


def standing_wave_cells(s):
    """A small standing wave's cells: the amplitude it loses a period, and its frequency's error beside."""
    j = s["judges"]
    return (f"loss {100 * j['loss']['error']:.1f} % a period",
            f"frequency {100 * j['period']['error_signed']:+.1f} % against linear theory")


def antoci_cells(s):
    """Antoci's gate released: the free end's RMS against the measured curve, and its peak beside."""
    return f"{100 * s['error']:.2f} %", f"peak {1e3 * s['tip_x_peak_m']:.1f} mm at {s['tip_x_peak_time_s']:.3f} s"


def study_cells(base, s):
    """The cells of a setting study's row by its base rung's case: the measure it is judged by, and what is beside it
    (the water at rest to 2 decimals, the solids at rest, the steel gate, Antoci's gate, SPHERIC, the jet, the standing
    wave; else its error)."""
    if base.case == "rest_pressure":
        return rest_pressure_cells(s, 2)
    if base.case == "jet_on_wall":
        return jet_cells(s)
    if base.case == "antoci_static":
        return deflection_cells(s, "tip_deflection_m", "tip_deflection_swing_m", 1)
    if base.case == "hydrostatic_plate":
        return deflection_cells(s, "midspan_deflection_m", "midspan_deflection_swing_m", 2)
    if base.case == "steel_gate":
        return steel_gate_cells(s)
    if base.case == "antoci":
        return antoci_cells(s)
    if base.case == "spheric2":
        return spheric2_cells(s)
    if base.case.startswith("standing_wave"):
        return standing_wave_cells(s)
    return f"{100 * rung_error(base, s):.2f} %", "-"
