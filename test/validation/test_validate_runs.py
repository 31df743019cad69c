"""`sph-fsi validate`'s bookkeeping: rungs that are the same run are run once."""
import json

from sph_fsi_core.validation import ladder as validation
from sph_fsi_core.validation.cases import Rung


def test_identical_rungs_run_once_and_both_get_the_outputs(tmp_path, monkeypatch):
    calls = []

    def fake_run(args):
        rung, out_dir = args
        calls.append(rung.key)
        d = validation.rung_dir(out_dir, rung)
        d.mkdir(parents=True)
        (d / "summary.json").write_text(json.dumps({"stable": True, "error": 0.01}))
        return {"stable": True}

    monkeypatch.setattr(validation, "run_rung", fake_run)
    a = Rung("ladder", "H4", "cantilever", {"numerics.spacing": 0.001}, periods=2.25)
    b = Rung("length", "L40", "cantilever", {"numerics.spacing": 0.001}, periods=2.25)
    c = Rung("length", "L60", "cantilever", {"geometry.length": 0.06}, periods=2.25)
    validation.run_rungs([a, b, c], tmp_path)
    assert calls == ["ladder/H4", "length/L60"]
    found = validation.load_summaries(tmp_path, [a, b, c])
    assert set(found) == {"ladder/H4", "length/L40", "length/L60"}
    # the real table: the sweep's L = 40 mm is the ladder's H/dp = 4
    rungs = {r.key: r for r in validation.all_rungs()}
    assert validation.same_run(rungs["cantilever_length/L40"]) == validation.same_run(
        rungs["cantilever_ladder/H_over_dp_4"])


def test_validate_and_stability_write_outside_the_source_tree_by_default():
    """A user's `sph-fsi validate` or `stability` never overwrites the committed report: docs/ only with --out."""
    from sph_fsi.cli import build_parser
    parser = build_parser()
    for command in ("validate", "stability"):
        assert parser.parse_args([command]).out == "runs/validation"
        assert parser.parse_args([command, "--out", "docs/validation"]).out == "docs/validation"
