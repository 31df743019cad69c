"""Antoci's gate's summary metrics on synthetic free-end curves with exact answers (no simulation)."""
import numpy as np
import pytest

from sph_fsi_core.scene import load_scene
from sph_fsi_core.scenes.antoci_gate import PEAK_SMOOTHING_S, evaluate, window_mean


def test_window_mean_keeps_a_line_and_removes_a_wobble_of_the_windows_period():
    """Samples every 2 ms, a 10 ms window: five samples a whole period apart, so a sine of that period sums to zero
    and a straight line is its own mean; at the ends the window is cut and the mean shifts along the line."""
    t = np.arange(0.0, 0.2 + 1e-12, 0.002)
    line = 0.01 + 0.3 * t
    wobble = 0.002 * np.sin(2.0 * np.pi * t / 0.010 + 0.3)
    mean = window_mean(t, line + wobble, 0.010)
    inside = (t >= 0.004 + 1e-12) & (t <= t[-1] - 0.004 - 1e-12)
    np.testing.assert_allclose(mean[inside], line[inside], rtol=0, atol=1e-14)
    assert mean[0] == pytest.approx(np.mean((line + wobble)[:3]), abs=1e-15)   # t = 0, 2, 4 ms


def test_the_smoothed_peak_is_the_motions_peak_without_its_ringing():
    """A broad bump (46 mm at 0.15 s) with a 1.5 mm, 10 ms ringing: the raw peak carries the ringing, the smoothed
    one is the bump's within its curvature over the window (a parabola's window mean lies below its top by
    c w^2 / 12 for the samples' variance 8e-6 s^2 here)."""
    t = np.arange(0.0, 0.4 + 1e-12, 0.002)
    curvature = 4.0                                           # m/s^2: 1.8 mm below the top 30 ms away
    bump = 0.046 - 0.5 * curvature * (t - 0.15) ** 2
    ring = 0.0015 * np.sin(2.0 * np.pi * t / PEAK_SMOOTHING_S)
    series = {"time": t, "tip_dx": bump + ring, "tip_dz": np.zeros_like(t)}
    out = evaluate(series, load_scene("antoci_gate").values)
    assert out["tip_x_peak_m"] == pytest.approx(0.046 + 0.0015, abs=1e-4)
    variance = np.mean((np.arange(-2, 3) * 0.002) ** 2)      # the five samples' spread about their centre
    assert out["tip_x_peak_smoothed_m"] == pytest.approx(0.046 - 0.5 * curvature * variance, abs=1e-12)
    assert out["tip_x_peak_smoothed_time_s"] == pytest.approx(0.15, abs=1e-9)


def test_the_load_against_the_level_behind_the_gate():
    """A column that loses 30 % of its water: the level is 0.7 H0 over the reservoir; the hydrostatic load of a level
    above the gate's free length is rho g W L (H - c - L / 2) (c: the clearance under it); a push of 0.8 of it
    reads 0.8."""
    from sph_fsi_core.scenes import gate
    values = load_scene("antoci_gate").values
    geometry = gate.effective_geometry(values)
    length, width, clearance = geometry["gate_free_length_m"], geometry["span_m"], geometry["gate_clearance_m"]
    level = 0.7 * gate.water_surface_z(values)
    assert level > clearance + length                        # 98 mm above a gate reaching 81.5 mm
    exact = 1000.0 * 9.81 * width * length * (level - clearance - 0.5 * length)
    assert gate.hydrostatic_gate_load(level, values) == pytest.approx(exact, rel=1e-12)
    assert gate.hydrostatic_gate_load(0.5 * clearance, values) == 0.0   # below the gate: no load on it
    t = np.arange(0.0, 0.4 + 1e-12, 0.002)
    push = 1.0 if values["geometry.mirror"] else -1.0
    series = {"time": t, "tip_dx": 0.04 - (t - 0.12) ** 2, "tip_dz": np.zeros_like(t),
              "water_past_gate": np.full_like(t, 0.3), "coupling_force_x": np.full_like(t, 0.8 * push * exact)}
    out = evaluate(series, values)
    assert out["water_level_at_x_peak_m"] == pytest.approx(level, rel=1e-12)
    assert out["water_load_over_hydrostatic_at_x_peak"] == pytest.approx(0.8, rel=1e-12)
