"""Coarse validation of Lobovsky et al. 2014's dam break in CI, through `sph-fsi validate --quick`: H / dp = 30
(20 mm), both releases, each from zero pressure and settled behind its gate, to T = 1.62, and the experiment's
procedure with a quarter of the fluid's step. About 30 s on one thread.

Measured at this rung (docs/validation/studies/lobovsky/REPORT.md has the ladder), RMS of Z over T >= 1 / best delay
dT / speed dZ/dT against the experiment's 1.339:
- the gate gone at t = 0: 2.4 % / 0.032 / +12 % from zero pressure, 2.6 % / 0.036 / +12 % settled;
- the gate lifted at 4.53 m/s: 3.9 % / 0.064 / +6.5 % from zero pressure, 0.53 % / -0.002 / +4.3 % settled (the
  experiment's procedure: the issue's goals, RMS <= 5 % and |dT| <= 0.06, are met; the speed's 3 % is not).
Bounds: RMS <= 5 % (the issue's goal) for all four, and for the experiment's procedure RMS <= 2.5 %, |dT| <= 0.06
and speed within 6 %; after the best shift <= 2 %; no particle through a wall.

The experiment's procedure again with a quarter of the fluid's step (fluid.cfl 0.05): measured 0.37 % / 0.000 /
+2.7 % (2026-12-05). Bounds: the speed at least a point closer to the experiment's than at the scene's step, and
within 3.5 % of it (docs/validation/OPEN.md, 3.1: about a point of the excess is the step's).
"""
import json

import pytest

from sph_fsi_core.validation.ladder import main as validate

pytestmark = pytest.mark.slow


def _summary(out, label):
    return json.loads((out / "runs" / "lobovsky_dam_break" / label / "summary.json").read_text())


def test_quick_lobovsky_rungs_within_bounds(tmp_path):
    assert validate(["lobovsky_dam_break"], quick=True, workers=1, out_dir=tmp_path) == 0
    for label, speed_bound in (("instant", 0.15), ("lifted", 0.08), ("instant_settled", 0.15),
                               ("lifted_settled", 0.06)):
        s = _summary(tmp_path, f"{label}_H_over_dp_30")
        assert s["stable"] and s["fluid_capped_steps"] == 0 and s["max_particles_outside_walls"] == 0
        assert s["front_rms_relative_error"] <= 0.05
        assert s["front_rms_after_time_shift"] <= 0.02
        assert abs(s["front_time_shift_T"]) < 0.1
        assert abs(s["front_speed_error"]) < speed_bound
        assert s["front_speed_dZdT_experiment"] == pytest.approx(1.339, abs=0.001)
        assert ("settling" in s) == label.endswith("settled")
    procedure = _summary(tmp_path, "lifted_settled_H_over_dp_30")
    assert procedure["front_rms_relative_error"] <= 0.025 and abs(procedure["front_time_shift_T"]) <= 0.06
    finer_step = _summary(tmp_path, "lifted_settled_cfl0.05_H_over_dp_30")
    assert finer_step["stable"] and finer_step["max_particles_outside_walls"] == 0
    assert finer_step["front_rms_relative_error"] <= 0.025 and abs(finer_step["front_time_shift_T"]) <= 0.06
    assert 0.0 < finer_step["front_speed_error"] < min(0.035, procedure["front_speed_error"] - 0.01)
    assert "lobovsky_front.png" in (tmp_path / "REPORT.md").read_text()
