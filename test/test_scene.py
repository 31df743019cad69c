"""Scenes (loading, validation, the cantilever builder), the references they are judged against, the reference
data's provenance, config/defaults.yaml, and the command line's handling of bad input."""
import math
from pathlib import Path

import numpy as np
import pytest

from sph_fsi.cli import main
from sph_fsi_core.answers import references
from sph_fsi_core.answers.references import (beam_theory_frequency, cantilever_mode_velocity, clamped_free_mode_kl,
                                     fe3d_frequency, plate_frequency_eq15, read_reference_csv)
from sph_fsi_core.scene import defaults_yaml, load_scene
from sph_fsi_core.scenes import BUILDERS
from sph_fsi_core.scenes.cases import cantilever
from sph_fsi_core.schema import SceneError
from sph_fsi_core.simulation import Simulation
from sph_fsi_core.solid.solver import QUADRATIC_FIT_TESTED_CFL

REPO = Path(__file__).resolve().parents[1]
SHARED_REFERENCE = Path(__file__).resolve().parents[2] / "shared" / "reference"
CANTILEVER_YAML = (REPO / "config" / "cantilever.yaml").read_text()


# ---- the cantilever scene ----------------------------------------------------------------------------------

def test_cantilever_scene_values():
    spec = load_scene("cantilever")
    assert spec.builder == "geometry" and spec["scene.case"] == "cantilever"
    assert spec.name == "cantilever"
    assert spec["numerics.spacing"] == 1e-3
    assert spec["solid.young_modulus"] == 1.859e6
    assert isinstance(spec["solid.young_modulus"], float)
    assert spec["solid.poisson_ratio"] == 0.49
    assert spec["solid.density"] == 1000.0
    assert spec["geometry.length"] == 0.04
    assert spec["geometry.thickness"] == 0.004
    assert spec["geometry.width"] == 0.006
    assert spec["numerics.smoothing_ratio"] == 1.3
    assert spec["geometry.tip_velocity"] == 0.01
    assert spec["scene.gravity"] == (0.0, 0.0, 0.0)
    assert spec.phases == ("solid",)
    # the default scene is the cantilever
    assert load_scene().values == spec.values


def build(spec):
    """The particles of a scene as its builder makes them (before the mirrored clamp's unreached ones go)."""
    return BUILDERS[spec.builder].build(spec.values)


def test_cantilever_build():
    spec = load_scene("cantilever")
    built = build(spec)
    s = built.solid
    assert s.moving_count == 960
    # the default scheme's mirrored clamp: the root's odd image, 4 x 4 x 6 ghosts, every one with its image in the beam
    assert s.count == 960 + 96 and int((~s.movable).sum()) == 96
    assert (built.clamp_mirror[~s.movable] >= 0).all()
    # the fixed clamp (Gray's scheme, the paper's): its wall 4 layers deep, 5 above and below: 4 x 14 x 6 = 336
    fixed = build(load_scene("cantilever", ["solid.scheme=gray2001"])).solid
    assert int((~fixed.movable).sum()) == 336
    assert np.ptp(fixed.pos[~fixed.movable][:, 2]) == pytest.approx(13 * 1e-3)
    dp = 1e-3
    # lattice: beam x in (0, L), clamp x < 0, centred in y and z
    beam = s.pos[s.movable]
    clamp = s.pos[~s.movable]
    assert beam[:, 0].min() == pytest.approx(0.5 * dp) and beam[:, 0].max() == pytest.approx(39.5 * dp)
    assert clamp[:, 0].max() == pytest.approx(-0.5 * dp) and clamp[:, 0].min() == pytest.approx(-3.5 * dp)
    assert abs(beam[:, 1].mean()) < 1e-15 and abs(beam[:, 2].mean()) < 1e-15
    assert np.ptp(clamp[:, 2]) == pytest.approx(3 * dp)
    # mass and density
    assert np.allclose(s.mass, 1000.0 * dp ** 3, rtol=1e-14)
    assert np.all(s.rho == 1000.0) and np.all(s.stress == 0.0)
    # the tip probe: the 24 particles of the last layer, at x = 39.5 mm
    assert len(built.probes) == 1
    tip = built.probes[0]
    assert tip.name == "tip" and tip.phase == "solid"
    assert len(tip.indices) == 24
    assert np.allclose(s.pos[tip.indices, 0], 0.0395, rtol=0, atol=1e-12)
    assert np.all(s.movable[tip.indices])
    assert tip.reference_position == pytest.approx([0.0395, 0.0, 0.0], abs=1e-12)
    # initial velocity: eq. (12) along z, 0.01 m/s at x = L, 9.828 mm/s at the tip layer x = L - dp/2
    vz_tip = s.vel[tip.indices, 2]
    assert np.all(np.abs(vz_tip - 0.01) < 0.02 * 0.01)
    assert np.allclose(vz_tip, cantilever_mode_velocity(0.0395, 0.04, 0.01), rtol=1e-12)
    assert vz_tip[0] == pytest.approx(0.0098279369, rel=1e-8)
    assert np.all(s.vel[:, :2] == 0.0)
    assert np.all(s.vel[~s.movable] == 0.0)
    # the profile rises monotonically from root to tip
    order = np.argsort(beam[:, 0])
    assert np.all(np.diff(s.vel[s.movable][order, 2]) >= -1e-15)
    # no fluid phase
    assert spec.phases == ("solid",)
    assert built.fluid is None and built.walls is None
    assert np.all(built.domain_lo < s.pos.min(axis=0)) and np.all(built.domain_hi > s.pos.max(axis=0))


