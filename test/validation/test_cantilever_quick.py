"""Coarse validation in CI: the paper's beam (L = 40 mm, 4 x 6 mm, dp = 1 mm: 4 particles through) with the default
scheme for 2.25 periods of its reference, judged against the 3D linear-elasticity frequency of
reference_data/cantilever_frequencies.csv; and a beam of another material through `sph-fsi validate --quick`.

The default scheme (quadratic fit, strain-gradient nodal integration, mirrored clamp, implicit pressure) is -0.87 %
at this spacing (docs/validation/studies/cantilever_shapes, nu = 0.49, L / H = 10); the bound is the verification goal,
1 %, and the sign is asserted: below the 3D value. The run also must stay stable, lose little energy and grow no
sideways motion.
"""
import json

import pytest

from sph_fsi_core.run import run_scene
from sph_fsi_core.scene import load_scene
from sph_fsi_core.answers.references import read_reference_csv
from sph_fsi_core.validation.ladder import main as validate


pytestmark = pytest.mark.slow   # over ~10 s on one thread: left out of `make test-fast`


def test_the_papers_beam_with_the_default_scheme_within_1_percent_of_3d_fe(tmp_path):
    fe3d = next(r["fe3d_extrapolated_Hz"] for r in read_reference_csv("cantilever_frequencies.csv")
                if r["L_mm"] == 40)
    summary = run_scene(load_scene("cantilever", [f"scene.end_time={2.25 / fe3d}", "output.snapshot_interval=0"]),
                        out_dir=tmp_path, progress=False)
    assert summary["stable"]
    assert summary["settings"]["solid.scheme"] == "quadratic_gradient"
    assert summary["settings"]["solid.clamp"] == "mirrored" and summary["settings"]["solid.pressure"] == "implicit"
    assert summary["reference_hz"] == fe3d
    assert -0.01 < (summary["frequency_hz"] - fe3d) / fe3d < 0.0
    # Beam theory is below the 3D value (shear and the clamp's compliance aside, the 3D beam is stiffened by
    # its width through nu); eq. (15), the plane-strain plate, is far above both.
    assert summary["error_vs_eq15_percent"] < -8.0
    assert 0.0 < summary["damping_ratio"] < 0.01
    assert summary["max_sideways_speed_over_tip_speed"] < 0.01


def test_quick_default_scheme_on_a_nu_03_beam_against_its_own_fe(tmp_path):
    """The default scheme (mirrored clamp) on a beam of another material, nu = 0.3 (L/H = 10, the paper's section):
    judged against the project's 3D FE for that shape and nu (reference_data/cantilever_fe3d_nondimensional.csv),
    not beam theory. Measured -0.79 % (docs/validation/studies/cantilever_shapes; -1.34 % while the mirrored clamp kept
    the fixed clamp's margin beside the root: docs/validation/studies/clamp_effect); the bound is the verification
    issue's goal, 1 %, soft side."""
    assert validate(["cantilever_shapes"], quick=True, out_dir=tmp_path) == 0
    s = json.loads((tmp_path / "runs" / "cantilever_shapes" / "nu0.3_L_over_H_10" / "summary.json").read_text())
    assert s["settings"]["solid.clamp"] == "mirrored" and s["settings"]["solid.poisson_ratio"] == 0.3
    assert s["judged_against"] == "fe3d" and s["fe3d_source"] == "fe3d_extrapolated"
    assert -0.01 < s["frequency_hz"] / s["reference_hz"] - 1.0 < 0.0
    assert s["euler_bernoulli_hz"] < s["reference_hz"] * 1.02     # a 3D beam at nu = 0.3 stays near beam theory
    report = (tmp_path / "REPORT.md").read_text()
    assert "nu0.3_L_over_H_10" in report and "error_vs_walltime.png" in report
