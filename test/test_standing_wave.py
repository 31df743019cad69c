"""The standing wave (config/standing_wave.yaml): linear theory's velocity field a water part starts with
(answers/linear_waves.py), the judge of the amplitude lost per period (answers/judges.py, kind `decay`) on an
analytic damped sine, and the keys refused by name."""
import math

import numpy as np
import pytest

from sph_fsi_core.answers.judges import evaluate_judges
from sph_fsi_core.answers.linear_waves import StandingWave, dispersion_omega, standing_wave_period
from sph_fsi_core.scene import SceneError, load_scene
from sph_fsi_core.scenes import build_scene
from sph_fsi_core.simulation import Simulation

# 20 through a depth of 0.1 m, k d = 1 (config/standing_wave.yaml's defaults)
WAVE = StandingWave(amplitude=0.005, wavelength=0.63, depth=0.1, floor=0.0, antinode=0.0, gravity=9.81)


# ---- the judge of the amplitude lost per period --------------------------------------------------------------

def _judged(y, t, kind, **keys):
    values = {"judge.j.kind": kind, "judge.j.column": "eta", "judge.j.source": "", "judge.j.from": 0.0,
              "judge.j.to": 0.0, "judge.j.when": True, "judge.j.reference": keys.pop("reference", 0.0),
              "judge.j.tolerance": keys.pop("tolerance", 0.0), "judge.j.baseline_from": 0.0,
              "judge.j.baseline_to": 0.0}
    return evaluate_judges({"time": t, "eta": y}, values)


@pytest.mark.parametrize("loss", [0.0, 0.004, 0.02, 0.08, -0.01])
def test_the_decay_judge_recovers_the_period_and_the_loss_of_a_damped_sine(loss):
    """eta = a (1 - loss)^(t / T) sin(2 pi t / T) on a level 0.1 m up, with a second harmonic of 5 % (a finite
    wave's crest-trough asymmetry) and sampled every 5 ms over five periods, as the scene's probe is: the loss per
    period to 2e-4 (a fiftieth of the 1 % goal), the period to 1e-4, whatever the level and the harmonic."""
    period = standing_wave_period(0.63, 0.1, 9.81)
    t = np.arange(0.0, 5.0 * period, 0.005)
    envelope = 0.005 * (1.0 - loss) ** (t / period)
    y = 0.1 + envelope * np.sin(2 * np.pi * t / period) + 0.05 * envelope * np.cos(4 * np.pi * t / period)
    out = _judged(y, t, "decay", tolerance=0.015)
    j = out["judges"]["j"]
    assert j["measured"] == pytest.approx(loss, abs=2e-4)
    assert j["error"] == pytest.approx(abs(loss), abs=2e-4) and j["error_signed"] == pytest.approx(loss, abs=2e-4)
    assert j["period_s"] == pytest.approx(period, rel=1e-4)
    assert j["amplitudes"] >= 8 and j["first_amplitude"] == pytest.approx(0.005, rel=0.1)
    assert out["check_j_error"] is (abs(loss) <= 0.015)
    assert out["error_metric"].startswith("loss per period")
    frequency = _judged(y, t, "frequency", reference=1.0 / period)["judges"]["j"]
    assert frequency["error"] < 1e-4


def test_the_decay_judge_says_so_when_the_record_holds_too_few_half_cycles():
    t = np.arange(0.0, 0.5, 0.005)
    j = _judged(np.sin(2 * np.pi * t / 0.73), t, "decay")["judges"]["j"]
    assert j["error"] is None and "not measured" in j["note"]


# ---- the initial velocity field ------------------------------------------------------------------------------

def test_the_standing_waves_field_is_divergence_free_and_lifts_the_surface_as_linear_theory_says():
    """grad phi of eta = a cos(k x) sin(omega t) at t = 0: its divergence by central differences is below 1e-5 of
    a omega k (the differences' own error at a step of 1e-4 m), the floor is not crossed, and at the still surface
    w = d eta / dt = a omega cos(k x) and u = -a omega sin(k x) coth(k d)."""
    rng = np.random.default_rng(3)
    pts = np.column_stack([rng.uniform(-0.2, 0.8, 200), rng.uniform(0.0, 0.03, 200), rng.uniform(0.0, 0.1, 200)])
    step = 1e-4
    div = np.zeros(len(pts))
    for axis in (0, 2):
        shift = np.zeros(3)
        shift[axis] = step
        div += (WAVE.velocity(pts + shift)[:, axis] - WAVE.velocity(pts - shift)[:, axis]) / (2 * step)
    omega, k = WAVE.omega, WAVE.wavenumber
    assert omega == pytest.approx(math.sqrt(9.81 * k * math.tanh(k * 0.1)), rel=1e-15)
    assert np.abs(div).max() < 1e-5 * 0.005 * omega * k
    x = np.linspace(-0.2, 0.8, 51)
    surface = WAVE.velocity(np.column_stack([x, np.full_like(x, 0.01), np.full_like(x, 0.1)]))
    np.testing.assert_allclose(surface[:, 2], 0.005 * omega * np.cos(k * x), rtol=0, atol=1e-15)
    np.testing.assert_allclose(surface[:, 0], -0.005 * omega * np.sin(k * x) / math.tanh(k * 0.1), rtol=0,
                               atol=1e-15)
    assert np.all(surface[:, 1] == 0.0)
    floor = WAVE.velocity(np.column_stack([x, np.zeros_like(x), np.zeros_like(x)]))
    assert np.all(floor[:, 2] == 0.0)
    assert dispersion_omega(k, 0.1, 9.81) * standing_wave_period(0.63, 0.1, 9.81) == pytest.approx(2 * math.pi)


