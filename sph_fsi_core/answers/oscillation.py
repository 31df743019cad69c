"""Frequency, damping and period averages of a sampled oscillation (pure NumPy).

Meant for signals such as the free-end deflection of a vibrating cantilever: one dominant mode, sampled at a
uniform or nearly uniform interval, possibly with an offset, slow decay or growth, and some noise.

Zero crossings are found with hysteresis (the signal has to leave a band of a few noise standard deviations
around its mean before the next crossing counts), so noise near the mean cannot produce spurious crossings.
Functions never raise on short, constant or non-finite input: they return nan instead.
"""
import math
from dataclasses import dataclass

import numpy as np

# A crossing needs the signal to leave +-(this many noise sigmas) on both sides.
_HYSTERESIS_SIGMAS = 4.0
_ZERO_PAD_FACTOR = 8
# Relative non-uniformity of the time step above which the FFT works on a resampled uniform grid.
_UNIFORM_TOLERANCE = 1e-6
# Below this many cycles per record the FFT peak gives way to a direct sinusoid fit.
_SHORT_RECORD_CYCLES = 3.0


@dataclass(frozen=True)
class FrequencyEstimate:
    frequency: float  # Hz
    uncertainty: float  # Hz, one standard error (or half-spread between methods if they disagree)
    periods: float  # number of full periods the signal covered
    method: str  # 'zero_crossings', 'spectral_peak', 'none', or 'zero_crossings (spectral disagrees: X Hz)'
    zero_crossing_frequency: float  # nan if fewer than 3 crossings
    spectral_frequency: float  # nan if undetermined


def _clean(t, y, skip_time=0.0):
    """Finite samples with t >= skip_time, sorted by time, as float arrays."""
    t = np.asarray(t, dtype=float).ravel()
    y = np.asarray(y, dtype=float).ravel()
    n = min(t.size, y.size)
    t, y = t[:n], y[:n]
    keep = np.isfinite(t) & np.isfinite(y) & (t >= skip_time)
    t, y = t[keep], y[keep]
    if t.size > 1 and np.any(np.diff(t) <= 0.0):
        order = np.argsort(t, kind="stable")
        t, y = t[order], y[order]
        # Repeated time stamps would make interpolation divide by zero.
        first = np.concatenate(([True], np.diff(t) > 0.0))
        t, y = t[first], y[first]
    return t, y


def _is_flat(y):
    if y.size < 3:
        return True
    scale = float(np.max(np.abs(y)))
    return float(np.ptp(y)) <= 1e-12 * scale or scale == 0.0


def _noise_sigma(t, y):
    """Noise standard deviation from each sample's deviation from its neighbours' linear interpolation.

    A smooth signal well resolved in time leaves only a tiny curvature residual, so the robust spread of these
    residuals measures the noise; for white noise var(residual) = sigma^2 (1 + a^2 + b^2) with a + b = 1.
    """
    if y.size < 3:
        return 0.0
    a = (t[2:] - t[1:-1]) / (t[2:] - t[:-2])
    b = 1.0 - a
    r = y[1:-1] - (a * y[:-2] + b * y[2:])
    mad = float(np.median(np.abs(r - np.median(r))))
    gain = float(np.sqrt(np.median(1.0 + a * a + b * b)))
    return 1.4826 * mad / gain


def _zero_crossings(t, y):
    """Times of alternating-sign zero crossings of `y` (already centred), and the sign of the side each
    crossing leaves (+1: downward crossing).

    Between the last sample above +h and the first below -h (or vice versa) there is one crossing: with a
    single sign change there it is the linear interpolation between the two bracketing samples, with several
    (noise) it is the root of a straight line fitted through the whole bracket.
    """
    if y.size < 2:
        return np.empty(0), np.empty(0)
    scale = float(np.max(np.abs(y)))
    h = max(_HYSTERESIS_SIGMAS * _noise_sigma(t, y), 1e-9 * scale)
    side = np.where(y > h, 1, np.where(y < -h, -1, 0))
    armed = np.flatnonzero(side)
    if armed.size < 2:
        return np.empty(0), np.empty(0)
    change = np.flatnonzero(side[armed[1:]] != side[armed[:-1]])
    times = np.empty(change.size)
    signs = np.empty(change.size)
    for m, c in enumerate(change):
        i, j = armed[c], armed[c + 1]
        ts, ys = t[i:j + 1], y[i:j + 1]
        positive = ys > 0.0
        flips = np.flatnonzero(positive[1:] != positive[:-1])
        if flips.size == 1:
            k = flips[0]
            times[m] = ts[k] + (ts[k + 1] - ts[k]) * ys[k] / (ys[k] - ys[k + 1])
        else:
            slope, intercept = np.polyfit(ts - ts[0], ys, 1)
            root = -intercept / slope if slope != 0.0 else 0.5 * (ts[-1] - ts[0])
            times[m] = ts[0] + min(max(root, 0.0), ts[-1] - ts[0])
        signs[m] = side[i]
    return times, signs