def test_cantilever_build_other_resolution():
    spec = load_scene("cantilever", ["numerics.spacing=0.0005", "geometry.length=0.01"])
    built = build(spec)
    # beam 20 x 12 x 8, the mirrored clamp 4 x 12 x 8 (the fixed clamp's margin counts layers: 4 x 12 x (8 + 10))
    assert built.solid.moving_count == 20 * 12 * 8
    assert built.solid.count == 20 * 12 * 8 + 4 * 12 * 8
    fixed = build(spec.with_overrides({"solid.clamp": "fixed"})).solid
    assert fixed.count == 20 * 12 * 8 + 4 * 12 * 18
    assert len(built.probes[0].indices) == 12 * 8


# ---- references --------------------------------------------------------------------------------------------

def test_clamped_free_root():
    kl = clamped_free_mode_kl()
    assert abs(kl - 1.8751040687) < 1e-9
    assert abs(math.cos(kl) * math.cosh(kl) + 1.0) < 1e-13
    assert clamped_free_mode_kl(2) == pytest.approx(4.6940911330, abs=1e-9)


def test_mode_velocity():
    for length, vf in ((0.04, 0.01), (0.12, -3.0), (1.0, 1.0)):
        assert cantilever_mode_velocity(length, length, vf) == pytest.approx(vf, rel=1e-12)
        assert abs(cantilever_mode_velocity(0.0, length, vf)) < 1e-15
        x = np.linspace(0.0, length, 50)
        assert np.allclose(cantilever_mode_velocity(x, length, vf) / vf,
                           cantilever_mode_velocity(x / length, 1.0, 1.0), rtol=1e-12, atol=1e-15)


def test_frequencies_against_reference_csv():
    rows = read_reference_csv("cantilever_frequencies.csv")
    assert [r["L_mm"] for r in rows] == [40.0, 60.0, 80.0, 100.0, 120.0]
    for row in rows:
        length = row["L_mm"] * 1e-3
        eb = beam_theory_frequency(length, 0.004, 1.859e6, 1000.0)
        eq15 = plate_frequency_eq15(length, 0.004, 1.859e6, 0.49, 1000.0)
        assert abs(eb - row["eb_Hz"]) < 1e-3 * row["eb_Hz"], (row, eb)
        assert abs(eq15 - row["eq15_Hz"]) < 1e-3 * row["eq15_Hz"], (row, eq15)
        fe, label = fe3d_frequency(length, 0.004, 0.006, 1.859e6, 0.49, 1000.0, compute=False)
        assert label == "fe3d_extrapolated"
        if row["fe3d_extrapolated_Hz"] is not None:
            assert fe == row["fe3d_extrapolated_Hz"]
        else:   # the extrapolated FE of the nondimensional table, below this file's 1 mm mesh by 0.15-0.5 %
            assert -0.005 < fe / row["fe3d_1mm_Hz"] - 1.0 < -0.0015, (length, fe)
    # frequencies scale as 1 / L^2
    assert beam_theory_frequency(0.08, 0.004, 1.859e6, 1000.0) == pytest.approx(
        beam_theory_frequency(0.04, 0.004, 1.859e6, 1000.0) / 4.0, rel=1e-14)


