"""The CI subset of `sph-fsi stability` (sph_fsi_core/validation/stability.py), run here.

Stiff (steel, E = 2e11 Pa) and soft (E = 1e5 Pa) beams run stably for two of their own periods with the time
step the sound speed dictates; inputs that cannot work (nu = 0.5, E = 0, a forced step 10x the stable limit, a
spacing coarser than the beam) are refused before any computation with a message naming the key and the allowed
range; no case writes a NaN.
"""
import pytest

from sph_fsi_core.validation import stability


pytestmark = pytest.mark.slow   # over ~10 s on one thread: left out of `make test-fast`


@pytest.fixture(scope="module")
def rows(tmp_path_factory):
    out = tmp_path_factory.mktemp("stability")
    cases = [c for c in stability.all_cases() if c.ci]
    return {c.name: stability.run_case(c, out) for c in cases}, out


# the inputs that cannot work; every other CI case must run to its end
REFUSED = {"cantilever, forced dt 10x the stable limit", "cantilever nu = 0.5", "cantilever E = 0",
           "cantilever spacing larger than the beam"}


def test_impossible_inputs_are_refused_and_the_rest_run_to_their_end_with_finite_outputs(rows):
    results, _ = rows
    assert len(results) >= 10
    assert {n for n, r in results.items() if r["outcome"] == "refused"} == REFUSED
    for name, row in results.items():
        if name in REFUSED:
            assert row["wall_time_s"] < 5.0, name        # refused at load or build, before any step
            continue
        assert row["outcome"] == "stable", (name, row.get("detail"))
        assert row["outputs_finite"], name
        assert row["end_time_s"] > 0 and (row["solid_dt_s"] or row["fluid_dt_s"]) > 0, name


def test_short_beams_vibrate_just_below_beam_theory(rows):
    """L/H = 5: shear and rotary inertia put the first bending frequency below Euler-Bernoulli's, by a few percent
    (rubber, nu = 0.49: ~3 %; steel, nu = 0.3, and nu = 0: 8-10 %), whatever the stiffness."""
    results, _ = rows
    beams = [n for n in results if n.startswith("cantilever") and results[n]["outcome"] == "stable"]
    assert len(beams) >= 3
    for name in beams:
        assert -12.0 < results[name]["frequency_error"] < 0.0, (name, results[name]["frequency_error"])


def test_refusals_name_the_key_and_the_allowed_range(rows):
    results, _ = rows
    refused = {n: r for n, r in results.items() if r["expect"] == "refused"}
    assert len(refused) >= 4
    for name, row in refused.items():
        detail = row["detail"]
        assert "allowed" in detail, (name, detail)
        key = next(iter(row["overrides"].keys() - {"geometry.length"}))
        assert key in detail, (name, key, detail)


def test_stiff_and_soft_beams_take_the_step_their_sound_speed_dictates(rows):
    """dt = cfl h / (c + |v|), c with the default scheme's implicit pressure the deviatoric waves' sqrt(4 G / 3 rho):
    steel's step is ~sqrt(E ratio) shorter than rubber's, and both runs are stable."""
    results, _ = rows
    steel = results["cantilever E = 2e+11 Pa"]
    rubber = results["cantilever E = 1e+05 Pa"]
    assert steel["outcome"] == rubber["outcome"] == "stable"
    # c^2 = 4 G / (3 rho), G = E / (2 (1 + nu)): steel 2e11 / (2.6 * 7850), rubber 1e5 / (2.98 * 1000)
    ratio = (2e11 / (2.6 * 7850) / (1e5 / (2.98 * 1000))) ** 0.5
    assert rubber["solid_dt_s"] / steel["solid_dt_s"] == pytest.approx(ratio, rel=0.01)
    for row in (steel, rubber):
        assert row["energy_drift"] < 0.02          # the energy does not grow (the viscosity takes a little)


def test_report_is_written(rows):
    results, out = rows
    stability.write_report(out, list(results.values()), {"cpus": 2, "numba_threads": 1, "commit": "test"})
    text = (out / "STABILITY.md").read_text()
    for name in results:
        assert name in text
    # hand-written notes under the notes heading survive a rerun
    (out / "STABILITY.md").write_text(text + "\n" + stability.NOTES_HEADING + "\n\n- a note\n")
    stability.write_report(out, list(results.values()), {"cpus": 2, "numba_threads": 1, "commit": "again"})
    text = (out / "STABILITY.md").read_text()
    assert "commit again" in text and text.count(stability.NOTES_HEADING) == 1 and text.endswith("- a note\n")


def test_gate_standing_on_the_floor_holds_the_water_and_bends(rows):
    """No gap: no water passes; the whole column leans on the plate and bends it downstream (-x). The static
    deflection of a clamped plate under the hydrostatic triangle (4 mm rubber, E = 1.859 MPa, 38 mm of water) is
    ~8 mm (P a^2 (3L - a) / 6EI with the resultant 7.1 N/m at a = 27 mm); a suddenly applied load overshoots to
    at most twice that."""
    results, _ = rows
    row = results["gate with no gap"]
    assert row["outcome"] == "stable"
    assert row["water_past_gate"] == 0.0
    assert -0.016 < row["tip_dx_peak_m"] < -0.002


def test_soft_gate_takes_the_long_step_its_sound_speed_allows(rows):
    """E = 1e5 Pa: c0 is sqrt(18.6) slower than the paper's gate, the solid step as much longer; the water pushes
    the free end downstream and flows out under it."""
    results, _ = rows
    row = results["gate E = 1e+05 Pa"]
    assert row["outcome"] == "stable" and row["tip_dx_peak_m"] < 0.0 and row["water_past_gate"] > 0.0
    paper_gate = results["gate with no gap"]     # same spacing, nu and density, E = 1.859 MPa
    assert row["solid_dt_s"] / paper_gate["solid_dt_s"] == pytest.approx((1.859e6 / 1e5) ** 0.5, rel=0.02)


def test_tall_column_runs_with_the_step_its_speed_dictates(rows):
    """10x the Martin & Moyce column: stable, the density correction converging without hitting the cap."""
    results, _ = rows
    row = results["dam break, 10x taller column"]
    assert row["outcome"] == "stable" and row["outputs_finite"]
    assert row["fluid_capped_steps"] == 0


def test_a_partial_rerun_replaces_its_rows_and_drops_cases_that_no_longer_exist(tmp_path):
    import json
    names = [c.name for c in stability.all_cases()]
    earlier = [{"case": names[0], "outcome": "old"}, {"case": names[1], "outcome": "old"},
               {"case": "a case renamed since", "outcome": "old"}]
    (tmp_path / "stability.json").write_text(json.dumps(earlier))
    merged = stability._merged_with_earlier(tmp_path, [{"case": names[1], "outcome": "new"}])
    assert [(r["case"], r["outcome"]) for r in merged] == [(names[0], "old"), (names[1], "new")]
