"""The `impulse` judge (answers/judges.py) and the scene it judges, config/box_moved_through_water.yaml (issue 59's
third exact case): the water's change of momentum against minus the impulse of its force on the walls it touches.

The judge on made-up series with an exact answer: forces sampled as the means over the intervals they close, so the
impulse is their sum times the intervals, and a momentum that is exactly minus that balances to round-off; a known
leak shows as the imbalance it is. The scene at its default spacing: within its own 6 % at every 5 ms sample
(measured 2.37 %), with the box's and the floor's impulses both substantial."""
import numpy as np
import pytest

from sph_fsi_core.answers.judges import evaluate_judges
from sph_fsi_core.run import run_scene
from sph_fsi_core.scene import SceneError, load_scene

SCENE = "config/box_moved_through_water.yaml"


def _values(**keys):
    base = {"judge.j.kind": "impulse", "judge.j.column": "fluid_momentum_x", "judge.j.source": "",
            "judge.j.from": 0.0, "judge.j.to": 0.0, "judge.j.when": True, "judge.j.forces": "box_fx, floor_fx",
            "judge.j.tolerance": 0.05}
    return {**base, **{f"judge.j.{k}": v for k, v in keys.items()}}


def _series(leak=0.0):
    """Two walls' forces over 1 s in 5 ms samples; the water's momentum minus their impulse, plus `leak` t."""
    t = np.linspace(0.0, 1.0, 201)
    box = np.where((t > 0.1) & (t <= 0.4), 2.0, 0.0)       # N, each the mean over (t - 5 ms, t]
    floor = -0.5 * np.sin(np.pi * t)
    impulse = np.concatenate([[0.0], np.cumsum((box + floor)[1:] * np.diff(t))])
    return {"time": t, "box_fx": box, "floor_fx": floor, "fluid_momentum_x": 3.0 - impulse + leak * t}


def test_a_momentum_that_is_minus_the_walls_impulse_balances_to_round_off():
    out = evaluate_judges(_series(), _values())
    j = out["judges"]["j"]
    # the walls' impulse, box 2 N over 0.3 s and floor -0.5 * 2 / pi (the sine's samples summed: its trapezoid
    # rule, as it is 0 at both ends), and the water gains minus it
    assert j["reference"] == pytest.approx(-(0.6 - 1.0 / np.pi), rel=1e-4)
    assert j["measured"] == pytest.approx(j["reference"], abs=1e-12)
    assert j["error"] < 1e-12 and out["check_j_error"] is True


def test_a_leak_shows_as_its_share_of_the_largest_impulse():
    j = evaluate_judges(_series(leak=0.02), _values())["judges"]["j"]
    largest = j["largest_impulse"]
    assert j["largest_imbalance"] == pytest.approx(0.02, abs=1e-12)          # at the end, t = 1 s
    assert j["largest_imbalance_at_s"] == pytest.approx(1.0)
    assert j["error"] == pytest.approx(0.02 / largest, rel=1e-12)
    assert (j["error"] <= 0.05) == j["check_error"]
    # judged from 0.5 s on: the momentum's and the impulse's changes since then, the leak's 0.01 over the window
    j = evaluate_judges(_series(leak=0.02), _values(**{"from": 0.5}))["judges"]["j"]
    assert j["largest_imbalance"] == pytest.approx(0.01, abs=1e-12)


def test_an_impulse_judge_naming_a_column_the_scene_does_not_write_is_refused_by_name():
    with pytest.raises(SceneError, match=r"judge.impulse.forces names 'wall_force_fx': not a column this scene "
                                         r"writes; allowed: force probes' columns, one of box_force_fx, "):
        load_scene(SCENE, ["judge.impulse.forces=box_force_fx, wall_force_fx"])


def test_the_box_moved_through_water_gives_the_water_the_walls_impulse(tmp_path):
    summary = run_scene(load_scene(SCENE), out_dir=tmp_path)
    j = summary["judges"]["impulse"]
    assert summary["stable"] and j["samples"] == 121
    assert j["error"] < 0.06 and summary["check_impulse_error"] is True
    series = np.genfromtxt(tmp_path / "timeseries.csv", delimiter=",", names=True)
    t = series["time"]
    box = np.concatenate([[0.0], np.cumsum(series["box_force_fx"][1:] * np.diff(t))])
    floor = np.concatenate([[0.0], np.cumsum(series["floor_force_fx"][1:] * np.diff(t))])
    # the box pushed the water (0.2 m/s for 0.25 s) and the floor held some of it back
    assert -box.min() > 0.05 and floor.max() > 0.2 * -box.min()
    assert j["largest_impulse"] == pytest.approx(np.abs(box + floor).max())