def test_fe3d_reference():
    rows = read_reference_csv("cantilever_frequencies.csv")
    f40 = rows[0]["fe3d_extrapolated_Hz"]
    assert f40 == 17.58
    assert fe3d_frequency(0.04, 0.004, 0.006, 1.859e6, 0.49, 1000.0) == (f40, "fe3d_extrapolated")
    fe, label = fe3d_frequency(0.04, 0.004, 0.006, 4 * 1.859e6, 0.49, 1000.0)
    assert fe == pytest.approx(2.0 * f40, rel=1e-14) and label == "fe3d_extrapolated"
    fe, _ = fe3d_frequency(0.04, 0.004, 0.006, 1.859e6, 0.49, 1100.0)
    assert fe == pytest.approx(f40 * math.sqrt(1000.0 / 1100.0), rel=1e-14)
    refs = references.cantilever_references(0.04, 0.004, 0.006, 1.859e6, 0.49, 1000.0)
    assert refs["judged_against"] == "fe3d" and refs["reference_hz"] == f40


def test_fe3d_nondimensional_table():
    """The committed table of other shapes and Poisson ratios: scaled exactly, and between the thin-beam limits."""
    table = references._nondimensional_rows(references.DATA_DIR / references.FE3D_TABLE)
    shapes = {(r[0], r[2]) for r in table}
    assert {(ratio, nu) for ratio in (10.0, 20.0, 30.0) for nu in (0.3, 0.4, 0.49)} <= shapes
    for ratio, width, nu, value in table:
        thickness, E, rho = 0.002, 3.0e6, 1200.0
        fe, label = fe3d_frequency(ratio * thickness, thickness, width * thickness, E, nu, rho, compute=False)
        assert label == "fe3d_extrapolated"
        assert fe == pytest.approx(value * math.sqrt(E / rho) / thickness, rel=1e-12)
        # a clamped 3D beam: shear makes it softer than Euler-Bernoulli by ~(H / L)^2, and it is never as stiff as
        # the plane-strain plate of eq. (15)
        eb = beam_theory_frequency(ratio * thickness, thickness, E, rho)
        plate = plate_frequency_eq15(ratio * thickness, thickness, E, nu, rho)
        assert eb * (1.0 - 3.0 / ratio ** 2) < fe < plate, (ratio, nu, fe / eb)
    # the paper's section at L = 60 mm: the table's extrapolated value is below the 1 mm mesh's (which is ~0.5 % high)
    fe60, _ = fe3d_frequency(0.06, 0.004, 0.006, 1.859e6, 0.49, 1000.0, compute=False)
    row60 = read_reference_csv("cantilever_frequencies.csv")[1]
    assert 0.990 < fe60 / row60["fe3d_1mm_Hz"] < 1.0
    fe, why = fe3d_frequency(0.04, 0.004, 0.008, 1.859e6, 0.49, 1000.0, compute=False)
    assert fe is None and "not computed" in why


@pytest.mark.slow
def test_fe3d_computed_on_demand_and_cached(monkeypatch, tmp_path):
    """A shape no table lists: computed (three meshes, extrapolated), kept in the cache, read back from it."""
    from sph_fsi_core.answers import fe_reference
    monkeypatch.setenv("SPH_FSI_CACHE", str(tmp_path))
    args = (0.012, 0.004, 0.002, 1.859e6, 0.3, 1000.0)       # L / H = 3, W / H = 0.5
    fe, label = fe3d_frequency(*args)
    assert label == "fe3d_extrapolated (computed)"
    direct = fe_reference.cantilever_fe_nondimensional(3.0, 0.5, 0.3)
    # the same eigenproblem solved twice: equal to LAPACK's rounding (threaded BLAS differs in the 12th digit)
    assert fe == pytest.approx(direct["frequency"] * math.sqrt(1.859e6 / 1000.0) / 0.004, rel=1e-9)
    meshes = direct["mesh_frequencies"]
    assert meshes[0] > meshes[1] > meshes[2] > direct["frequency"]   # the meshes converge from above
    assert 1.0 < direct["order"] < 3.0

    def not_again(*_):
        raise AssertionError("computed twice")
    monkeypatch.setattr(fe_reference, "cantilever_fe_nondimensional", not_again)
    fe2, label2 = fe3d_frequency(*args)
    assert fe2 == pytest.approx(fe, rel=1e-9) and label2 == "fe3d_extrapolated (computed, cached)"
    refs = references.cantilever_references(*args)
    assert refs["judged_against"] == "fe3d" and refs["reference_hz"] == pytest.approx(fe, rel=1e-9)


