"""A geometry scene's judges: how its time series is held against a reference, declared in the scene file.

    frequency  the dominant frequency of a column (answers/oscillation.measure_frequency) against `reference` Hz
    mean       the column's mean over [from, to] against `reference`; with a baseline (baseline_from, baseline_to),
               its change from its mean over the baseline's window (a level's rise)
    series     the column (times `scale`) against a measured series in a CSV file, over [from, to]: the RMS of the
               difference (the simulated series interpolated at the measurement's times), the time shift that
               minimises it (within +-0.2 s, steps of 1 ms) and the RMS after it; with `threshold`, the first time each
               series reaches it (an impact's onset) and the peak of each from 10 ms before the measured onset to
               `to`. With `average` both series are first averaged over a centred window of that length (a
               measurement sampled at 1 kHz and a simulation's 1 ms samples are both noisy at an impact: the same
               window on both).
    swing      the column's standard deviation over [from, to] as a fraction of `reference` (a scale in the
               column's unit, e.g. rho g H for a pressure): how far a value that should hold still swings from
               sample to sample (with the samples one fluid step apart, from step to step)
    decay      the fraction of the column's oscillation amplitude lost per period over [from, to]
               (answers/oscillation.amplitude_loss_per_period: the half-cycle extremes' amplitudes fitted
               log-linear in time, over the period measured as a frequency judge measures it), against `reference`
               (default 0: an inviscid answer loses none, so the error is the loss itself)
    impulse    the water's momentum (`column`, a fluid_momentum_ column) against the impulse of the force columns
               `forces` (the water's force on each wall it touches, along the same axis): by Newton's third law the
               water gains what the walls lose, so at every sample in [from, to] its change since `from` should be
               minus the forces' impulse since then (each force sample the mean over the interval it closes, so the
               impulse is the sum of samples times intervals); the error is the largest imbalance over the largest
               impulse

Each judge reports its measures, its error (relative: to the reference for a frequency and a mean; for a series the
RMS over the measured series' range in the window, the RMS itself in the column's unit beside it; for a swing the
standard deviation over the reference; for a decay the loss less the reference, a fraction per period; for an
impulse the largest imbalance over the largest impulse) and, where
the scene sets a tolerance, a `check_<judge>...` flag. The summary's `error` is the first judge's.
A measurement file is a CSV with '#' comment lines and a header row, time (s) in its first column; a path relative to
the scene file, or `reference_data:<name>` for the package's copies (answers/reference_data, with their sources).
"""
import csv
import io
import math
from pathlib import Path

import numpy as np

from ..geometry.parts import list_entries
from ..schema import SceneError
from .oscillation import amplitude_loss_per_period, measure_frequency
from .references import DATA_DIR

PACKAGE_DATA = "reference_data:"
# the time shift searched, s, and its step
SHIFT_RANGE = 0.2
SHIFT_STEP = 1.0e-3
# a peak is sought from this long before the measured onset (s)
PEAK_LEAD = 0.01
# a frequency is measured on a record of at least this many periods of its reference (as scenes/cases/cantilever.py's)
MIN_PERIODS = 1.0


def measurement_path(value):
    return DATA_DIR / value[len(PACKAGE_DATA):] if value.startswith(PACKAGE_DATA) else Path(value)


def read_measurement(value, key):
    """{column: array} of a measurement CSV (SceneError naming `key` if it cannot be read)."""
    path = measurement_path(value)
    if path.is_dir():
        raise SceneError(f"{key} = {value!r}: a directory, not a file; allowed: a CSV file relative to the scene "
                         f"file, or reference_data:<name> of the package's")
    if not path.is_file():
        raise SceneError(f"{key} = {value!r}: not found ({path}); allowed: a CSV file relative to the scene file, or "
                         f"reference_data:<name> of the package's")
    lines = [ln for ln in path.read_text(encoding="utf-8", errors="replace").splitlines()
             if ln.strip() and not ln.startswith("#")]
    rows = list(csv.reader(io.StringIO("\n".join(lines))))
    if len(rows) < 3:
        raise SceneError(f"{key} = {value!r}: fewer than two rows of data; allowed: a header row and the measured "
                         f"rows")
    header = [h.strip() for h in rows[0]]
    ragged = next((i for i, r in enumerate(rows[1:], 2) if len(r) != len(header)), None)
    if ragged is not None:
        raise SceneError(f"{key} = {value!r}: data row {ragged} has {len(rows[ragged - 1])} values, the header "
                         f"{len(header)}; allowed: a value under every column of the header")
    try:
        data = np.array([[float(x) for x in r] for r in rows[1:]], dtype=np.float64)
    except ValueError as exc:
        raise SceneError(f"{key} = {value!r}: a value is not a number ({exc}); allowed: numbers under a header "
                         f"row") from None
    return {h: data[:, i] for i, h in enumerate(header)}


