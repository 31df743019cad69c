"""sph_fsi_core/precompile.py: a coupled scene's solid and fluid kernels compiled in two processes at once."""
import subprocess

import pytest

from sph_fsi_core import precompile
from sph_fsi_core.scene import load_scene


@pytest.mark.parametrize("scheme", ["quadratic_gradient", "gray2001", "quadratic_plain_artificial_stress"])
def test_the_solid_warm_up_runs_the_scenes_own_solid_code(scheme):
    """A coupled scene gets two parts: the small beam with the scene's code-selecting solid values (so it compiles the
    driver and pair variant the scene runs, not the beam's own scheme) and the dam break's fluid."""
    gate = load_scene("elastic_gate", [f"solid.scheme={scheme}"])
    parts = precompile.warm_up_parts(gate)
    assert [scene for scene, _ in parts] == ["cantilever", "dam_break"]
    solid_overrides = parts[0][1]
    assert set(solid_overrides) == set(precompile.SOLID_CODE_KEYS)
    beam = load_scene("cantilever", list(solid_overrides.items()))
    assert {k: beam[k] for k in precompile.SOLID_CODE_KEYS} == {k: gate[k] for k in precompile.SOLID_CODE_KEYS}
    fluid = load_scene(*parts[1])
    assert "fluid" in fluid.phases and "solid" not in fluid.phases


@pytest.mark.parametrize("scene", ["cantilever", "dam_break", "hydrostatic"])
def test_a_scene_with_one_phase_compiles_in_its_own_process(scene, monkeypatch):
    """Nothing to share out: no part, and no process started."""
    monkeypatch.setattr(subprocess, "Popen", _no_process)
    spec = load_scene(scene)
    assert precompile.warm_up_parts(spec) == []
    assert precompile.compile_in_parallel(spec, cpus=2) is None


def test_one_cpu_or_the_switch_keeps_it_in_process(monkeypatch):
    monkeypatch.setattr(subprocess, "Popen", _no_process)
    gate = load_scene("elastic_gate")
    both = precompile.warm_up_parts(gate)
    assert precompile.compile_in_parallel(gate, cpus=1, parts=both) is None
    monkeypatch.setenv(precompile.SWITCH_ENV, "0")
    assert precompile.compile_in_parallel(gate, cpus=2, parts=both) is None


def test_only_the_halves_not_cached_yet_are_compiled(monkeypatch):
    """A half whose entry kernel is cached is left out; with one half left there is nothing to run side by side."""
    gate = load_scene("elastic_gate")
    monkeypatch.setattr(precompile, "kernels_cached", lambda phases, fitted=True: "solid" in phases)
    assert [scene for scene, _ in precompile.uncached_parts(gate)] == ["dam_break"]
    monkeypatch.setattr(subprocess, "Popen", _no_process)
    assert precompile.compile_in_parallel(gate, cpus=2) is None
    monkeypatch.setattr(precompile, "kernels_cached", lambda phases, fitted=True: False)
    assert [scene for scene, _ in precompile.uncached_parts(gate)] == ["cantilever", "dam_break"]
    monkeypatch.setattr(precompile, "kernels_cached", lambda phases, fitted=True: None)   # cannot tell: compile
    assert len(precompile.uncached_parts(gate)) == 2


def test_a_failed_part_is_named_and_the_run_goes_on(monkeypatch):
    """Two real processes that fail at once (unknown scenes): each failure comes back as one line naming its scene
    and the error, and compile_cold_scene warns with it instead of raising."""
    monkeypatch.setattr(precompile, "uncached_parts", lambda spec: [("no_such_scene_a", {}), ("no_such_scene_b", {})])
    seconds, failures = precompile.compile_in_parallel(load_scene("elastic_gate"), cpus=2)
    assert seconds > 0.0
    assert len(failures) == 2
    assert failures[0].startswith("no_such_scene_a: exit status 1: ") and "no_such_scene_a" in failures[0][20:]
    assert failures[1].startswith("no_such_scene_b: exit status 1: ")
    said, warned = [], []
    precompile.compile_cold_scene(load_scene("elastic_gate"), said.append, warned.append)
    assert len(said) == 1 and "two processes" in said[0]
    assert len(warned) == 2 and all("the run compiles its part itself" in w for w in warned)


def _no_process(*args, **kwargs):
    raise AssertionError("no process should start")