def test_reference_data_provenance_and_copies():
    files = sorted(p for p in references.DATA_DIR.iterdir() if p.is_file())
    assert len(files) >= 5
    for p in files:
        first = p.read_text().splitlines()[0]
        assert first.startswith("#") and len(first) > 20, f"{p.name}: first line is not a source citation"
    if SHARED_REFERENCE.is_dir():
        for p in files:
            if p.name == references.FE3D_TABLE:   # the project's own FE, computed here (its header says how)
                continue
            original = SHARED_REFERENCE / p.name
            assert original.is_file(), f"{p.name} has no original in {SHARED_REFERENCE}"
            assert p.read_bytes() == original.read_bytes(), f"{p.name} differs from {original}"


# ---- YAML loading ------------------------------------------------------------------------------------------

def _write(tmp_path, text, name="scene.yaml"):
    p = tmp_path / name
    p.write_text(text)
    return str(p)


def test_yaml12_floats(tmp_path):
    text = CANTILEVER_YAML.replace("young_modulus: 1.859e6", "young_modulus: 2e6")
    assert "young_modulus: 2e6" in text
    spec = load_scene(_write(tmp_path, text))
    assert spec["solid.young_modulus"] == 2e6 and isinstance(spec["solid.young_modulus"], float)
    spec = load_scene("cantilever", ["solid.young_modulus=3E+6", "solid.density=1.1e3"])
    assert spec["solid.young_modulus"] == 3e6 and spec["solid.density"] == 1100.0


def test_file_and_override_order(tmp_path):
    text = CANTILEVER_YAML.replace("poisson_ratio: 0.49", "poisson_ratio: 0.45")
    path = _write(tmp_path, text, "my_beam.yaml")
    spec = load_scene(path)
    assert spec["solid.poisson_ratio"] == 0.45
    assert spec["solid.cfl"] == 0.25                       # schema default
    assert spec["scene.end_time"] == 0.3                    # file (and builder default)
    spec = load_scene(path, ["solid.poisson_ratio=0.3"])
    assert spec["solid.poisson_ratio"] == 0.3
    spec2 = spec.with_overrides({"solid.young_modulus": 1e6})
    assert spec2["solid.poisson_ratio"] == 0.3 and spec2["solid.young_modulus"] == 1e6
    # a minimal file: its parts (the geometry builder without scene.builder), everything else by default
    spec = load_scene(_write(tmp_path, "solid:\n  density: 1200.0\nparts:\n  - {name: block, role: solid, "
                                       "shape: box, size: [0.01, 0.01, 0.01]}\n", "block.yaml"))
    assert spec.builder == "geometry" and spec["solid.density"] == 1200.0 and spec["numerics.spacing"] == 1e-3


def _replace(old, new):
    assert old in CANTILEVER_YAML, old
    return CANTILEVER_YAML.replace(old, new)


