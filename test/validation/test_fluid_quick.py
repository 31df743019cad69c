"""Coarse validation of the fluid in CI, through `sph-fsi validate --quick`: the hydrostatic tank at dp = 5 mm
(H / dp = 20, 0.6 s) and Martin & Moyce's dam break at a / dp = 10 (to T = 3.15). About 20 s on one thread.

Hydrostatic (issue goal: floor pressure within 1 % of rho g H after settling): the line fit of p(z) extrapolated
to the floor within 2 % (measured -1.0 %), the bottom layer's pressure within 2 % of rho g (H - dp/2), the floor's
load within 1 % of the water's weight per area, no particle through a wall, mass unchanged to the last bit.

Dam break (issue goal: front RMS <= 5 %): measured 10.5 % RMS at this resolution, every point ahead of the
experiment (8-12 %). The lead is a delay at the start: shifted later by dT ~ 0.19 the simulated front fits the
experiment to 1.5 % RMS, and its speed dZ/dT over T = 1.5..3 is within 5 % of the measured one. Bounds: RMS
< 15 %, after the best shift < 3 %, speed within 10 %.
"""
import json

import pytest

from sph_fsi_core.answers.references import martin_moyce_front
from sph_fsi_core.validation.ladder import main as validate


pytestmark = pytest.mark.slow   # over ~10 s on one thread: left out of `make test-fast`


def test_quick_fluid_cases_within_bounds(tmp_path):
    # two worker processes (the rungs are independent), each with cores / workers Numba threads
    assert validate(["hydrostatic", "dam_break"], quick=True, workers=2, out_dir=tmp_path) == 0
    runs = tmp_path / "runs"
    hs = json.loads((runs / "hydrostatic" / "dp_5mm" / "summary.json").read_text())
    assert hs["machine"]["numba_threads"] == max(1, hs["machine"]["cpus"] // 2)
    assert hs["stable"] and hs["particles"]["fluid"] == 10 * 20 * 6
    assert hs["reference_floor_pressure_pa"] == 1000.0 * 9.81 * 0.1
    assert abs(hs["floor_pressure_error"]) < 0.02
    assert abs(hs["bottom_layer_error"]) < 0.02
    assert abs(hs["floor_load_error"]) < 0.01
    assert abs(hs["pressure_gradient_over_rho_g"] - 1.0) < 0.03
    assert hs["pressure_profile_rms_over_rho_g_h"] < 0.03
    assert hs["max_particles_outside_walls"] == 0
    assert hs["mass_change_kg"] == 0.0
    assert hs["fluid_capped_steps"] == 0

    db = json.loads((runs / "dam_break" / "a_over_dp_10" / "summary.json").read_text())
    assert db["stable"] and db["fluid_capped_steps"] == 0
    ref_t, ref_z = martin_moyce_front()
    points = db["front_points"]
    assert [p["T"] for p in points] == [t for t in ref_t if t <= 3.0]
    assert [p["Z_experiment"] for p in points] == [z for t, z in zip(ref_t, ref_z) if t <= 3.0]
    assert db["front_rms_relative_error"] < 0.15
    assert all(0.0 < p["relative_error"] < 0.2 for p in points)
    assert db["front_rms_after_time_shift"] < 0.03
    assert abs(db["front_speed_dZdT"] / db["front_speed_dZdT_experiment"] - 1.0) < 0.10
    assert db["max_particles_outside_walls"] == 0
    report = (tmp_path / "REPORT.md").read_text()
    assert "dam_break_front.png" in report and "hydrostatic_pressure.png" in report
