"""`sph-fsi validate`'s bookkeeping: rungs that are the same run are run once."""
import json

import numpy as np

from sph_fsi_core.validation import ladder as validation
from sph_fsi_core.validation.rung import Rung


def fake_runs(monkeypatch, summary):
    """Replace running a rung by writing `summary` as its summary.json; returns the keys run, in order."""
    calls = []

    def fake_run(args):
        rung, out_dir = args
        calls.append(rung.key)
        d = validation.rung_dir(out_dir, rung)
        d.mkdir(parents=True)
        (d / "summary.json").write_text(json.dumps(summary))
        return {"stable": True}

    monkeypatch.setattr(validation, "run_rung", fake_run)
    return calls


def test_identical_rungs_run_once_and_both_get_the_outputs(tmp_path, monkeypatch):
    calls = fake_runs(monkeypatch, {"stable": True, "error": 0.01})
    a = Rung("ladder", "H4", "cantilever", {"numerics.spacing": 0.001}, periods=2.25)
    b = Rung("length", "L40", "cantilever", {"numerics.spacing": 0.001}, periods=2.25)
    c = Rung("length", "L60", "cantilever", {"geometry.length": 0.06}, periods=2.25)
    validation.run_rungs([a, b, c], tmp_path)
    assert calls == ["ladder/H4", "length/L60"]
    found = validation.load_summaries(tmp_path, [a, b, c])
    assert set(found) == {"ladder/H4", "length/L40", "length/L60"}
    # the real table: the sweep's L = 40 mm is the ladder's H/dp = 4
    rungs = {r.key: r for r in validation.all_rungs(studies=True)}
    assert validation.same_run(rungs["cantilever_length/L40"]) == validation.same_run(
        rungs["cantilever_ladder/H_over_dp_4"])


def test_validate_and_stability_write_outside_the_source_tree_by_default():
    """A user's `sph-fsi validate` or `stability` never overwrites the committed report: docs/ only with --out."""
    from sph_fsi.cli import build_parser
    parser = build_parser()
    for command in ("validate", "stability"):
        assert parser.parse_args([command]).out == "runs/validation"
        assert parser.parse_args([command, "--out", "docs/validation"]).out == "docs/validation"


def _summary(**fields):
    base = {"stable": True, "diverged": None, "particles": {"solid": 100, "fluid": 1000}, "solid_steps": 10,
            "fluid_steps": 2, "wall_time_s": 12.0, "particle_steps_per_second": 1.0e6,
            "machine": {"numba_threads": 1, "commit": "abc"}, "settings": {"numerics.spacing": 0.00125}}
    base.update(fields)
    return base


def test_report_names_its_command_and_separates_load_transfer_from_bending(tmp_path):
    """The static gate's table: coupled against loaded (the load transfer), loaded against FE (the bending), from
    the rungs' summaries; the header gives the command that made the page, with its cases and --out."""
    from sph_fsi_core.validation.report import write_report
    rungs = [r for r in validation.all_rungs(studies=True) if r.case == "gate_static"]
    fe = 3.7e-3
    summaries = {
        "gate_static/coupled_dp1.25mm": _summary(tip_deflection_m=1.10 * fe, tip_deflection_swing_m=1e-4,
                                                 reference_tip_deflection_m=fe, error_signed=0.10, error=0.10),
        "gate_static/loaded_dp1.25mm": _summary(tip_deflection_m=1.05 * fe, tip_deflection_swing_m=0.0,
                                                reference_tip_deflection_m=fe, error_signed=0.05, error=0.05),
    }
    text = write_report(tmp_path / "gs", rungs, summaries).read_text()
    assert f"`sph-fsi validate gate_static --out {(tmp_path / 'gs').as_posix()}`" in text
    rows = [line for line in text.splitlines() if line.startswith("| dp1.25mm |")]
    assert len(rows) == 1                                           # the default scheme's rungs not run: no row
    cells = [c.strip() for c in rows[0].strip("|").split("|")]
    assert cells[1] == "quadratic_plain_artificial_stress"
    assert cells[2] == "4.070 (12 s)" and cells[5] == "3.885 (12 s)"
    assert cells[4] == "-" and cells[6] == "3.700"                 # no water load in this coupled summary
    assert cells[7] == "+10.00 %"                                   # coupled against FE
    assert cells[8] == "+4.76 %" and cells[9] == "+5.00 %"          # 1.10 / 1.05 - 1; loaded against FE
    assert "| gate_static | coupled_dp1.67mm | not run |" in text