# (id, YAML text or None for the stock file, overrides, words the message must contain)
BAD_FILES = [
    ("yaml_syntax", "scene: [unclosed\n", [], ["not valid YAML"]),
    ("yaml_tab_indent", "solid:\n\tdensity: 3\n", [], ["not valid YAML"]),
    ("empty_file", "", [], ["empty"]),
    ("comments_only", "# nothing here\n", [], ["empty"]),
    ("top_level_list", "- solid\n- fluid\n", [], ["mapping", "list"]),
    ("top_level_scalar", "42\n", [], ["mapping", "int"]),
    ("section_not_mapping", CANTILEVER_YAML + "watchdog: 3\n", [], ["watchdog", "mapping"]),
    ("nested_section", _replace("  poisson_ratio: 0.49", "  poisson_ratio:\n    value: 0.49"), [],
     ["solid.poisson_ratio", "nested"]),
    ("unknown_section", CANTILEVER_YAML + "bogus:\n  x: 1\n", [], ["bogus.x", "unknown"]),
    ("unknown_key", _replace("  poisson_ratio: 0.49", "  poisson_ratio: 0.49\n  hardness: 3"), [],
     ["solid.hardness", "unknown"]),
    ("misspelt_key", _replace("  young_modulus: 1.859e6", "  youngs_modulus: 1.859e6"), [],
     ["solid.youngs_modulus", "did you mean solid.young_modulus"]),
    ("misspelt_key_2", _replace("  spacing: 0.001", "  spacnig: 0.001"), [],
     ["numerics.spacnig", "did you mean numerics.spacing"]),
    ("duplicate_key", _replace("  poisson_ratio: 0.49", "  poisson_ratio: 0.49\n  poisson_ratio: 0.3"), [],
     ["poisson_ratio", "duplicate"]),
    ("duplicate_section", CANTILEVER_YAML + "solid:\n  density: 900.0\n", [], ["solid", "duplicate"]),
    ("fluid_section_in_cantilever", CANTILEVER_YAML + "fluid:\n  density: 1000.0\n", [], ["fluid.density"]),
    ("unknown_builder", _replace("builder: geometry", "builder: dam_break_xyz"), [],
     ["scene.builder", "allowed", "geometry"]),
    ("builder_not_string", _replace("builder: geometry", "builder: 3"), [], ["scene.builder"]),
    ("string_for_float", _replace("young_modulus: 1.859e6", "young_modulus: stiff"), [],
     ["solid.young_modulus", "allowed"]),
    ("yaml11_nan_word", _replace("young_modulus: 1.859e6", "young_modulus: nan"), [],
     ["solid.young_modulus", "allowed"]),
    ("list_for_float", _replace("density: 1000.0", "density: [1000.0, 2.0]"), [], ["solid.density", "allowed"]),
    ("float_for_int", None, ["geometry.clamp_layers=2.5"], ["geometry.clamp_layers", "allowed"]),
    ("bool_for_int", None, ["geometry.clamp_layers=true"], ["geometry.clamp_layers", "allowed"]),
    ("declared_range_not_numbers", _replace('clamp_layers: {value: 4, unit: "1", range: [1, 20]',
                                            'clamp_layers: {value: 4, unit: "1", range: [true, 20]'),
     [], ["geometry.clamp_layers.range", "allowed"]),
    ("declared_without_unit", _replace("thickness: {value: 0.004, unit: m,", "thickness: {value: 0.004,"), [],
     ["geometry.thickness.unit", "missing"]),
    ("declared_unknown_field", _replace("thickness: {value: 0.004, unit: m,", "thickness: {value: 0.004, units: m,"),
     [], ["geometry.thickness.units", "allowed"]),
    ("derived_set", None, ["geometry.reach=0.1"], ["geometry.reach", "derives", "allowed"]),
    ("expression_unknown_name", _replace("size: [length, width, thickness]", "size: [lenght, width, thickness]"), [],
     ["parts.beam.size", "lenght", "did you mean 'length'", "allowed"]),
    ("expression_not_allowed", _replace("size: [length, width, thickness]", "size: [__import__('os'), width, 1]"),
     [], ["parts.beam.size", "not allowed"]),
    ("expression_out_of_range", None, ["parts.beam.mode_length=-length"],
     ["parts.beam.mode_length = '-length' = -0.04", "out of range"]),
    ("bool_for_float", _replace("density: 1000.0", "density: yes"), [], ["solid.density", "allowed"]),
    ("negative", _replace("young_modulus: 1.859e6", "young_modulus: -1.859e6"), [],
     ["solid.young_modulus", "allowed"]),
    ("zero", _replace("young_modulus: 1.859e6", "young_modulus: 0"), [], ["solid.young_modulus", "allowed"]),
    ("nan", _replace("young_modulus: 1.859e6", "young_modulus: .nan"), [], ["solid.young_modulus", "allowed"]),
    ("inf", _replace("density: 1000.0", "density: .inf"), [], ["solid.density", "allowed"]),
    ("minus_inf", _replace("tip_velocity: {value: 0.01,", "tip_velocity: {value: -.inf,"), [],
     ["geometry.tip_velocity", "allowed"]),
    ("nu_half", _replace("poisson_ratio: 0.49", "poisson_ratio: 0.5"), [], ["solid.poisson_ratio", "allowed"]),
    ("nu_0.6", _replace("poisson_ratio: 0.49", "poisson_ratio: 0.6"), [], ["solid.poisson_ratio", "allowed"]),
    ("gravity_two_components", _replace("gravity: [0.0, 0.0, 0.0]", "gravity: [0.0, -9.81]"), [],
     ["scene.gravity", "allowed"]),
    ("gravity_nan_component", _replace("gravity: [0.0, 0.0, 0.0]", "gravity: [0.0, 0.0, .nan]"), [],
     ["scene.gravity", "allowed"]),
    ("gravity_scalar", _replace("gravity: [0.0, 0.0, 0.0]", "gravity: -9.81"), [], ["scene.gravity", "allowed"]),
    ("end_time_zero", _replace("end_time: 0.3", "end_time: 0"), [], ["scene.end_time", "allowed"]),
    ("smoothing_ratio_3", _replace("smoothing_ratio: 1.3", "smoothing_ratio: 3"), [],
     ["numerics.smoothing_ratio", "allowed"]),
    ("spacing_above_thickness", _replace("spacing: 0.001", "spacing: 0.005"), [],
     ["numerics.spacing", "geometry.thickness", "allowed"]),
    ("spacing_equal_to_thickness", _replace("spacing: 0.001", "spacing: 0.004"), [],
     ["numerics.spacing", "geometry.thickness", "allowed"]),
    ("length_not_multiple", _replace("length: {value: 0.04,", "length: {value: 0.0405,"), [],
     ["geometry.length", "allowed"]),
    ("scene_name_number", _replace("name: cantilever", "name: 5"), [], ["scene.name", "allowed"]),
    # overrides
    ("set_negative_modulus", None, ["solid.young_modulus=-1"], ["solid.young_modulus", "allowed"]),
    ("set_modulus_too_large", None, ["solid.young_modulus=1e14"], ["solid.young_modulus", "allowed"]),
    ("set_overflow_inf", None, ["solid.young_modulus=1e999"], ["solid.young_modulus", "allowed"]),
    ("set_empty_value", None, ["solid.young_modulus="], ["solid.young_modulus", "allowed"]),
    ("set_nu_half", None, ["solid.poisson_ratio=0.5"], ["solid.poisson_ratio", "allowed"]),
    ("set_nu_negative", None, ["solid.poisson_ratio=-0.1"], ["solid.poisson_ratio", "allowed"]),
    ("set_neighbour_skin_zero", None, ["numerics.neighbour_skin=0"], ["numerics.neighbour_skin", "allowed"]),
    ("set_end_time_negative", None, ["scene.end_time=-1"], ["scene.end_time", "allowed"]),
    ("set_exponent_zero", None, ["solid.artificial_stress_exponent=0"],
     ["solid.artificial_stress_exponent", "allowed"]),
    ("set_energy_growth_one", None, ["watchdog.energy_growth=1"], ["watchdog.energy_growth", "allowed"]),
    ("set_spacing_not_divisor", None, ["numerics.spacing=0.0015"], ["numerics.spacing", "allowed"]),
    ("set_width_below_spacing", None, ["geometry.width=0.0005"], ["geometry.width", "allowed"]),
    ("set_fluid_key", None, ["fluid.density=1000"], ["fluid.density"]),
    ("set_unknown_builder", None, ["scene.builder=foo"], ["scene.builder", "allowed"]),
    ("set_without_equals", None, ["solid.young_modulus"], ["--set", "solid.young_modulus", "KEY=VALUE"]),
    ("set_colon_not_equals", None, ["solid.young_modulus: 3"], ["--set", "KEY=VALUE"]),
    ("set_key_without_section", None, ["young_modulus=3"], ["--set", "young_modulus", "section.name"]),
    ("set_key_upper_case", None, ["Solid.density=3"], ["--set", "Solid.density", "section.name"]),
    ("set_bad_yaml_value", None, ["solid.density=[1,"], ["solid.density", "not valid YAML"]),
]