def test_the_scene_builds_its_water_with_the_wave_over_its_own_floor_and_depth():
    """config/standing_wave.yaml at its 20 through: one wavelength of 126 spacings (k d = 0.997), the wave over the
    part's floor (z = 0) and its whole layers (0.1 m), its antinode at x = 0, and no warning."""
    spec = load_scene("standing_wave")
    built, _ = build_scene(spec.builder, spec.values)
    (rows, wave), = built.fluid_start
    assert len(rows) == built.fluid.count == 126 * 20 * 6 and built.warnings == []
    assert (wave.amplitude, wave.wavelength, wave.depth, wave.floor, wave.antinode) == pytest.approx(
        (0.005, 0.63, 0.1, 0.0, 0.0))
    assert 1.0 / spec["judge.period.reference"] == pytest.approx(standing_wave_period(0.63, 0.1, 9.81), rel=1e-12)
    assert np.all(built.fluid.vel == 0.0)       # laid on at t = 0, once the water has settled


def test_a_run_starts_the_wave_on_the_settled_water():
    """A closed tank half a wavelength long, walls at both antinodes (x = 0 and L / 2), settled for 10 ms: at t = 0
    every water particle moves as linear theory's field says at the position where it settled, and nowhere else
    (settling ends at rest)."""
    spec = load_scene("standing_wave", ["numerics.spacing=0.01", "geometry.period=[0, 0.06, 0]",
                                        "geometry.lattice_origin=[0, 0, 0]", "geometry.domain_lo=[-0.05, 0, -0.05]",
                                        "geometry.domain_hi=[0.37, 0.06, 0.2]",
                                        "parts.tank.size=[0.32, 0.06, 0.2]", "parts.tank.position=[0.16, 0.03, 0.1]",
                                        "parts.water.size=[0.32, 0.06, 0.1]", "parts.water.position=[0.16, 0.03, 0.05]",
                                        "parts.water.standing_wave_length=0.64", "probes.antinode_0.position=[0.01, 0.03, 0]",
                                        "probes.antinode_half.position=[0.31, 0.03, 0]", "fluid.settle_time=0.01"])
    sim = Simulation(spec)
    assert sim.warnings == []
    (_, wave), = build_scene(spec.builder, spec.values)[0].fluid_start
    np.testing.assert_array_equal(sim.fluid.vel, wave.velocity(sim.fluid.pos))
    assert np.abs(sim.fluid.vel[:, 2]).max() > 0.5 * 0.005 * wave.omega


# ---- keys refused by name ------------------------------------------------------------------------------------

@pytest.mark.parametrize("override, words", [
    ("parts.water.standing_wave_amplitude=-0.001", ["parts.water.standing_wave_amplitude", "out of range",
                                                     "allowed: in [0, 1000] m"]),
    ("parts.water.standing_wave_length=0", ["parts.water.standing_wave_length = 0", "needs its length", "allowed"]),
    ("parts.water.standing_wave_amplitude=0.1", ["parts.water.standing_wave_amplitude = 0.1", "not below the "
                                                 "water's depth 0.1 m", "allowed"]),
    ("scene.gravity=[1, 0, -9.81]", ["parts.water.standing_wave_amplitude", "not straight down", "allowed"]),
    ("parts.water.standing_wave_amplitud=0.001", ["parts.water.standing_wave_amplitud", "standing_wave_amplitude"]),
    ("judge.loss.reference=1", ["judge.loss.reference", "out of range", "allowed"]),
    ("judge.loss.kind=decai", ["judge.loss.kind", "'decay'", "allowed"]),
])
def test_bad_standing_wave_keys_are_refused_by_name(override, words):
    with pytest.raises(SceneError) as info:
        spec = load_scene("standing_wave", [override])
        build_scene(spec.builder, spec.values)
    for word in words:
        assert word in str(info.value), (word, str(info.value))


def test_a_wave_that_is_no_mode_of_its_water_is_warned_about():
    spec = load_scene("standing_wave", ["parts.water.standing_wave_length=0.5"])
    built, _ = build_scene(spec.builder, spec.values)
    assert len(built.warnings) == 1 and "parts.water.standing_wave_length = 0.5 m" in built.warnings[0]
    assert "not a whole number of wavelengths" in built.warnings[0]


def test_the_reports_cells_give_the_loss_and_the_period():
    """A decay judge's row: the loss a period and the period it measured, against the loss expected, the error
    signed (a growing wave's negative); a frequency judge's: the frequency and its period."""
    from sph_fsi_core.validation.report import measured_against
    decay = {"kind": "decay", "column": "antinode_0", "measured": 0.504, "reference": 0.0, "error": 0.504,
             "error_signed": 0.504, "period_s": 0.6079}
    frequency = {"kind": "frequency", "column": "antinode_0", "measured": 1.645, "reference": 1.373, "error": 0.198,
                 "error_signed": 0.198}
    summary = {"judges": {"period": frequency, "loss": decay}}
    assert measured_against(summary, "loss") == ("antinode_0 loses 50.40 % a period (0.6079 s)", "0.00 % a period",
                                                 "+50.40 %")
    assert measured_against(summary, "period") == ("antinode_0 1.645 Hz (period 0.6079 s)", "1.373 Hz (0.7283 s)",
                                                   "+19.80 %")
