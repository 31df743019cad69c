"""Tests of sph_fsi_core.answers.oscillation on synthetic signals with known frequency and damping."""
import math

import numpy as np
import pytest

from sph_fsi_core.answers.oscillation import FrequencyEstimate, damping_ratio, measure_frequency, period_averaged

F = 17.58  # Hz
DT = 1.0 / 5000.0
DURATION = 0.6


def _time():
    return np.arange(0.0, DURATION, DT)


def _damped(t, zeta, offset=0.0, phase=0.4):
    """exp(-zeta omega_n t) cos(omega_d t + phase) + offset with f_n = F; returns (signal, f_d)."""
    f_d = F * math.sqrt(1.0 - zeta * zeta)
    y = offset + np.exp(-zeta * 2.0 * math.pi * F * t) * np.cos(2.0 * math.pi * f_d * t + phase)
    return y, f_d


def test_pure_sine():
    t = _time()
    est = measure_frequency(t, np.sin(2.0 * math.pi * F * t + 0.7))
    assert isinstance(est, FrequencyEstimate)
    assert est.method == "zero_crossings"
    assert abs(est.zero_crossing_frequency - F) < 1e-5 * F
    assert est.frequency == est.zero_crossing_frequency
    assert est.uncertainty < 1e-3
    assert abs(est.spectral_frequency - F) < 1e-3 * F
    assert est.periods == pytest.approx(F * (t[-1] - t[0]), rel=1e-6)


def test_jittered_sampling():
    rng = np.random.default_rng(12345)
    t = _time() + rng.uniform(-0.3, 0.3, _time().size) * DT
    est = measure_frequency(t, np.sin(2.0 * math.pi * F * t + 0.7))
    assert est.method == "zero_crossings"
    assert abs(est.frequency - F) < 1e-4 * F
    assert abs(est.spectral_frequency - F) < 1e-3 * F


@pytest.mark.parametrize("zeta", [0.005, 0.03])
def test_damped_sine(zeta):
    t = _time()
    y, f_d = _damped(t, zeta, offset=0.25)
    est = measure_frequency(t, y)
    assert est.method == "zero_crossings"
    assert abs(est.frequency - f_d) < 1e-4 * f_d
    z, se = damping_ratio(t, y, est.frequency)
    assert abs(z - zeta) < 0.05 * zeta
    assert 0.0 < se < 0.05 * zeta


def test_growing_sine_gives_negative_damping():
    t = _time()
    y, f_d = _damped(t, -0.01)
    est = measure_frequency(t, y)
    assert abs(est.frequency - f_d) < 1e-4 * f_d
    z, _ = damping_ratio(t, y, est.frequency)
    assert z < 0.0
    assert abs(z + 0.01) < 0.05 * 0.01


@pytest.mark.parametrize("noise", [0.01, 0.05])  # 5 %: noise chatters across the mean, hysteresis must hold
def test_offset_and_noise(noise):
    rng = np.random.default_rng(2024)
    t = _time()
    y = 3.0 + np.sin(2.0 * math.pi * F * t + 1.1) + noise * rng.standard_normal(t.size)
    est = measure_frequency(t, y)
    assert est.method.startswith("zero_crossings")
    assert abs(est.frequency - F) < 1e-3 * F
    assert est.uncertainty < 1e-3 * F


def test_skip_time_ignores_transient():
    t = _time()
    y = np.sin(2.0 * math.pi * F * t)
    y[t < 0.1] = 5.0  # a start-up transient without crossings, far off the mean
    est = measure_frequency(t, y, skip_time=0.1)
    assert abs(est.frequency - F) < 1e-5 * F


@pytest.mark.parametrize("phase", [0.0, 1.0, 2.5])
def test_short_signal_uses_spectral_peak(phase):
    t = np.arange(0.0, 0.7 / F, DT)
    est = measure_frequency(t, np.sin(2.0 * math.pi * F * t + phase))
    assert est.method == "spectral_peak"
    assert abs(est.frequency - F) < 0.2 * F
    assert est.uncertainty > 0.0


def test_constant_and_degenerate_signals():
    t = _time()
    est = measure_frequency(t, np.full(t.size, 0.1))
    assert math.isnan(est.frequency)
    assert est.method == "none"
    for tt, yy in [([], []), ([0.0], [1.0]), ([0.0, 1.0], [1.0, -1.0])]:
        est = measure_frequency(tt, yy)
        assert math.isnan(est.frequency) and est.method == "none"
    assert all(math.isnan(v) for v in damping_ratio(t, np.full(t.size, 2.0), F))


def test_damping_needs_three_half_cycles():
    t = np.arange(0.0, 1.2 / F, DT)  # two zero crossings at most
    y, _ = _damped(t, 0.01, phase=0.0)
    assert all(math.isnan(v) for v in damping_ratio(t, y, F))


def test_period_averaged_sine_squared():
    t = _time()
    mid, mean = period_averaged(t, np.sin(2.0 * math.pi * F * t + 0.3) ** 2, F)
    assert mid.size == int(DURATION * F)
    assert np.allclose(np.diff(mid), 1.0 / F)
    assert mid[0] == pytest.approx(0.5 / F)
    assert np.max(np.abs(mean - 0.5)) < 1e-3