def test_missing_runs_only_the_rungs_without_a_summary(tmp_path, monkeypatch):
    """`sph-fsi validate --missing` finishes a stopped ladder: rungs with a summary.json are not run again."""
    calls = fake_runs(monkeypatch, _summary(error=0.01))
    rungs = [r for r in validation.all_rungs(studies=True) if r.case == "gate_static"]
    done = validation.rung_dir(tmp_path, rungs[0])
    done.mkdir(parents=True)
    (done / "summary.json").write_text(json.dumps(_summary(error=0.02)))
    assert validation.main(["gate_static"], out_dir=tmp_path, missing=True) == 0
    assert calls == [r.key for r in rungs[1:]]
    assert json.loads((done / "summary.json").read_text())["error"] == 0.02


def test_the_material_band_spans_the_materials_at_one_spacing_and_leaves_out_twins():
    """Antoci's plot draws the published materials as a band per spacing (the verification issue's item 5): two
    materials at one spacing give one band, their envelope; a relaxed twin of one of them (another override) and a
    run at another spacing join none."""
    from sph_fsi_core.validation.cases.gate import material_bands
    t = np.linspace(0.0, 0.4, 5)

    def curve(label, overrides, e, nu, peak):
        rung = Rung("solid_pressure", label, "antoci_gate", overrides)
        settings = {"numerics.spacing": overrides["numerics.spacing"], "solid.young_modulus": e,
                    "solid.poisson_ratio": nu}
        return rung, settings, t, peak * np.sin(np.pi * t / 0.4)

    dp = 0.005 / 3
    bands = material_bands([
        curve("a", {"numerics.spacing": dp}, 12e6, 0.4, 0.0345),
        curve("b", {"numerics.spacing": dp, "solid.young_modulus": 1e7, "solid.poisson_ratio": 0.49}, 1e7, 0.49,
              0.0352),
        curve("c", {"numerics.spacing": dp, "coupling.relaxation": 0.25}, 12e6, 0.4, 0.0340),
        curve("d", {"numerics.spacing": 0.00125}, 12e6, 0.4, 0.0359)])
    assert len(bands) == 1
    spacing, materials, times, lower, upper = bands[0]
    assert spacing == round(dp, 9) and materials == [(12e6, 0.4), (1e7, 0.49)]
    assert np.allclose(lower.max(), 0.0345) and np.allclose(upper.max(), 0.0352)


def test_the_default_report_lists_every_rung_holds_the_papers_gate_to_its_finest_and_names_kept_runs(tmp_path):
    """docs/validation/REPORT.md's headline (issue 50, item 1): a row per rung of the default suite, "not run yet"
    where none is stored; the paper's gate, which has no measurement, held to its finest rung; a run kept from an
    older commit names the commit its bits were checked against; the figure is written."""
    from sph_fsi_core.validation import cases
    from sph_fsi_core.validation.report import write_default_report
    rungs = validation.all_rungs()
    assert {r.case for r in rungs} == set(cases.default_case_names())
    assert all(not any(k in r.overrides for k in ("solid.scheme", "solid.pressure", "solid.clamp",
                                                  "solid.fit_refresh", "coupling.model")) for r in rungs)
    summaries = {
        "paper_gate/through_4": _summary(tip_dx_peak_m=-7.0e-3, tip_dx_peak_time_s=0.06),
        "paper_gate/through_6": _summary(tip_dx_peak_m=-8.0e-3, tip_dx_peak_time_s=0.06),
        "tank/H_over_dp_20": _summary(floor_pressure_pa=970.0, reference_floor_pressure_pa=981.0, error=0.0112,
                                      bits_unchanged={"same_bits_at": "def", "checked": "2026-12-06"}),
    }
    text = write_default_report(tmp_path, rungs, summaries).read_text()
    gate = [line for line in text.splitlines() if "| 4 through |" in line and "tip dx peak -7.00 mm" in line]
    assert len(gate) == 1 and "12.50 % (against the 6-through rung)" in gate[0]     # |-7 / -8 - 1|
    tank = next(line for line in text.splitlines() if "floor p 970.0 Pa" in line)
    assert "1.12 %" in tank and "abc; same bits at def (2026-12-06)" in tank
    lines = text.splitlines()
    first = next(i for i, line in enumerate(lines) if line.startswith("| case | measured |"))
    rows = lines[first + 2:lines.index("", first)]
    assert len(rows) == len(rungs) and all(line.count("|") == 14 for line in rows)   # a row per rung
    assert sum("not run yet" in line for line in rows) == len(rungs) - len(summaries)
    assert (tmp_path / "error_vs_walltime.png").stat().st_size > 10_000
    assert "`sph-fsi validate --out " in text
