"""Coarse validation of Lobovsky et al. 2014's dam break in CI, through `sph-fsi validate --quick`: H / dp = 30
(20 mm), both releases, to T = 1.62. About 10 s on one thread.

Measured at this rung (docs/validation/lobovsky/REPORT.md has the ladder): the gate gone at t = 0, RMS of Z over
T >= 1 2.4 %, the front ahead by dT = 0.03, speed dZ/dT +12 % against the experiment's 1.339; the gate lifted at
4.53 m/s, RMS 3.9 %, ahead by dT = 0.06, speed +6.5 %. Bounds: RMS <= 5 % (the issue's goal), after the best shift
<= 2 %, speed within 15 % (instant) and 8 % (lifted), the lead positive and below 0.1, no particle through a wall.
"""
import json

import pytest

from sph_fsi_core.validation.ladder import main as validate

pytestmark = pytest.mark.slow


def test_quick_lobovsky_rungs_within_bounds(tmp_path):
    assert validate(["lobovsky_dam_break"], quick=True, workers=1, out_dir=tmp_path) == 0
    for release, speed_bound in (("instant", 0.15), ("lifted", 0.08)):
        s = json.loads((tmp_path / "runs" / "lobovsky_dam_break" / f"{release}_H_over_dp_30" /
                        "summary.json").read_text())
        assert s["stable"] and s["fluid_capped_steps"] == 0 and s["max_particles_outside_walls"] == 0
        assert s["front_rms_relative_error"] <= 0.05
        assert s["front_rms_after_time_shift"] <= 0.02
        assert 0.0 < s["front_time_shift_T"] < 0.1
        assert abs(s["front_speed_error"]) < speed_bound
        assert s["front_speed_dZdT_experiment"] == pytest.approx(1.339, abs=0.001)
    assert "lobovsky_front.png" in (tmp_path / "REPORT.md").read_text()