@pytest.mark.parametrize("case", BAD_FILES, ids=[c[0] for c in BAD_FILES])
def test_bad_input_raises_scene_error(tmp_path, case):
    _, text, overrides, words = case
    source = "cantilever" if text is None else _write(tmp_path, text)
    with pytest.raises(SceneError) as info:
        load_scene(source, overrides)
    message = str(info.value)
    for word in words:
        assert word in message, f"{word!r} not in {message!r}"


def test_unknown_scene_name_and_missing_file(tmp_path):
    with pytest.raises(SceneError, match="no such built-in scene.*allowed.*cantilever"):
        load_scene("no_such_scene")
    with pytest.raises(SceneError, match="not found"):
        load_scene(str(tmp_path / "missing.yaml"))


def test_time_step_above_stable_limit_is_refused():
    spec = load_scene("cantilever", ["geometry.length=0.004", "solid.time_step=1e-3"])
    assert spec["solid.time_step"] == 1e-3       # in range for the schema; the stability check is the simulation's
    with pytest.raises(SceneError) as info:
        Simulation(spec)
    message = str(info.value)
    assert "solid.time_step" in message and "allowed" in message
    # a step below the limit is accepted: 0.25 * 1.3 mm / (176 m/s + |v|) = 1.85e-6 s with the explicit pressure (the
    # bulk sound speed), 0.25 * 1.3 mm / (28.82 m/s + |v|) = 1.13e-5 s with the implicit one (the deviatoric waves,
    # sqrt(4 G / 3 rho0), G = E / (2 (1 + nu)))
    sim = Simulation(load_scene("cantilever", ["geometry.length=0.004", "solid.time_step=1e-6",
                                               "solid.pressure=explicit"]))
    assert sim.solid_phase.solver.stable_dt() == pytest.approx(0.25 * 1.3e-3 / (176.0208 + 0.01), rel=1e-4)
    sim = Simulation(load_scene("cantilever", ["geometry.length=0.004", "solid.time_step=1e-5"]))
    shear_wave = (4.0 / 3.0 * 1.859e6 / (2.0 * 1.49) / 1000.0) ** 0.5
    assert sim.solid_phase.solver.stable_dt() == pytest.approx(0.25 * 1.3e-3 / (shear_wave + 0.01), rel=1e-4)
    # the mirrored clamp's 4 x 4 x 6, less its last layer, beyond the body's reach (scenes/built.py)
    assert sim.solid.count == 4 * 24 + 3 * 24