def _crossing_indices(times):
    """Half-period index of each crossing; a gap of several half periods (a missed pair) advances it by more."""
    gaps = np.diff(times)
    half = float(np.median(gaps))
    steps = np.maximum(1, np.rint(gaps / half)).astype(np.int64)
    return np.concatenate(([0], np.cumsum(steps)))


def _line_fit(x, y):
    """Least-squares y = c + s x: (s, standard error of s, c). The error is nan without residual freedom."""
    xm, ym = float(np.mean(x)), float(np.mean(y))
    sxx = float(np.sum((x - xm) ** 2))
    s = float(np.sum((x - xm) * (y - ym))) / sxx
    c = ym - s * xm
    dof = x.size - 2
    if dof < 1:
        return s, math.nan, c
    resid = y - (c + s * x)
    return s, math.sqrt(float(np.sum(resid * resid)) / dof / sxx), c


def _zero_crossing_frequency(times):
    """(frequency, standard error) from the least-squares fit t_k = t0 + k T/2; nan below 3 crossings.

    From 4 crossings on, the fit also carries a term c (-1)^k: a small residual offset of the signal delays
    upward and advances downward crossings (or the reverse) by a constant time, which would otherwise pass for
    scatter and inflate the error without biasing T.
    """
    if times.size < 3:
        return math.nan, math.nan
    k = _crossing_indices(times).astype(float)
    if times.size < 4:
        half_period, se_half, _ = _line_fit(k, times)
    else:
        design = np.column_stack((np.ones_like(k), k - k.mean(), np.where(k % 2 == 0, 1.0, -1.0)))
        coef, _, rank, _ = np.linalg.lstsq(design, times - times[0], rcond=None)
        if rank < 3:
            half_period, se_half, _ = _line_fit(k, times)
        else:
            half_period = float(coef[1])
            dof = times.size - 3
            resid = times - times[0] - design @ coef
            if dof < 1:
                se_half = math.nan
            else:
                cov = np.linalg.inv(design.T @ design) * (float(resid @ resid) / dof)
                se_half = math.sqrt(max(float(cov[1, 1]), 0.0))
    if not half_period > 0.0:
        return math.nan, math.nan
    period = 2.0 * half_period
    return 1.0 / period, 2.0 * se_half / period**2


def _half_cycle_extremes(t, y, times):
    """Index of the largest |y| between each pair of consecutive crossing times."""
    bounds = np.searchsorted(t, times)
    return np.array([a + int(np.argmax(np.abs(y[a:b]))) for a, b in zip(bounds[:-1], bounds[1:]) if b > a],
                    dtype=np.int64)


