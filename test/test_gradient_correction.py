"""The velocity gradient behind Hooke's law, plain (Gray 2001, the paper) and kernel-corrected (L K^-1).

On a block of particles a linear velocity field v = A r has gradient A everywhere. The plain SPH sum is exact
in the interior of a lattice only up to the kernel sum (about 0.99 at h = 1.3 dp) and is badly wrong at the free
surfaces, where the kernel is cut: there a rigid rotation shows up as strain, which is what made the paper's thin
beam too stiff in rotation (docs/validation/FINDINGS.md). The corrected gradient is exact for linear fields on
every particle, surface and corners included.
"""
import numpy as np

from sph_fsi_core.neighbours import NeighbourList, pair_kernel_values
from sph_fsi_core.solid_gray2001 import xsph_velocity_and_gradient


def _block_gradient(velocity_gradient, correct):
    dp, h = 1e-3, 1.3e-3
    g = (np.arange(6) + 0.5) * dp
    pos = np.ascontiguousarray(np.stack(np.meshgrid(g, g, g, indexing="ij"), -1).reshape(-1, 3))
    n = len(pos)
    vel = np.ascontiguousarray(pos @ velocity_gradient.T)
    mass = np.full(n, 1000.0 * dp ** 3)
    rho = np.full(n, 1000.0)
    nl = NeighbourList(2 * h, 0.1 * h, half=True)
    nl.build(pos, pos)
    w = np.zeros(nl.pairs)
    f = np.zeros(nl.pairs)
    pair_kernel_values(pos, pos, nl.start, nl.index, h, np.zeros(3), w, f)
    vhat = np.zeros((n, 3))
    grad = np.zeros((n, 3, 3))
    buf = np.zeros((2, n, 18))
    xsph_velocity_and_gradient(pos, np.zeros(3), mass, rho, vel, nl.start, nl.index, w, f, 0.5, vhat, grad, buf,
                               correct, np.zeros((n, 3, 3)))
    return pos, grad


def test_corrected_gradient_is_exact_everywhere():
    rng = np.random.default_rng(3)
    a = rng.normal(size=(3, 3))
    _, grad = _block_gradient(a, True)
    assert np.abs(grad - a).max() < 1e-9 * np.abs(a).max()


def test_plain_gradient_turns_rotation_into_strain_at_surfaces():
    spin = np.array([[0.0, 0.0, 1.0], [0.0, 0.0, 0.0], [-1.0, 0.0, 0.0]])   # rigid rotation about y
    pos, plain = _block_gradient(spin, False)
    _, corrected = _block_gradient(spin, True)
    strain_plain = 0.5 * (plain + plain.transpose(0, 2, 1))
    strain_corrected = 0.5 * (corrected + corrected.transpose(0, 2, 1))
    surface = (pos[:, 0] < 1e-3) | (pos[:, 2] < 1e-3)
    assert np.abs(strain_corrected).max() < 1e-9
    assert np.abs(strain_plain[surface]).max() > 0.1          # spurious shear of order 10-50 % of the spin


def test_momentum_pass_conserves_momentum_with_and_without_correction():
    """Each pair adds equal and opposite forces (half list), also with per-particle K^-1: sum_a m_a a_a = 0."""
    from sph_fsi_core.solid_gray2001 import momentum_rate
    rng = np.random.default_rng(5)
    dp, h = 1e-3, 1.3e-3
    g = (np.arange(5) + 0.5) * dp
    pos = np.stack(np.meshgrid(g, g, g, indexing="ij"), -1).reshape(-1, 3)
    pos = np.ascontiguousarray(pos + rng.normal(scale=0.05 * dp, size=pos.shape))
    n = len(pos)
    mass = np.full(n, 1e-6)
    rho = 1000.0 * (1 + 0.01 * rng.normal(size=n))
    vel = rng.normal(scale=0.01, size=(n, 3))
    sig = rng.normal(scale=1e3, size=(n, 6)) / rho[:, None] ** 2
    art = rng.normal(scale=1e2, size=(n, 6)) / rho[:, None] ** 2
    kinv = np.linalg.inv(np.eye(3) + 0.2 * rng.normal(size=(n, 3, 3)))
    kinv = np.ascontiguousarray(0.5 * (kinv + kinv.transpose(0, 2, 1)))
    nl = NeighbourList(2 * h, 0.1 * h, half=True)
    nl.build(pos, pos)
    for correct in (False, True):
        acc = np.zeros((n, 3))
        momentum_rate(pos, np.zeros(3), mass, rho, vel, sig, art, nl.start, nl.index, h, 176.0, 1.0, 1.0, 4,
                      1.0 / 0.2, np.zeros(3), acc, np.zeros(nl.pairs), np.zeros(nl.pairs), np.zeros((2, n, 18)),
                      correct, kinv)
        total = (mass[:, None] * acc).sum(axis=0)
        scale = (mass[:, None] * np.abs(acc)).sum()
        assert scale > 0
        assert np.abs(total).max() < 1e-12 * scale
