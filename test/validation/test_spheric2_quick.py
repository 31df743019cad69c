"""SPHERIC test 2 (config/spheric2_dam_break.yaml) at its coarsest rung, 20 particles through the column, over the
first impact (0-0.6 s) in CI: the water leaves the reservoir as measured (H4), reaches the box when measured (P1's
and P3's onsets) and piles up in front of it (H2). The whole 0-6 s ladder at three spacings, with its wall times:
docs/validation/REPORT.md (`sph-fsi validate spheric2`, in the default suite).

Measured at this rung over 0-0.8 s (the bounds hold to 0.6 s) (the judges' own measures, answers/judges.py): H4 RMS 0.011 m; P1's onset
(the 5 ms-averaged series' first 1 kPa) 0.016 s after the measured 0.393 s, P3's 0.000 s from the measured 0.424 s.
"""
import numpy as np
import pytest

from sph_fsi_core.run import run_scene
from sph_fsi_core.scene import load_scene

pytestmark = pytest.mark.slow

END = 0.6


def test_the_coarse_spheric2_run_leaves_the_reservoir_and_reaches_the_box_when_measured():
    overrides = [f"scene.end_time={END}", "output.snapshot_interval=0"]
    overrides += [f"judge.{name}.to={END}" for name in ("H2", "H4", "P1", "P3")]
    rows = []
    summary = run_scene(load_scene("spheric2_dam_break", overrides), on_sample=lambda sim, row: rows.append(row))
    series = {k: np.array([r[k] for r in rows]) for k in rows[0]}
    judges = summary["judges"]
    assert summary["stable"] and summary["fluid_capped_steps"] == 0
    assert summary["fluid_particles_lost"] < 0.001 * summary["particles"]["fluid"]
    assert judges["H4"]["rms"] < 0.02                                  # the reservoir empties as measured
    assert judges["P1"]["onset_measured_s"] == pytest.approx(0.393, abs=0.002)
    assert abs(judges["P1"]["onset_difference_s"]) < 0.03
    assert abs(judges["P3"]["onset_difference_s"]) < 0.01
    t, h2 = series["time"], series["H2"]
    assert h2[t < 0.35].max() < 0.01 and h2[(t > 0.5) & (t <= 0.6)].mean() > 0.05   # dry until the surge passes
    # the probes read nothing before the water arrives, and the box's force points downstream (-x) once it does
    assert np.all(series["P1"][t < 0.35] == 0.0) and series["box_force_fx"][t > 0.45].mean() < 0.0