# ---- config/defaults.yaml ----------------------------------------------------------------------------------

def test_defaults_yaml_is_current():
    path = REPO / "config" / "defaults.yaml"
    assert path.is_file(), "config/defaults.yaml missing: python -m sph_fsi.cli keys --yaml > config/defaults.yaml"
    assert path.read_text() == defaults_yaml(), \
        "config/defaults.yaml is stale: python -m sph_fsi.cli keys --yaml > config/defaults.yaml"


def test_defaults_yaml_parses_to_the_schema_defaults():
    from sph_fsi_core.scene import parse_yaml
    from sph_fsi_core.schema import COMMON, SOLID
    tree = parse_yaml(defaults_yaml())
    for p in COMMON + SOLID:
        section, name = p.key.split(".", 1)
        value = tree[section][name]
        default = list(p.default) if isinstance(p.default, tuple) else p.default
        assert value == default and type(value) is type(default), (p.key, value, default)


def test_builtin_scenes_load():
    from sph_fsi_core.scene import builtin_scenes
    scenes = builtin_scenes()
    assert "cantilever" in scenes and "defaults" not in scenes
    for name, path in scenes.items():
        spec = load_scene(str(path))
        assert spec.builder in BUILDERS


# ---- command line ------------------------------------------------------------------------------------------

def test_cli_bad_poisson_ratio(capsys):
    assert main(["run", "cantilever", "--set", "solid.poisson_ratio=0.5"]) == 2
    out, err = capsys.readouterr()
    lines = err.strip().splitlines()
    assert len(lines) == 1, err
    assert "solid.poisson_ratio" in lines[0] and "allowed" in lines[0]
    assert out == ""


def test_cli_scenes(capsys):
    assert main(["scenes"]) == 0
    out, _ = capsys.readouterr()
    names = [line.split()[0] for line in out.strip().splitlines()]
    assert "cantilever" in names
    assert "(default)" in [line for line in out.splitlines() if line.startswith("cantilever")][0]


def test_cli_unwritable_out(capsys):
    # tiny scene and end time, so that even a broken check could not start a long run
    code = main(["run", "cantilever", "--set", "geometry.length=0.004", "--end-time", "1e-5",
                 "--out", "/proc/forbidden"])
    assert code == 2
    _, err = capsys.readouterr()
    lines = err.strip().splitlines()
    assert len(lines) == 1, err
    assert "--out" in lines[0] and "/proc/forbidden" in lines[0]


