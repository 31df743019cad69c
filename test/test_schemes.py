"""The solid's named schemes (`solid.scheme`, sph_fsi_core/solid/schemes.py): each expands to its documented detailed
keys, an explicitly set detailed key beats its scheme, an unknown name is refused naming the key and the allowed
names, every built-in scene with a solid names its scheme, and a scheme set later is expanded again."""
from pathlib import Path

import pytest

from sph_fsi_core.scene import builtin_scenes, load_scene, parse_yaml
from sph_fsi_core.scenes import BUILDERS
from sph_fsi_core.schema import SOLID, SceneError
from sph_fsi_core.simulation import Simulation
from sph_fsi_core.solid.schemes import DEFAULT_SCHEME, SCHEME_KEYS, SCHEMES

REPO = Path(__file__).resolve().parents[1]

# What docs/method.md ("Solid schemes") documents; the table here is written out so that a change to schemes.py
# that would change the validated runs shows up as a failing test, not as a silent change of results.
DOCUMENTED = {
    "quadratic_gradient": {"solid.velocity_gradient": "quadratic", "solid.nodal_integration": "gradient",
                           "solid.artificial_stress_epsilon": 0.0, "solid.cfl": 0.25, "solid.clamp": "mirrored",
                           "solid.pressure": "implicit", "solid.fit_refresh": "rotate"},
    "quadratic_plain": {"solid.velocity_gradient": "quadratic", "solid.nodal_integration": "plain",
                        "solid.artificial_stress_epsilon": 0.0, "solid.cfl": 0.25, "solid.clamp": "fixed",
                        "solid.pressure": "explicit", "solid.fit_refresh": "remake"},
    "quadratic_plain_artificial_stress": {"solid.velocity_gradient": "quadratic", "solid.nodal_integration": "plain",
                                          "solid.artificial_stress_epsilon": 0.15, "solid.cfl": 0.25,
                                          "solid.clamp": "fixed", "solid.pressure": "explicit",
                                          "solid.fit_refresh": "remake"},
    "gray2001": {"solid.velocity_gradient": "sph", "solid.nodal_integration": "plain",
                 "solid.artificial_stress_epsilon": 0.15, "solid.cfl": 0.5, "solid.clamp": "fixed",
                 "solid.pressure": "explicit", "solid.fit_refresh": "remake"},
}
# the scheme each built-in scene with a solid runs: the default, every scene's (the verification issue's item 4)
SCENE_SCHEMES = {name: DEFAULT_SCHEME for name in ("cantilever", "elastic_gate", "antoci_gate", "clamped_plate",
                                                   "hydrostatic_plate", "antoci_gate_static", "antoci_gate_loaded",
                                                   "cantilever_loaded")}
SMALL_BEAM = [("geometry.length", 0.004)]


def _scheme_values(spec):
    return {k: spec[k] for k in SCHEME_KEYS}


def test_the_table_is_the_documented_one_and_every_scheme_sets_every_key():
    assert set(SCHEMES) == set(DOCUMENTED)
    for name, scheme in SCHEMES.items():
        assert scheme.name == name and scheme.summary
        assert scheme.values == DOCUMENTED[name], name
        assert set(scheme.values) == set(SCHEME_KEYS)
    method = (REPO / "docs" / "method.md").read_text()
    assert "## Solid schemes" in method
    section = method[method.index("## Solid schemes"):]
    for name in SCHEMES:
        assert f"`{name}`" in section, name


@pytest.mark.parametrize("scene", ["cantilever", "elastic_gate", "antoci_gate"])
@pytest.mark.parametrize("name", sorted(DOCUMENTED))
def test_each_scheme_expands_to_its_documented_values(scene, name):
    spec = load_scene(scene, [f"solid.scheme={name}"])
    assert spec["solid.scheme"] == name
    assert _scheme_values(spec) == DOCUMENTED[name]
    for key, value in DOCUMENTED[name].items():
        assert type(spec[key]) is type(value), key