def check_judges(values, columns):
    """SceneError naming a judge whose column is not one the scene writes, or whose file lacks its column."""
    for name, keys in list_entries(values, "judge").items():
        if 0.0 < keys["to"] <= keys["from"]:
            raise SceneError(f"judge.{name}.to = {keys['to']:g}: not after judge.{name}.from = {keys['from']:g} s, so "
                             f"nothing would be judged; allowed: to > from (or 0: the run's end)")
        if "baseline_to" in keys and 0.0 < keys["baseline_to"] <= keys["baseline_from"]:
            raise SceneError(f"judge.{name}.baseline_to = {keys['baseline_to']:g}: not after judge.{name}."
                             f"baseline_from = {keys['baseline_from']:g} s; allowed: baseline_to > baseline_from "
                             f"(or 0: no baseline)")
        if keys["column"] not in columns:
            raise SceneError(f"judge.{name}.column = {keys['column']!r}: not a column this scene writes; allowed: one "
                             f"of " + ", ".join(sorted(columns)))
        if keys["kind"] == "impulse":
            for force in force_columns(keys["forces"]):
                if force not in columns:
                    raise SceneError(f"judge.{name}.forces names {force!r}: not a column this scene writes; allowed: "
                                     f"force probes' columns, one of " + ", ".join(sorted(c for c in columns if
                                                                                   c[-3:-1] == "_f")))
        if keys["kind"] == "series":
            data = read_measurement(keys["file"], f"judge.{name}.file")
            if keys["file_column"] not in data:
                raise SceneError(f"judge.{name}.file_column = {keys['file_column']!r}: not a column of "
                                 f"{keys['file']}; allowed: one of " + ", ".join(list(data)[1:]))


def centred_mean(t, y, window):
    """y averaged over [t - window/2, t + window/2] at each sample (the samples in the window, equally weighted); y
    itself for window 0."""
    if window <= 0.0:
        return y
    csum = np.concatenate([[0.0], np.cumsum(y)])
    lo = np.searchsorted(t, t - 0.5 * window, side="left")
    hi = np.searchsorted(t, t + 0.5 * window, side="right")
    return (csum[hi] - csum[lo]) / np.maximum(hi - lo, 1)


def first_crossing(t, y, level):
    """The first time y reaches `level` (linear between samples); None if it never does."""
    above = np.flatnonzero(y >= level)
    if len(above) == 0:
        return None
    i = above[0]
    if i == 0:
        return float(t[0])
    return float(t[i - 1] + (t[i] - t[i - 1]) * (level - y[i - 1]) / (y[i] - y[i - 1]))


def _window(t, keys):
    end = keys["to"] if keys["to"] > 0.0 else float(t[-1])
    return keys["from"], end