def test_cli_yaml_syntax_error_is_one_line(tmp_path, capsys):
    """cli.py promises one line on bad input; a YAML syntax error's message (PyYAML's) spans several."""
    path = _write(tmp_path, "scene: [unclosed\n")
    assert main(["run", path, "--out", str(tmp_path / "out")]) == 2
    _, err = capsys.readouterr()
    lines = err.strip().splitlines()
    assert "not valid YAML" in lines[0]
    assert len(lines) == 1, err


def test_cli_keys(capsys):
    assert main(["keys", "cantilever"]) == 0
    out, _ = capsys.readouterr()
    keys = [line.split()[0] for line in out.strip().splitlines()]
    assert "solid.young_modulus" in keys and "geometry.length" in keys
    assert not any(k.startswith("fluid.") for k in keys)
    assert main(["keys", "--yaml"]) == 0
    out, _ = capsys.readouterr()
    assert out == defaults_yaml()


def test_cli_run_reports_the_fallback_of_a_too_thin_body(tmp_path, capsys):
    """Two layers through the thickness: the default quadratic fit is not determined there; the run says so."""
    code = main(["run", "cantilever", "--set", "numerics.spacing=0.002", "--set", "geometry.length=0.02",
                 "--end-time", "2e-4", "--out", str(tmp_path / "thin")])
    assert code == 0
    out, err = capsys.readouterr()
    assert "solid steps:" in out and "fluid steps" not in out
    assert "warning: solid.velocity_gradient = quadratic" in err and "linear fit" in err
    assert main(["run", "cantilever", "--set", "geometry.length=0.01", "--end-time", "2e-5",
                 "--out", str(tmp_path / "thick")]) == 0
    out, err = capsys.readouterr()
    assert "warning" not in err


def test_cli_run_of_a_fluid_scene_reports_its_steps_and_error(tmp_path, capsys):
    assert main(["run", "hydrostatic", "--end-time", "0.004", "--out", str(tmp_path / "hs")]) == 0
    out, _ = capsys.readouterr()
    assert "fluid steps:" in out and "correction iterations per step" in out and "solid steps" not in out
    assert "error:" in out and "rho g H" in out


def test_cantilever_frequency_needs_one_reference_period():
    """A run shorter than one period of the reference frequency is not judged (its ripples would pass for a
    frequency: 0.03 s of the paper's beam once reported 105 Hz, +496 %); one that covers a few periods is."""
    values = load_scene("cantilever").values
    ref = cantilever.evaluate({"time": np.array([0.0, 1.0]), "tip_dz": np.zeros(2)}, values)["reference_hz"]

    def record(duration):
        t = np.linspace(0.0, duration, 600)
        return {"time": t, "tip_dz": 1e-4 * np.sin(2 * np.pi * ref * t) + 2e-6 * np.sin(2 * np.pi * 9 * ref * t),
                "tip_vy": np.zeros_like(t), "kinetic_energy": np.ones_like(t), "strain_energy": np.zeros_like(t)}

    short = cantilever.evaluate(record(0.5 / ref), values)
    assert short["error"] is None and short["frequency_hz"] is None
    assert "0.50 periods" in short["frequency_note"]
    full = cantilever.evaluate(record(5.0 / ref), values)
    assert full["error"] < 1e-3


def test_a_solid_cfl_past_the_quadratic_fits_tested_value_warns_and_follows_live_changes():
    """The fit's stable limit is lower than Gray's gradient's (docs/method.md, the solid's step factor)."""
    small = [("geometry.length", 0.01), ("solid.velocity_gradient", "quadratic")]
    assert not any("solid.cfl" in w for w in Simulation(load_scene("cantilever", small)).warnings)
    sim = Simulation(load_scene("cantilever", small + [("solid.cfl", 0.5)]))
    warned = [w for w in sim.warnings if "solid.cfl = 0.5" in w]
    assert len(warned) == 1 and f"{QUADRATIC_FIT_TESTED_CFL:g} or less" in warned[0]
    sim.apply({"solid.cfl": QUADRATIC_FIT_TESTED_CFL})
    assert not any("solid.cfl" in w for w in sim.warnings)
    sim.apply({"solid.cfl": 0.45})
    assert sum("solid.cfl = 0.45" in w for w in sim.warnings) == 1
    gray = Simulation(load_scene("cantilever", [("geometry.length", 0.01), ("solid.velocity_gradient", "sph"),
                                                ("solid.nodal_integration", "plain"),
                                                ("solid.pressure", "explicit"), ("solid.cfl", 0.5)]))
    assert not any("solid.cfl" in w for w in gray.warnings)