def test_the_schema_default_is_a_scheme_and_the_detailed_defaults_are_its_values():
    params = {p.key: p for p in SOLID}
    assert params["solid.scheme"].default == DEFAULT_SCHEME
    for key in SCHEME_KEYS:
        assert params[key].default == SCHEMES[DEFAULT_SCHEME].values[key], key


# a scene with a solid and nothing else said: one block of the solid (everything else by default)
BLOCK = "parts:\n  - {name: block, role: solid, shape: box, size: [0.01, 0.004, 0.004]}\n"


def _write(tmp_path, text, name="block.yaml"):
    p = tmp_path / name
    p.write_text(text + BLOCK)
    return str(p)


def test_a_file_without_a_scheme_gets_the_default(tmp_path):
    spec = load_scene(_write(tmp_path, "solid:\n  density: 1200.0\n"))
    assert spec["solid.scheme"] == DEFAULT_SCHEME
    assert _scheme_values(spec) == DOCUMENTED[DEFAULT_SCHEME]


def test_an_explicit_detailed_key_beats_the_scheme(tmp_path):
    # in the file
    path = _write(tmp_path, "solid:\n  scheme: gray2001\n  artificial_stress_epsilon: 0.0\n")
    spec = load_scene(path)
    assert spec["solid.artificial_stress_epsilon"] == 0.0
    assert spec["solid.velocity_gradient"] == "sph" and spec["solid.cfl"] == 0.5      # the rest from the scheme
    # the order within the file does not matter
    (tmp_path / "other").mkdir()
    spec2 = load_scene(_write(tmp_path / "other", "solid:\n  artificial_stress_epsilon: 0.0\n  scheme: gray2001\n"))
    assert spec2.values == spec.values
    # by --set, over the file's scheme
    spec = load_scene("elastic_gate", ["solid.cfl=0.3"])
    assert spec["solid.scheme"] == "quadratic_gradient" and spec["solid.cfl"] == 0.3
    assert spec["solid.velocity_gradient"] == "quadratic" and spec["solid.clamp"] == "mirrored"
    # a detailed key in the file survives a scheme given by --set
    spec = load_scene(path, ["solid.scheme=quadratic_plain"])
    assert spec["solid.artificial_stress_epsilon"] == 0.0
    assert spec["solid.velocity_gradient"] == "quadratic" and spec["solid.cfl"] == 0.25
    # a detailed key by --set beats a scheme by --set, whichever comes first
    for overrides in (["solid.scheme=gray2001", "solid.cfl=0.3"], ["solid.cfl=0.3", "solid.scheme=gray2001"]):
        spec = load_scene("cantilever", overrides)
        assert spec["solid.cfl"] == 0.3 and spec["solid.velocity_gradient"] == "sph"
    # an explicit value equal to the default still counts as set
    spec = load_scene("cantilever", [("solid.cfl", 0.25), ("solid.scheme", "gray2001")])
    assert spec["solid.cfl"] == 0.25


@pytest.mark.parametrize("bad", ["grey2001", "sph", "", "Gray2001"])
def test_an_unknown_scheme_is_refused_naming_the_key_and_the_allowed_values(tmp_path, bad):
    for source, overrides in (("cantilever", [("solid.scheme", bad)]),
                              (_write(tmp_path, f"solid:\n  scheme: '{bad}'\n"), [])):
        with pytest.raises(SceneError) as info:
            load_scene(source, overrides)
        message = str(info.value)
        # a key set in a scene file names the file first (scene.py)
        assert message.startswith("solid.scheme" if source == "cantilever" else f"{source}: solid.scheme"), message
        assert "allowed" in message, message
        for name in SCHEMES:
            assert repr(name) in message, (name, message)
    with pytest.raises(SceneError, match="solid.scheme"):
        load_scene("cantilever", [("solid.scheme", 3)])