def judge_series(series, keys):
    """A 'series' judge's measures (module docstring)."""
    t_sim = np.asarray(series["time"], dtype=np.float64)
    y_sim = keys["scale"] * np.asarray(series[keys["column"]], dtype=np.float64)
    data = read_measurement(keys["file"], "judge file")
    t_exp = list(data.values())[0]
    y_exp = data[keys["file_column"]]
    start, end = _window(t_sim, keys)
    end = min(end, float(t_sim[-1]), float(t_exp[-1]))
    y_sim_avg = centred_mean(t_sim, y_sim, keys["average"])
    y_exp_avg = centred_mean(t_exp, y_exp, keys["average"])
    use = (t_exp >= start) & (t_exp <= end)
    if use.sum() < 2:
        return {"error": None, "note": "the run does not cover the judged window"}
    te, ye = t_exp[use], y_exp_avg[use]
    diff = np.interp(te, t_sim, y_sim_avg) - ye
    rms = float(np.sqrt(np.mean(diff ** 2)))
    best = (rms, 0.0)
    for shift in np.arange(-SHIFT_RANGE, SHIFT_RANGE + 0.5 * SHIFT_STEP, SHIFT_STEP):
        inside = (te - shift >= t_sim[0]) & (te - shift <= t_sim[-1])
        if inside.sum() < 0.9 * len(te):
            continue
        d = np.interp(te[inside] - shift, t_sim, y_sim_avg) - ye[inside]
        best = min(best, (float(np.sqrt(np.mean(d ** 2))), float(shift)))
    relative = rms / float(np.ptp(ye)) if np.ptp(ye) > 0 else None
    out = {"rms": rms, "rms_relative_to_measured_range": relative,
           "best_time_shift_s": round(best[1], 4), "rms_after_time_shift": best[0],
           "from_s": start, "to_s": end, "average_window_s": keys["average"], "error": relative}
    if keys["rms_tolerance"] > 0.0:
        out["rms_tolerance"] = keys["rms_tolerance"]
        out["check_rms"] = rms <= keys["rms_tolerance"]
    if keys["threshold"] != 0.0:
        level = keys["threshold"]
        window_sim = (t_sim >= start) & (t_sim <= end)
        window_exp = (t_exp >= start) & (t_exp <= end)
        onset_sim = first_crossing(t_sim[window_sim], y_sim_avg[window_sim], level)
        onset_exp = first_crossing(t_exp[window_exp], y_exp_avg[window_exp], level)
        out.update({"threshold": level, "onset_s": onset_sim, "onset_measured_s": onset_exp,
                    "onset_difference_s": (onset_sim - onset_exp) if onset_sim is not None and onset_exp is not None
                    else None})
        if onset_exp is not None:
            from_t = onset_exp - PEAK_LEAD
            ps = y_sim_avg[(t_sim >= from_t) & (t_sim <= end)]
            pe = y_exp_avg[(t_exp >= from_t) & (t_exp <= end)]
            peak_sim = float(ps.max()) if len(ps) else None
            peak_exp = float(pe.max()) if len(pe) else None
            out.update({"peak": peak_sim, "peak_measured": peak_exp,
                        "peak_relative_error": (peak_sim / peak_exp - 1.0) if peak_sim is not None and peak_exp
                        else None})
        if keys["onset_tolerance"] > 0.0:
            out["onset_tolerance_s"] = keys["onset_tolerance"]
            out["check_onset"] = (out["onset_difference_s"] is not None
                                  and abs(out["onset_difference_s"]) <= keys["onset_tolerance"])
        if keys["peak_tolerance"] > 0.0:
            out["peak_tolerance"] = keys["peak_tolerance"]
            out["check_peak"] = (out.get("peak_relative_error") is not None
                                 and abs(out["peak_relative_error"]) <= keys["peak_tolerance"])
    return out


def judge_decay(series, keys):
    """A 'decay' judge's measures: the period (as a frequency judge measures it) and the fraction of the amplitude
    lost per period, with their uncertainties; the error is the loss less `reference`."""
    t = np.asarray(series["time"], dtype=np.float64)
    y = np.asarray(series[keys["column"]], dtype=np.float64)
    start, end = _window(t, keys)
    use = (t >= start) & (t <= end)
    est = measure_frequency(t[use], y[use]) if use.sum() > 2 else None
    decay = amplitude_loss_per_period(t[use], y[use], est.frequency) if est is not None else None
    ref = keys["reference"]
    if decay is None or not math.isfinite(decay.loss_per_period):
        return {"measured": None, "reference": ref, "error_signed": None, "error": None, "from_s": start,
                "to_s": end, "note": "not measured: fewer than three half-cycles in the window"}
    signed = decay.loss_per_period - ref
    out = {"measured": decay.loss_per_period, "reference": ref, "error_signed": signed, "error": abs(signed),
           "loss_uncertainty": decay.uncertainty, "period_s": 1.0 / est.frequency,
           "period_uncertainty_s": est.uncertainty / est.frequency ** 2, "amplitudes": decay.amplitudes,
           "first_amplitude": decay.first_amplitude, "last_amplitude": decay.last_amplitude, "from_s": start,
           "to_s": end}
    if keys["tolerance"] > 0.0:
        out["tolerance"] = keys["tolerance"]
        out["check_error"] = abs(signed) <= keys["tolerance"]
    return out


def force_columns(text):
    """The column names of an impulse judge's `forces` (comma-separated)."""
    return [c.strip() for c in text.split(",") if c.strip()]


