"""The quadratic fit's rows turned with the particle (`solid.fit_refresh: rotate`, sph_fsi_core/solid/fit_rotation.py):

- rows made on the paper's beam and turned by a rotation equal, to round-off, the rows remade from scratch on the beam
  rigidly turned by it (every particle: interior, surface, the linear fallback);
- the rotation followed step by step from a constant spin is the exact rotation (Rodrigues composes exactly about a
  fixed axis) and a pure spin accumulates no strain; a pure stretch accumulates its strain and no turn;
- only the particles past the limit are turned.
"""
import math

import numpy as np
import pytest

from sph_fsi_core.numerics.neighbours import NeighbourList
from sph_fsi_core.scene import load_scene
from sph_fsi_core.simulation import Simulation
from sph_fsi_core.solid import fit_rotation as fr
from sph_fsi_core.solid.fitted_gradient import MOMENT_COUNT, N_BASIS, mls_fit_rows


def _rotation(axis, angle):
    axis = np.asarray(axis, float) / np.linalg.norm(axis)
    k = np.array([[0.0, -axis[2], axis[1]], [axis[2], 0.0, -axis[0]], [-axis[1], axis[0], 0.0]])
    return np.eye(3) + math.sin(angle) * k + (1.0 - math.cos(angle)) * k @ k


@pytest.fixture(scope="module")
def beam():
    return Simulation(load_scene("cantilever", ["output.snapshot_interval=0", "solid.fit_refresh=rotate"]))


def _fit(sim, pos, hessian_rows):
    s, nb = sim.solid, sim.solid_phase.solver.neighbours
    lists = NeighbourList(nb.radius, nb.skin, period=sim.period, half=True)
    lists.build(pos, pos)
    rows = np.zeros((s.count, N_BASIS if hessian_rows else 3, N_BASIS))
    order = np.zeros(s.count, dtype=np.int64)
    mls_fit_rows(pos, sim.period, s.mass, s.rho, lists.start, lists.index, sim.h, rows, order,
                 np.zeros((2, s.count, MOMENT_COUNT)))
    return rows, order


@pytest.mark.parametrize("hessian_rows", [False, True])
def test_turned_rows_equal_rows_remade_on_the_turned_beam(beam, hessian_rows):
    pos = beam.solid.pos.copy()
    q = _rotation([1.0, 2.0, 3.0], 0.4)
    rows0, order = _fit(beam, pos, hessian_rows)
    remade, order_turned = _fit(beam, (pos - pos.mean(axis=0)) @ q.T, hessian_rows)
    assert np.array_equal(order, order_turned) and (order == 2).all()
    rotation = np.repeat(q[None], len(pos), axis=0)
    turned = np.zeros_like(rows0)
    fr.rotate_fit_rows(rows0, rotation, np.ones(len(pos)), 0.0, turned)
    scale = np.abs(remade).max(axis=(1, 2))[:, None, None]
    assert np.abs(turned - remade).max() < 1e-10 * scale.max()
    assert np.all(np.abs(turned - remade) <= 1e-9 * scale)
    assert np.abs(rows0 - remade).max() > 0.1 * scale.max()      # the turn does change the rows


def test_a_constant_spin_is_followed_exactly_and_strains_nothing():
    n, dt, steps = 3, 1e-3, 500
    omega = np.array([0.3, -1.2, 0.8])                     # rad/s
    grad_v = np.zeros((n, 3, 3))
    grad_v[:] = np.array([[0.0, -omega[2], omega[1]], [omega[2], 0.0, -omega[0]], [-omega[1], omega[0], 0.0]])
    rotation = np.repeat(np.eye(3)[None], n, axis=0)
    deformation = rotation.copy()
    strain, spin = np.zeros(n), np.zeros(n)
    for _ in range(steps):
        worst_strain, worst_spin = fr.follow_spin(grad_v, dt, rotation, deformation, strain, spin)
    exact = _rotation(omega, np.linalg.norm(omega) * dt * steps)
    assert np.abs(rotation - exact).max() < 1e-13
    # the deformation gradient of a spin by forward Euler grows as (1 + |w|^2 dt^2)^(steps / 2): a strain of
    # steps |w|^2 dt^2 / 2, nothing like the 0.77 rad turned
    assert worst_strain == pytest.approx(strain.max()) and strain.max() < steps * (omega @ omega) * dt ** 2
    assert worst_spin == pytest.approx(np.linalg.norm(omega) * dt * steps, rel=1e-12)


def test_a_stretch_strains_and_does_not_turn_and_a_vibration_leaves_no_strain():
    grad_v = np.zeros((2, 3, 3))
    grad_v[:, 0, 0], grad_v[:, 1, 1] = 2.0, -1.0           # 1/s
    rotation = np.repeat(np.eye(3)[None], 2, axis=0)
    deformation = rotation.copy()
    strain, spin = np.zeros(2), np.zeros(2)
    worst_strain, worst_spin = fr.follow_spin(grad_v, 1e-3, rotation, deformation, strain, spin)
    # F = diag(1.002, 0.999, 1): E = diag(F^2 - 1) / 2
    e = 0.5 * np.array([1.002 ** 2 - 1.0, 0.999 ** 2 - 1.0])
    assert worst_strain == pytest.approx(np.sqrt(e @ e), rel=1e-12) and worst_spin == 0.0
    assert np.array_equal(rotation[0], np.eye(3))
    fr.follow_spin(-grad_v, 1e-3, rotation, deformation, strain, spin)     # and back: second order is left
    assert strain.max() < 1e-5 < 1e-3 * math.sqrt(5.0)


def test_only_the_particles_past_the_limit_are_turned():
    rows0 = np.random.default_rng(3).normal(size=(4, 3, 9))
    rotation = np.repeat(_rotation([0.0, 0.0, 1.0], 0.5)[None], 4, axis=0)
    rows = rows0.copy()
    spin = np.array([0.0, 2e-4, 5e-5, 3e-4])
    fr.rotate_fit_rows(rows0, rotation, spin, 1e-4, rows)
    assert np.array_equal(rows[[0, 2]], rows0[[0, 2]]) and np.array_equal(spin, [0.0, 0.0, 5e-5, 0.0])
    assert not np.allclose(rows[[1, 3]], rows0[[1, 3]])