def test_every_builtin_scene_with_a_solid_names_its_scheme_and_only_that():
    scenes = builtin_scenes()
    with_solid = []
    for name, path in scenes.items():
        tree = parse_yaml(path.read_text(), origin=str(path))
        if "solid" not in load_scene(name).phases:      # a geometry scene's phases follow from its parts
            assert "solid" not in tree, name
            continue
        with_solid.append(name)
        solid = tree.get("solid", {})
        assert "scheme" in solid, f"{name}: no solid.scheme"
        assert name in SCENE_SCHEMES, f"{name}: a new scene with a solid; add the scheme it was validated with here"
        assert solid["scheme"] == SCENE_SCHEMES[name], name
        # a built-in scene runs its scheme as validated: none of the scheme's keys set beside it
        assert not {k.split(".", 1)[1] for k in SCHEME_KEYS} & set(solid), name
        assert _scheme_values(load_scene(name)) == DOCUMENTED[SCENE_SCHEMES[name]]
    assert sorted(with_solid) == sorted(SCENE_SCHEMES)


def test_builders_set_a_scheme_not_its_keys():
    """A builder's DEFAULTS come before the scheme is expanded: a detailed key there would be silently replaced."""
    for name, builder in BUILDERS.items():
        defaults = builder.defaults
        assert not set(SCHEME_KEYS) & set(defaults), name
        if "solid.scheme" in defaults:
            assert defaults["solid.scheme"] in SCHEMES, name


def test_a_new_scheme_through_with_overrides_is_expanded_again_under_the_explicit_keys():
    spec = load_scene("elastic_gate")
    assert _scheme_values(spec) == DOCUMENTED["quadratic_gradient"]
    plain = spec.with_overrides({"solid.scheme": "quadratic_plain"})
    assert _scheme_values(plain) == DOCUMENTED["quadratic_plain"]
    assert plain["solid.young_modulus"] == spec["solid.young_modulus"]     # the rest as before
    back = plain.with_overrides({"solid.scheme": "quadratic_gradient"})
    assert back.values == spec.values
    # an explicit detailed key (file, --set or an earlier override) stays through later scheme changes
    tuned = load_scene("elastic_gate", ["solid.artificial_stress_epsilon=0.05"])
    tuned = tuned.with_overrides({"solid.cfl": 0.3})
    for name in SCHEMES:
        other = tuned.with_overrides({"solid.scheme": name})
        assert other["solid.artificial_stress_epsilon"] == 0.05 and other["solid.cfl"] == 0.3, name
        assert other["solid.velocity_gradient"] == DOCUMENTED[name]["solid.velocity_gradient"], name
        assert other["solid.nodal_integration"] == DOCUMENTED[name]["solid.nodal_integration"], name


def test_the_scheme_is_a_declared_key_that_waits_for_a_reset():
    """Declared like every other key (the node's parameter descriptors come from the same Param): a string with
    its choices, and a rebuild key, since it may change the velocity gradient and the nodal integration."""
    p = load_scene("cantilever").schema.params["solid.scheme"]
    assert p.kind == "str" and p.choices == tuple(SCHEMES) and p.rebuild and p.description
    assert p.coerce("gray2001") == "gray2001"
    assert all(name in p.range_text() for name in SCHEMES)
    assert all(name in p.description for name in SCHEMES)
    assert "solid.scheme" not in load_scene("dam_break").schema.params


def test_simulation_apply_defers_a_scheme_change_to_the_reset_and_keeps_explicit_keys():
    sim = Simulation(load_scene("cantilever", SMALL_BEAM + [("solid.cfl", 0.3)]))
    assert sim.solid_phase.solver.params.gradient_order == 2 and sim.solid_phase.solver.params.cell_moment > 0.0
    live_spec, deferred = sim.check({"solid.scheme": "gray2001"})
    assert deferred == ["solid.scheme"]
    assert sim.apply({"solid.scheme": "gray2001"}) == ["solid.scheme"]
    assert sim.spec["solid.scheme"] == "quadratic_gradient" and sim.pending == {"solid.scheme": "gray2001"}
    sim.reset()
    assert sim.spec["solid.scheme"] == "gray2001"
    assert _scheme_values(sim.spec) == {**DOCUMENTED["gray2001"], "solid.cfl": 0.3}      # cfl was set explicitly
    assert sim.solid_phase.solver.params.gradient_order != 2 and sim.solid_phase.solver.params.cell_moment == 0.0
    assert not sim.warnings, sim.warnings
