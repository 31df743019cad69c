"""The memory guard (sph_fsi_core/memory_guard.py): every builder's particle count, computed without making the
particles, equals what it builds; a scene too large for the memory, or above --max-particles, is refused before
anything is built, with one line naming numerics.spacing, the particles and the memory; scene-file errors name the
file."""
import os
import subprocess
import sys

import pytest

from sph_fsi_core import memory_guard
from sph_fsi_core.scene import builtin_scenes, load_scene
from sph_fsi_core.scenes import BUILDERS
from sph_fsi_core.schema import SceneError

# a second spacing per scene, besides its file's: other layer counts (walls, clamps, slabs) than the default's
OTHER_SPACING = {"cantilever": 0.0005, "clamped_plate": 0.05 / 6, "hydrostatic": 0.0025, "dam_break": 0.05715 / 10,
                 "elastic_gate": 0.0008, "antoci_gate": 0.005 / 3, "antoci_gate_static": 0.005 / 3,
                 "antoci_gate_loaded": 0.005 / 3, "hydrostatic_plate": 0.05 / 4,
                 "cantilever_loaded": 0.0005, "lobovsky_dam_break": 0.02, "spheric2_dam_break": 0.05,
                 "box_pushed_into_tank": 0.02, "standing_wave": 0.0025, "sliding_water": 0.0025,
                 "box_moved_through_water": 0.005, "jet_on_wall": 0.005}


@pytest.mark.parametrize("scene", sorted(builtin_scenes()))
def test_particle_counts_equal_what_the_builder_makes(scene):
    for extra in ([], [f"numerics.spacing={OTHER_SPACING[scene]}"]):
        spec = load_scene(scene, extra)
        builder = BUILDERS[spec.builder]
        built = builder.build(spec.values)
        made = {phase: getattr(built, phase).count for phase in ("solid", "fluid", "walls")
                if getattr(built, phase) is not None}
        if spec.builder == "geometry":    # counted from the parts' volumes and surfaces (test_geometry.py)
            if built.release_walls is not None:
                made["walls"] = made.get("walls", 0) + built.release_walls.count
            counted = builder.particle_counts(spec.values)
            assert counted.keys() == made.keys(), (scene, extra)
            for phase, n in made.items():
                assert n <= counted[phase] * 1.1 and counted[phase] <= 2.0 * n, (scene, extra, phase)
            continue
        assert builder.particle_counts(spec.values) == made, (scene, extra)


def test_every_builder_counts_its_particles():
    assert all(callable(b.particle_counts) for b in BUILDERS.values())


def test_a_scene_beyond_the_memory_is_refused_before_building(monkeypatch):
    """The cantilever at 10 um: 960,984,000 particles, about 4,900 GiB; refused in the time it takes to count."""
    monkeypatch.delenv(memory_guard.MAX_PARTICLES_ENV, raising=False)
    with pytest.raises(SceneError) as info:
        load_scene("cantilever", ["numerics.spacing=1e-5"])
    message = str(info.value)
    assert "numerics.spacing = 1e-05 m" in message and "960,960,000 particles" in message
    particles, need = memory_guard.estimate({"solid": 960_960_000})
    assert f"about {need / 2 ** 30:,.1f} GiB" in message and "GiB of memory is available" in message
    assert need / 2 ** 30 > 4_000


def test_the_estimate_follows_the_available_memory(monkeypatch):
    """The same scene passes or not depending on what the machine has: the limit is the estimate, not a constant."""
    monkeypatch.delenv(memory_guard.MAX_PARTICLES_ENV, raising=False)
    spec = load_scene("elastic_gate")
    _, need = memory_guard.estimate(BUILDERS[spec.builder].particle_counts(spec.values))
    monkeypatch.setattr(memory_guard, "available_bytes", lambda: need - 1)
    with pytest.raises(SceneError, match="elastic_gate.yaml: numerics.spacing = 0.001 m: the scene would have"):
        load_scene("elastic_gate")
    monkeypatch.setattr(memory_guard, "available_bytes", lambda: need + 1)
    load_scene("elastic_gate")


def test_max_particles_overrides_the_estimate(monkeypatch):
    monkeypatch.setenv(memory_guard.MAX_PARTICLES_ENV, "1055")    # the beam's 960 and the mirrored clamp's 96
    with pytest.raises(SceneError, match=r"1,056 particles \(solid 1,056\), above the limit"):
        load_scene("cantilever")
    monkeypatch.setenv(memory_guard.MAX_PARTICLES_ENV, "1056")
    load_scene("cantilever")
    monkeypatch.setenv(memory_guard.MAX_PARTICLES_ENV, "many")
    with pytest.raises(SceneError, match="SPH_FSI_MAX_PARTICLES = 'many': not a particle count"):
        load_scene("cantilever")


def _cli(*args):
    env = {k: v for k, v in os.environ.items() if k != memory_guard.MAX_PARTICLES_ENV}
    return subprocess.run([sys.executable, "-m", "sph_fsi.cli", *args], capture_output=True, text=True, env=env,
                          timeout=120)


def test_cli_refuses_with_exit_2_and_one_line(tmp_path):
    r = _cli("run", "cantilever", "--set", "numerics.spacing=1e-5", "--out", str(tmp_path / "out"))
    assert r.returncode == 2
    lines = r.stderr.strip().splitlines()
    assert len(lines) == 1 and "numerics.spacing = 1e-05 m" in lines[0] and "GiB" in lines[0], r.stderr
    assert not (tmp_path / "out").exists()
    r = _cli("run", "cantilever", "--max-particles", "100", "--out", str(tmp_path / "out"))
    assert r.returncode == 2 and "above the limit" in r.stderr and "--max-particles" in r.stderr, r.stderr


def test_scene_file_errors_name_the_file(tmp_path):
    binary = tmp_path / "binary.yaml"
    binary.write_bytes(b"solid:\n  young_modulus: \xff\xfe\n")
    with pytest.raises(SceneError) as info:
        load_scene(str(binary))
    assert str(info.value).startswith(f"scene file {str(binary)!r}: not UTF-8 text") and "allowed" in str(info.value)
    bad_value = tmp_path / "bad_value.yaml"
    block = "parts:\n  - {name: block, role: solid, shape: box, size: [0.01, 0.004, 0.004]}\n"
    bad_value.write_text("scene:\n  builder: geometry\nsolid:\n  young_modulus: -3\n" + block)
    with pytest.raises(SceneError, match=f"^{bad_value}: solid.young_modulus = -3: out of range"):
        load_scene(str(bad_value))
    not_a_section = tmp_path / "not_a_section.yaml"
    not_a_section.write_text("scene:\n  builder: geometry\nsolid: 3\n" + block)
    with pytest.raises(SceneError, match=f"^{not_a_section}: solid: expected a mapping"):
        load_scene(str(not_a_section))
    # an override's error is the override's: it names the key, not the file
    with pytest.raises(SceneError, match="^solid.young_modulus = -1: out of range"):
        load_scene("cantilever", ["solid.young_modulus=-1"])
    r = _cli("run", str(binary), "--out", str(tmp_path / "out"))
    assert r.returncode == 2 and str(binary) in r.stderr and "UTF-8" in r.stderr, r.stderr