def judge_impulse(series, keys):
    """An 'impulse' judge's measures (module docstring): the water's change of momentum and the forces' impulse at
    the window's end, and the largest imbalance between them over the window, against the largest impulse."""
    t = np.asarray(series["time"], dtype=np.float64)
    start, end = _window(t, keys)
    use = (t >= start) & (t <= end)
    momentum = np.asarray(series[keys["column"]], dtype=np.float64)[use]
    force = sum(np.asarray(series[c], dtype=np.float64) for c in force_columns(keys["forces"]))[use]
    times = t[use]
    if len(times) < 2:
        return {"measured": None, "reference": None, "error_signed": None, "error": None, "from_s": start,
                "to_s": end, "note": "not measured: fewer than two samples in the window"}
    # the sample at t_i is the force's mean over (t_i-1, t_i]: the window's first sample closes an interval before it
    impulse = np.concatenate([[0.0], np.cumsum(force[1:] * np.diff(times))])
    gained = momentum - momentum[0]
    imbalance = gained + impulse
    largest = float(np.abs(impulse).max())
    worst = int(np.argmax(np.abs(imbalance)))
    error = float(abs(imbalance[worst])) / largest if largest > 0.0 else None
    out = {"measured": float(gained[-1]), "reference": float(-impulse[-1]), "error_signed": error, "error": error,
           "largest_impulse": largest, "largest_imbalance": float(imbalance[worst]),
           "largest_imbalance_at_s": float(times[worst]), "samples": int(len(times)), "from_s": start, "to_s": end}
    if keys["tolerance"] > 0.0:
        out["tolerance"] = keys["tolerance"]
        out["check_error"] = error is not None and error <= keys["tolerance"]
    return out


def judge_scalar(series, keys):
    """A 'frequency', 'mean' or 'swing' judge's measures."""
    t = np.asarray(series["time"], dtype=np.float64)
    y = np.asarray(series[keys["column"]], dtype=np.float64)
    start, end = _window(t, keys)
    use = (t >= start) & (t <= end)
    extra = {}
    if keys["baseline_to"] > 0.0:
        before = (t >= keys["baseline_from"]) & (t <= keys["baseline_to"])
        baseline = float(np.mean(y[before])) if before.any() else float("nan")
        y = y - baseline
        extra["baseline"] = baseline
    if keys["kind"] == "frequency":
        covered = (float(t[use][-1] - t[use][0]) if use.sum() > 1 else 0.0) * keys["reference"]
        if covered < MIN_PERIODS:   # part of a swing has crossings of ripples about its own mean
            return {"measured": None, "reference": keys["reference"], "error_signed": None, "error": None,
                    "from_s": start, "to_s": end, "note": f"not measured: the record covers {covered:.2f} periods "
                                                          f"of the reference; at least {MIN_PERIODS:g} are needed"}
        est = measure_frequency(t[use], y[use])
        value = est.frequency
        extra.update({"frequency_uncertainty": est.uncertainty, "periods": est.periods, "method": est.method})
    elif keys["kind"] == "swing":
        value = float(np.std(y[use])) if use.any() else float("nan")
        extra.update({"samples": int(use.sum()), "mean": float(np.mean(y[use])) if use.any() else float("nan"),
                      "min": float(np.min(y[use])) if use.any() else float("nan"),
                      "max": float(np.max(y[use])) if use.any() else float("nan")})
    else:
        value = float(np.mean(y[use])) if use.any() else float("nan")
        extra["samples"] = int(use.sum())
    ref = keys["reference"]
    if keys["kind"] == "swing":   # a spread against a scale: the error is the spread's fraction of it
        error = value / abs(ref) if math.isfinite(value) and ref != 0.0 else None
        signed = error
    else:
        error = abs(value - ref) / abs(ref) if math.isfinite(value) and ref != 0.0 else None
        signed = (value - ref) / ref if error is not None else None
    out = {"measured": value, "reference": ref, "error_signed": signed, "error": error, "from_s": start, "to_s": end,
           **extra}
    if keys["tolerance"] > 0.0:
        out["tolerance"] = keys["tolerance"]
        out["check_error"] = error is not None and error <= keys["tolerance"]
    return out


def evaluate_judges(series, values):
    """{'judges': {name: measures}, the checks as check_<judge>_<what>, 'error' and 'error_metric' of the first}."""
    judges = {}
    checks = {}
    for name, keys in list_entries(values, "judge").items():
        judge = {"series": judge_series, "decay": judge_decay, "impulse": judge_impulse}.get(keys["kind"],
                                                                                            judge_scalar)
        result = judge(series, keys)
        result = {"kind": keys["kind"], "column": keys["column"], "source": keys["source"], **result}
        judges[name] = result
        checks.update({f"check_{name}_{k[len('check_'):]}": v for k, v in result.items() if k.startswith("check_")})
    out = {"judges": judges, **checks}
    if judges:
        first, result = next(iter(judges.items()))
        what = {"frequency": "relative error of the frequency", "mean": "relative error of the mean",
                "series": "RMS difference from the measured series over its range",
                "swing": "standard deviation over the reference",
                "decay": "loss per period (a fraction of the amplitude, less the reference)",
                "impulse": "largest imbalance of momentum and impulse over the largest impulse"}[result["kind"]]
        out["error"] = result.get("error")
        out["error_metric"] = f"{what} of {result['column']} (judge '{first}'" + (
            f", {result['source']})" if result["source"] else ")")
    return out