def _centre(t, y):
    """y minus its offset, and the zero-crossing times of the result.

    The plain mean is biased by an incomplete last cycle and, for a decaying signal, by the first lobe being
    the largest; this shifts upward and downward crossings apart by a growing amount. It is therefore replaced
    by the mean over whole periods from one extreme to the last extreme of the same sign, where the bias is
    down by a factor of about zeta.
    """
    y = y - np.mean(y)
    times, _ = _zero_crossings(t, y)
    if times.size < 4:
        return y, times
    ext = _half_cycle_extremes(t, y, times)
    if ext.size < 3:
        return y, times
    i, j = int(ext[0]), int(ext[2 * ((ext.size - 1) // 2)])
    ts, ys = t[i:j + 1], y[i:j + 1]
    y = y - float(np.sum(0.5 * (ys[1:] + ys[:-1]) * np.diff(ts))) / float(ts[-1] - ts[0])
    times, _ = _zero_crossings(t, y)
    return y, times


def _sine_fit_power(t, y, freqs):
    """Fraction of the variance of y explained by a least-squares fit c0 + c1 cos(2 pi f t) + c2 sin(2 pi f t),
    for each f (a floating-mean Lomb-Scargle periodogram)."""
    tc = t - 0.5 * (t[0] + t[-1])
    phase = 2.0 * np.pi * np.asarray(freqs)[:, None] * tc[None, :]
    basis = np.stack((np.ones_like(phase), np.cos(phase), np.sin(phase)), axis=1)  # (F, 3, n)
    gram = basis @ basis.transpose(0, 2, 1)
    rhs = basis @ y
    try:
        coef = np.linalg.solve(gram, rhs[..., None])[..., 0]
    except np.linalg.LinAlgError:
        return np.zeros(len(freqs))
    sst = float(np.sum((y - np.mean(y)) ** 2))
    explained = np.einsum("fi,fi->f", coef, rhs) - y.size * float(np.mean(y)) ** 2
    return explained / sst if sst > 0.0 else np.zeros(len(freqs))


def _short_record_frequency(t, y):
    """Frequency of the best single sinusoid plus offset for a record of at most a few periods, where the
    windowed FFT peak is dragged by the mean and by the negative-frequency image; nan if none stands out."""
    duration = float(t[-1] - t[0])
    freqs = np.geomspace(0.25, 6.0, 241) / duration
    power = _sine_fit_power(t, y, freqs)
    k = int(np.argmax(power))
    if not power[k] > 0.0 or k == 0 or k == freqs.size - 1:
        return math.nan
    lo, hi = freqs[k - 1], freqs[k + 1]
    # Golden-section search on the bracketing grid cells: the peak is smooth at this scale.
    g = 0.5 * (math.sqrt(5.0) - 1.0)
    a, b = lo + (1.0 - g) * (hi - lo), lo + g * (hi - lo)
    pa, pb = _sine_fit_power(t, y, [a, b])
    for _ in range(40):
        if pa >= pb:
            hi, b, pb = b, a, pa
            a = lo + (1.0 - g) * (hi - lo)
            pa = _sine_fit_power(t, y, [a])[0]
        else:
            lo, a, pa = a, b, pb
            b = lo + g * (hi - lo)
            pb = _sine_fit_power(t, y, [b])[0]
    return 0.5 * (lo + hi)


def _spectral_frequency(t, y):
    """Frequency of the largest positive-frequency peak of the Hann-windowed, 8x zero-padded FFT, refined by a
    parabola through the log magnitudes of the peak bin and its neighbours; nan if there is no peak.

    Non-uniform samples are first interpolated linearly onto a uniform grid of the same count. When the peak
    lies below 3 cycles per record, the FFT cannot resolve it from the mean and from its own negative-frequency
    image, and the best-fitting sinusoid (floating-mean periodogram) is used instead.
    """
    n = y.size
    if n < 4:
        return math.nan
    t_raw, y_raw = t, y
    steps = np.diff(t)
    dt = (t[-1] - t[0]) / (n - 1)
    if np.max(np.abs(steps - dt)) > _UNIFORM_TOLERANCE * dt:
        grid = np.linspace(t[0], t[-1], n)
        y = np.interp(grid, t, y)
    x = (y - np.mean(y)) * np.hanning(n)
    nfft = 1 << int(math.ceil(math.log2(_ZERO_PAD_FACTOR * n)))
    mag = np.abs(np.fft.rfft(x, nfft))
    frequency = math.nan
    if mag.size >= 3 and np.any(mag[1:] > 0.0):
        inner = mag[1:-1]
        peaks = np.flatnonzero((inner > mag[:-2]) & (inner >= mag[2:])) + 1
        if peaks.size:
            k = int(peaks[np.argmax(mag[peaks])])
            tiny = np.finfo(float).tiny
            a, b, c = np.log(np.maximum(mag[k - 1:k + 2], tiny))
            denom = a - 2.0 * b + c
            p = 0.5 * (a - c) / denom if denom < 0.0 else 0.0
            frequency = (k + p) / (nfft * dt)
    if not frequency * (t[-1] - t[0]) >= _SHORT_RECORD_CYCLES:
        refined = _short_record_frequency(t_raw, y_raw)
        if math.isfinite(refined):
            frequency = refined
    return frequency


def measure_frequency(t, y, skip_time=0.0):
    """Dominant oscillation frequency of samples y(t), ignoring samples before `skip_time`.

    Assumes one dominant mode about a constant mean (the mean of the kept samples is removed). The primary
    estimate fits the zero-crossing times t_k = t0 + k T/2 by least squares (>= 4 crossings needed); its
    uncertainty is the propagated standard error of T. With fewer crossings the Hann-windowed FFT peak is used,
    with an uncertainty of half a DFT bin, 1 / (2 record length). If both estimates exist and differ by more
    than 5 combined standard errors (the spectral one taken as half a bin, since window leakage biases it far
    above the fit error of a clean signal), the zero-crossing value is kept, the uncertainty is widened to half
    the spread, and `method` names the spectral value.
    """
    t, y = _clean(t, y, skip_time)
    nan = math.nan
    if y.size < 3 or _is_flat(y):
        return FrequencyEstimate(nan, nan, nan, "none", nan, nan)
    y, times = _centre(t, y)
    duration = float(t[-1] - t[0])
    f_zc, se_zc = _zero_crossing_frequency(times)
    f_sp = _spectral_frequency(t, y)
    se_sp = 0.5 / duration

    if times.size >= 4 and math.isfinite(f_zc):
        frequency, uncertainty, method = f_zc, max(se_zc, 0.0), "zero_crossings"
        if math.isfinite(f_sp):
            spread = abs(f_sp - f_zc)
            if spread > 5.0 * math.hypot(se_zc, se_sp):
                uncertainty = max(uncertainty, 0.5 * spread)
                method = f"zero_crossings (spectral disagrees: {f_sp:.6g} Hz)"
    elif math.isfinite(f_sp):
        frequency, uncertainty, method = f_sp, se_sp, "spectral_peak"
    elif math.isfinite(f_zc):
        frequency, uncertainty, method = f_zc, max(se_zc, se_sp), "zero_crossings"
    elif times.size == 2:
        frequency, uncertainty, method = 0.5 / float(times[1] - times[0]), se_sp, "zero_crossings"
    else:
        return FrequencyEstimate(nan, nan, nan, "none", f_zc, f_sp)
    return FrequencyEstimate(frequency, uncertainty, frequency * duration, method, f_zc, f_sp)


def _peak_value(t, y, i, half_window):
    """Signed extreme value near sample i: vertex of a least-squares parabola over +-half_window (a 3-point
    parabola when that holds fewer than 5 samples), falling back to y[i] if the parabola is not a peak there."""
    lo = int(np.searchsorted(t, t[i] - half_window, side="left"))
    hi = int(np.searchsorted(t, t[i] + half_window, side="right"))
    if hi - lo < 5:
        lo, hi = max(i - 1, 0), min(i + 2, t.size)
    if hi - lo < 3:
        return float(y[i])
    x = t[lo:hi] - t[i]
    c2, c1, c0 = np.polyfit(x, y[lo:hi], 2)
    if c2 == 0.0 or np.sign(c2) == np.sign(y[i]):
        return float(y[i])
    xv = -c1 / (2.0 * c2)
    if not x[0] <= xv <= x[-1]:
        return float(y[i])
    return float(c0 - c1 * c1 / (4.0 * c2))


def damping_ratio(t, y, frequency, skip_time=0.0):
    """Damping ratio zeta of a decaying (or, with zeta < 0, growing) single-mode oscillation, with its standard
    error, for y = A exp(-zeta omega_n t) cos(omega_d t + phi) + offset.

    `frequency` is the observed (damped) frequency f_d. The extreme of each half-cycle between consecutive zero
    crossings is taken; half the difference of consecutive extremes (opposite signs) is an amplitude free of
    the offset, and a straight-line fit of its logarithm against time gives the slope -zeta omega_n. With
    omega_n = omega_d / sqrt(1 - zeta^2) this is solved exactly: r = -slope / omega_d, zeta = r / sqrt(1 + r^2),
    valid for either sign. Returns (nan, nan) with fewer than 3 half-cycles; the error is nan with exactly 3.
    """
    nan = (math.nan, math.nan)
    fit = _amplitude_decay(t, y, frequency, skip_time)
    if fit is None:
        return nan
    slope, se_slope, _, _ = fit
    omega_d = 2.0 * math.pi * frequency
    r = -slope / omega_d
    zeta = r / math.sqrt(1.0 + r * r)
    se = (se_slope / omega_d) / (1.0 + r * r) ** 1.5
    return zeta, se


def _end_extremes(t, y, times, ext):
    """The half-cycle extremes with the record's two partial half-cycles (before its first crossing, after its last)
    added where each holds an extreme of its own: |y|'s largest sample inside it, not at either of its ends, of the
    sign opposite to the next full half-cycle's. A record that starts at rest or at a crossing (a wave started at
    its flat phase) keeps its first crest, its largest."""
    bounds = np.searchsorted(t, times[[0, -1]])
    out = list(ext)
    for lo, hi, neighbour, at in ((0, bounds[0], ext[0], 0), (bounds[1], t.size, ext[-1], len(out))):
        if hi - lo < 3:
            continue
        i = lo + int(np.argmax(np.abs(y[lo:hi])))
        if lo < i < hi - 1 and np.sign(y[i]) == -np.sign(y[neighbour]):
            out.insert(at, i)
    return np.array(out, dtype=np.int64)


def _amplitude_decay(t, y, frequency, skip_time=0.0, ends=False):
    """(slope, its standard error, the half-cycle amplitudes (K,), their times (K,)) of the straight-line fit of
    log amplitude against time (1/s), the amplitudes half the differences of consecutive half-cycle extremes (free
    of the offset; with `ends`, the partial half-cycles' too: _end_extremes); None with fewer than 3 half-cycles or
    2 amplitudes."""
    if not (np.isfinite(frequency) and frequency > 0.0):
        return None
    t, y = _clean(t, y, skip_time)
    if y.size < 3 or _is_flat(y):
        return None
    y, times = _centre(t, y)
    if times.size < 4:
        return None
    ext = _half_cycle_extremes(t, y, times)
    if ends and ext.size:
        ext = _end_extremes(t, y, times, ext)
    peak_t = t[ext]
    peak_y = np.array([_peak_value(t, y, i, 0.125 / frequency) for i in ext])
    if peak_y.size < 3:
        return None
    amp = 0.5 * np.abs(np.diff(peak_y))
    mid = 0.5 * (peak_t[1:] + peak_t[:-1])
    ok = amp > 0.0
    if np.count_nonzero(ok) < 2:
        return None
    slope, se_slope, _ = _line_fit(mid[ok], np.log(amp[ok]))
    return slope, se_slope, amp[ok], mid[ok]


@dataclass(frozen=True)
class DecayEstimate:
    loss_per_period: float  # the fraction of the amplitude lost over one period, 1 - exp(slope T); < 0: growth
    uncertainty: float      # one standard error of it (nan with exactly 2 amplitudes)
    amplitudes: int         # half-cycle amplitudes fitted
    first_amplitude: float  # the first and the last of them, in the signal's unit
    last_amplitude: float


def amplitude_loss_per_period(t, y, frequency, skip_time=0.0):
    """The fraction of a single-mode oscillation's amplitude lost per period 1 / `frequency` (the observed one):
    the logarithmic decrement of damping_ratio's fit (the half-cycle extremes' amplitudes, log-linear in time,
    slope s), as 1 - exp(s / f), with its standard error; the record's partial first and last half-cycles count
    where they hold an extreme (a wave started at its flat phase peaks a quarter period in, before any crossing).
    nan with fewer than 3 half-cycles."""
    fit = _amplitude_decay(t, y, frequency, skip_time, ends=True)
    if fit is None:
        return DecayEstimate(math.nan, math.nan, 0, math.nan, math.nan)
    slope, se_slope, amp, _ = fit
    ratio = math.exp(slope / frequency)
    return DecayEstimate(1.0 - ratio, ratio * se_slope / frequency, int(amp.size), float(amp[0]), float(amp[-1]))


def _cumulative_integral_at(t, y, tau):
    """Integral of the piecewise-linear interpolant of y(t) from t[0] to each tau (t[0] <= tau <= t[-1])."""
    cum = np.concatenate(([0.0], np.cumsum(0.5 * (y[1:] + y[:-1]) * np.diff(t))))
    j = np.clip(np.searchsorted(t, tau, side="right") - 1, 0, t.size - 2)
    d = tau - t[j]
    slope = (y[j + 1] - y[j]) / (t[j + 1] - t[j])
    return cum[j] + y[j] * d + 0.5 * slope * d * d


def period_averaged(t, y, frequency):
    """Means of y over consecutive whole periods 1/frequency starting at t[0] (e.g. to see energy drift through
    the oscillation). Each mean integrates the linear interpolant of the samples (trapezoid rule, bin edges
    interpolated); incomplete trailing periods are dropped. Returns (period mid-times, means)."""
    empty = (np.empty(0), np.empty(0))
    if not (np.isfinite(frequency) and frequency > 0.0):
        return empty
    t, y = _clean(t, y, -math.inf)
    if t.size < 2:
        return empty
    period = 1.0 / frequency
    count = int(math.floor((t[-1] - t[0]) / period * (1.0 + 1e-12)))
    if count < 1:
        return empty
    edges = np.minimum(t[0] + period * np.arange(count + 1), t[-1])
    integral = _cumulative_integral_at(t, y, edges)
    return 0.5 * (edges[1:] + edges[:-1]), np.diff(integral) / period
