"""The clamped plate's set-up (config/clamped_plate.yaml, scenes/cases/clamped_plate.py): its particles, the load it
carries and its clamps."""
import math

import numpy as np
import pytest

from sph_fsi_core.scene import load_scene
from sph_fsi_core.scenes import BUILDERS
from sph_fsi_core.scenes.cases import clamped_plate
from sph_fsi_core.simulation import Simulation


def built(*overrides):
    spec = load_scene("clamped_plate", list(overrides))
    return spec, BUILDERS[spec.builder].build(spec.values)


def test_lattice_clamps_and_probe():
    spec, b = built()
    dp = spec["numerics.spacing"]
    c = clamped_plate.layer_counts(spec.values)
    assert (c["nx"], c["nz"], c["nc"]) == (80, 4, 4)
    assert b.solid.moving_count == 80 * 4 * c["ny"]
    assert b.solid.count == (80 + 2 * 4) * 4 * c["ny"]
    assert b.period[1] == pytest.approx(c["ny"] * dp)
    fixed = b.solid.pos[~b.solid.movable]
    assert np.all((fixed[:, 0] < 0.0) | (fixed[:, 0] > spec["geometry.span"]))
    # mid-span, mid-thickness: two columns by two layers across the slab, centred on (L/2, t/2)
    probe = b.probes[0]
    assert len(probe.indices) == 2 * 2 * c["ny"]
    assert probe.reference_position[[0, 2]] == pytest.approx([0.5, 0.025])


@pytest.mark.parametrize("gradient", [0.0, 5000.0])
def test_load_is_the_pressure_integrated_over_the_top_face(gradient):
    spec, b = built(f"geometry.load_gradient={gradient}")
    c = clamped_plate.layer_counts(spec.values)
    width, span, p0 = c["ny"] * spec["numerics.spacing"], spec["geometry.span"], spec["geometry.load_pressure"]
    total = b.solid_load.sum(axis=0)
    # the midpoint rule is exact for a linear pressure: -(p0 L + g L^2 / 2) W, all of it on the span's top layer
    assert total[2] == pytest.approx(-(p0 * span + 0.5 * gradient * span ** 2) * width, rel=1e-12)
    assert total[0] == 0.0 and total[1] == 0.0
    loaded = np.flatnonzero(b.solid_load[:, 2])
    assert np.all(b.solid.movable[loaded])
    assert np.allclose(b.solid.pos[loaded, 2], spec["geometry.thickness"] - 0.5 * spec["numerics.spacing"])


def test_mirrored_clamp_maps_each_end_across_its_own_face():
    spec, b = built()
    span = spec["geometry.span"]
    pos, mirror = b.solid.pos, b.clamp_mirror
    ghosts = np.flatnonzero(mirror >= 0)
    assert len(ghosts) == (~b.solid.movable).sum()      # every clamp particle is some body particle's image
    left = pos[ghosts, 0] < 0.0
    image = pos[mirror[ghosts]]
    assert np.allclose(image[left, 0], -pos[ghosts[left], 0])
    assert np.allclose(image[~left, 0], 2.0 * span - pos[ghosts[~left], 0])
    assert np.allclose(image[:, 1:], pos[ghosts, 1:])


def test_load_ramps_in_and_damping_follows_the_first_mode():
    spec = load_scene("clamped_plate")
    sim = Simulation(spec)
    omega = clamped_plate.first_mode_omega(spec.values)
    assert sim.solid_phase.load_ramp_time == pytest.approx(2.0 * 2.0 * math.pi / omega)
    assert sim.solid_phase.damping_rate == pytest.approx(2.0 * omega)
    full = sim.solid_phase.load / sim.solid.mass[:, None]
    assert np.allclose(sim.solid_phase.prescribed_acceleration(0.5 * sim.solid_phase.load_ramp_time), 0.5 * full)
    assert np.allclose(sim.solid_phase.prescribed_acceleration(2.0 * sim.solid_phase.load_ramp_time), full)
    assert not np.any(sim.solid_phase.prescribed_acceleration(0.0))
