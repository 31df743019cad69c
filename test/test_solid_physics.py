"""Per-particle physics of the elastic solid (sph_fsi_core.solid.gray2001): material constants, the Jaumann
stress rate, pressure / sigma over rho^2 / Gray's artificial stress, and the strain energy.

The pair passes (XSPH and velocity gradient, continuity, momentum) are not tested here: their signatures are
about to change."""
import math
import re

import numpy as np
import pytest

from sph_fsi_core.solid.gray2001 import jaumann_stress_rate, material_constants, strain_energy, stress_terms
from sph_fsi_core.numerics.tensors import to_matrices

E_PAPER, NU_PAPER, RHO_PAPER = 1.859e6, 0.49, 1000.0


def _pack(m):
    """(N, 3, 3) or (3, 3) symmetric -> (N, 6) in XX, YY, ZZ, XY, XZ, YZ order."""
    m = np.asarray(m)
    if m.ndim == 2:
        m = m[None]
    return np.ascontiguousarray(np.stack([m[:, 0, 0], m[:, 1, 1], m[:, 2, 2], m[:, 0, 1], m[:, 0, 2], m[:, 1, 2]],
                                         axis=1))


def _rotation(axis, theta):
    axis = np.asarray(axis, float) / np.linalg.norm(axis)
    k = np.array([[0, -axis[2], axis[1]], [axis[2], 0, -axis[0]], [-axis[1], axis[0], 0]])
    return np.eye(3) + math.sin(theta) * k + (1 - math.cos(theta)) * k @ k


def _random_symmetric(rng, n, scale=1.0):
    m = rng.normal(size=(n, 3, 3)) * scale
    return 0.5 * (m + np.transpose(m, (0, 2, 1)))


# ---- material constants ------------------------------------------------------------------------------------

@pytest.mark.parametrize("e, nu, rho", [(E_PAPER, NU_PAPER, RHO_PAPER), (2.0e11, 0.3, 7800.0), (1.0e6, 0.0, 1.0),
                                        (5.0e5, 0.4999, 1100.0)])
def test_material_constants(e, nu, rho):
    k, g, c0 = material_constants(e, nu, rho)
    assert k == pytest.approx(e / (3.0 * (1.0 - 2.0 * nu)), rel=1e-14)
    assert g == pytest.approx(e / (2.0 * (1.0 + nu)), rel=1e-14)
    assert c0 == pytest.approx(math.sqrt(k / rho), rel=1e-14)
    # the usual identity E = 9 K G / (3 K + G)
    assert 9.0 * k * g / (3.0 * k + g) == pytest.approx(e, rel=1e-12)


def test_paper_sound_speed():
    """METHOD.md: c0 = 176 m/s for the paper's rubber (E = 1.859 MPa, nu = 0.49, rho = 1000). Measured 176.0208."""
    k, g, c0 = material_constants(E_PAPER, NU_PAPER, RHO_PAPER)
    assert abs(c0 - 176.0) < 0.005 * 176.0
    assert c0 == pytest.approx(176.02083, abs=1e-4)
    assert k == pytest.approx(3.0983333e7, rel=1e-7)
    assert g == pytest.approx(6.2382550e5, rel=1e-7)


# ---- Jaumann stress rate -----------------------------------------------------------------------------------

def _jaumann(grad_v, stress, g):
    out = np.zeros_like(stress)
    jaumann_stress_rate(np.ascontiguousarray(grad_v), np.ascontiguousarray(stress), g, out)
    return out


def _jaumann_numpy(grad_v, stress, g):
    s = to_matrices(stress)
    d = 0.5 * (grad_v + np.transpose(grad_v, (0, 2, 1)))
    om = 0.5 * (grad_v - np.transpose(grad_v, (0, 2, 1)))
    tr = np.trace(d, axis1=1, axis2=2)[:, None, None]
    rate = 2.0 * g * (d - tr / 3.0 * np.eye(3)) + s @ np.transpose(om, (0, 2, 1)) + om @ s
    return _pack(rate)


def test_jaumann_rigid_rotation_without_stress_is_zero():
    rng = np.random.default_rng(1)
    w = rng.normal(size=(20, 3, 3)) * 50.0
    w = w - np.transpose(w, (0, 2, 1))          # antisymmetric: a rigid spin
    out = _jaumann(w, np.zeros((20, 6)), 6.2e5)
    assert np.all(out == 0.0)


def test_jaumann_uniform_strain_rate():
    """L = D symmetric (no spin): dS = 2G (D - tr(D)/3 I) exactly, whatever the stress."""
    rng = np.random.default_rng(2)
    g = 6.2382550e5
    d = _random_symmetric(rng, 30, 3.0)
    stress = _pack(_random_symmetric(rng, 30, 1e4))
    out = _jaumann(d, stress, g)
    expected = _pack(2.0 * g * (d - np.trace(d, axis1=1, axis2=2)[:, None, None] / 3.0 * np.eye(3)))
    assert np.allclose(out, expected, rtol=1e-14, atol=1e-14 * np.abs(expected).max())
    # the result is traceless
    assert np.abs(out[:, :3].sum(axis=1)).max() < 1e-12 * np.abs(out).max()
    # a pure volumetric rate gives no deviatoric stress rate
    out = _jaumann(np.repeat(np.eye(3)[None] * 7.0, 3, axis=0), np.zeros((3, 6)), g)
    assert np.abs(out).max() < 1e-9 * g


def test_jaumann_against_numpy():
    rng = np.random.default_rng(3)
    g = 1.7e5
    for scale_l, scale_s in ((1.0, 1.0), (100.0, 1e5), (1e-3, 1e6)):
        grad_v = rng.normal(size=(50, 3, 3)) * scale_l
        stress = _pack(_random_symmetric(rng, 50, scale_s))
        out = _jaumann(grad_v, stress, g)
        ref = _jaumann_numpy(grad_v, stress, g)
        assert np.abs(out - ref).max() <= 1e-12 * np.abs(ref).max()


def test_jaumann_rotation_term_alone_against_numpy():
    """G = 0 isolates S Omega^T + Omega S (the term a sign slip would break) for single spins about x, y, z."""
    rng = np.random.default_rng(4)
    stress = _pack(_random_symmetric(rng, 1, 1e3))
    for i, j in ((0, 1), (0, 2), (1, 2)):
        L = np.zeros((1, 3, 3))
        L[0, i, j] = 2.0
        out = _jaumann(L, stress, 0.0)
        ref = _jaumann_numpy(L, stress, 0.0)
        assert np.abs(ref).max() > 0
        assert np.abs(out - ref).max() <= 1e-13 * np.abs(ref).max()


@pytest.mark.parametrize("axis", [(0, 0, 1), (1, 0, 0), (1.0, -2.0, 0.5)])
def test_jaumann_objectivity_quarter_turn(axis):
    """A body spinning rigidly (L = W constant, antisymmetric; velocity v = W x) for a quarter turn: integrating
    dS/dt by RK4 must carry S0 to Q S0 Q^T with Q = exp(W t) (the stress turns with the material), keeping the
    invariants tr S and S:S."""
    omega = 2.0 * math.pi * 3.0              # rad/s
    n = np.asarray(axis, float) / np.linalg.norm(axis)
    w = omega * np.array([[0, -n[2], n[1]], [n[2], 0, -n[0]], [-n[1], n[0], 0]])
    grad_v = w[None]
    t_end = 0.25 * 2.0 * math.pi / omega
    steps = 400
    dt = t_end / steps
    rng = np.random.default_rng(5)
    s0m = _random_symmetric(rng, 1, 1e4)[0]
    s0m[2, 2] += 3e4                          # give it a trace too
    s = _pack(s0m)
    g = 6.2e5
    for _ in range(steps):
        k1 = _jaumann(grad_v, s, g)
        k2 = _jaumann(grad_v, s + 0.5 * dt * k1, g)
        k3 = _jaumann(grad_v, s + 0.5 * dt * k2, g)
        k4 = _jaumann(grad_v, s + dt * k3, g)
        s = s + dt / 6.0 * (k1 + 2 * k2 + 2 * k3 + k4)
    q = _rotation(n, omega * t_end)
    expected = q @ s0m @ q.T
    got = to_matrices(s)[0]
    scale = np.linalg.norm(s0m)
    assert np.linalg.norm(got - expected) < 1e-6 * scale, (got, expected)
    assert np.trace(got) == pytest.approx(np.trace(s0m), rel=1e-9)
    assert np.sum(got * got) == pytest.approx(np.sum(s0m * s0m), rel=1e-9)
    # and it did turn: a quarter turn moves a general stress by O(|S|)
    assert np.linalg.norm(got - s0m) > 0.1 * scale


# ---- pressure, sigma / rho^2, artificial stress ------------------------------------------------------------

def _eig_work(n):
    """Scratch for stress_terms: rows 0-2 matrix, 3-5 eigenvectors (identity: cold start), 6 eigenvalues, then
    solver scratch. The row count is read from the docstring's '(N, rows, 3)' (it has changed before); too many
    rows is harmless, too few would be an out-of-bounds write in compiled code, hence at least 16."""
    found = re.search(r"eig_work` \(N, (\d+), 3\)", stress_terms.py_func.__doc__ or "")
    rows = max(int(found.group(1)) if found else 0, 16)
    work = np.zeros((n, rows, 3))
    work[:, 3:6] = np.eye(3)
    return work


def _stress_terms(stress, rho, rho0, c0_squared, art_eps):
    n = len(stress)
    pressure = np.zeros(n)
    sor2 = np.zeros((n, 6))
    art = np.full((n, 6), np.nan)
    eig_work = _eig_work(n)
    stress_terms(np.ascontiguousarray(stress, dtype=float), np.asarray(rho, float), rho0, c0_squared, art_eps,
                 pressure, sor2, art, eig_work)
    return pressure, sor2, art, eig_work


def test_pressure_and_sigma_over_rho2():
    rng = np.random.default_rng(6)
    n = 40
    rho0 = 1000.0
    c0_squared = 176.0 ** 2
    rho = rho0 * (1.0 + rng.uniform(-0.01, 0.01, n))
    stress = _pack(_random_symmetric(rng, n, 2e3))
    p, sor2, _, _ = _stress_terms(stress, rho, rho0, c0_squared, 0.3)
    assert np.allclose(p, c0_squared * (rho - rho0), rtol=1e-14, atol=1e-9)
    sigma = to_matrices(stress) - p[:, None, None] * np.eye(3)
    expected = _pack(sigma / rho[:, None, None] ** 2)
    assert np.allclose(sor2, expected, rtol=1e-14, atol=1e-14 * np.abs(expected).max())


def test_artificial_stress_uniaxial_tension():
    """Principal stresses (+2, -1, 0) along x, y, z: only the tensile one gets R = -eps sigma / rho^2."""
    eps, rho0 = 0.3, 1000.0
    stress = np.array([[2.0, -1.0, 0.0, 0.0, 0.0, 0.0]])
    _, _, art, _ = _stress_terms(stress, [rho0], rho0, 176.0 ** 2, eps)   # rho = rho0: p = 0
    expected = np.array([[-eps * 2.0 / rho0 ** 2, 0, 0, 0, 0, 0]])
    assert np.allclose(art, expected, rtol=1e-14, atol=1e-15 * eps * 2.0 / rho0 ** 2)
    # the same with a pressure: rho > rho0 gives p > 0, sigma = S - p I
    rho = 1000.01
    c2 = 100.0
    p = c2 * (rho - rho0)                     # 1.0 Pa (to round-off)
    stress = np.array([[2.0 + p, -1.0 + p, 0.0 + p, 0.0, 0.0, 0.0]])
    _, _, art, _ = _stress_terms(stress, [rho], rho0, c2, eps)
    assert art[0, 0] == pytest.approx(-eps * 2.0 / rho ** 2, rel=1e-9)
    assert np.abs(art[0, 1:]).max() < 1e-12 * abs(art[0, 0])


def test_artificial_stress_rotated_tension_against_eigh():
    rng = np.random.default_rng(7)
    eps, rho0 = 0.3, 1000.0
    n = 25
    mats = []
    for i in range(n):
        q = _rotation(rng.normal(size=3), rng.uniform(0, 2 * math.pi))
        lam = np.array([3.0, -1.0, 0.5]) * 10.0 ** rng.uniform(-1, 5)
        if i % 5 == 0:
            lam = np.array([2.0, 2.0, -1.0])  # a repeated tensile eigenvalue
        mats.append(q @ np.diag(lam) @ q.T)
    mats = np.array(mats)
    rho = rho0 * (1.0 + rng.uniform(-1e-3, 1e-3, n))
    c2 = 50.0
    p = c2 * (rho - rho0)
    stress = _pack(mats + p[:, None, None] * np.eye(3))   # so that sigma = S - p I = mats
    _, _, art, _ = _stress_terms(stress, rho, rho0, c2, eps)
    for a in range(n):
        lam, v = np.linalg.eigh(mats[a])
        rbar = np.where(lam > 0, -eps * lam / rho[a] ** 2, 0.0)
        expected = v @ np.diag(rbar) @ v.T
        got = to_matrices(art[a:a + 1])[0]
        assert np.linalg.norm(got - expected) < 1e-10 * np.linalg.norm(expected), (a, got, expected)


def test_artificial_stress_warm_start_repeats_result():
    """eig_work keeps the eigenvectors for a warm start: a second call from them gives the same R."""
    rng = np.random.default_rng(8)
    n = 10
    stress = _pack(_random_symmetric(rng, n, 1e3))
    rho = np.full(n, 1000.0)
    pressure, sor2, art = np.zeros(n), np.zeros((n, 6)), np.zeros((n, 6))
    eig_work = _eig_work(n)
    stress_terms(stress, rho, 1000.0, 1e4, 0.3, pressure, sor2, art, eig_work)
    first = art.copy()
    q = eig_work[:, 3:6]
    assert np.allclose(np.einsum("nki,nkj->nij", q, q), np.eye(3), atol=1e-13)
    stress_terms(stress, rho, 1000.0, 1e4, 0.3, pressure, sor2, art, eig_work)
    assert np.allclose(art, first, rtol=1e-12, atol=1e-12 * np.abs(first).max())


def test_artificial_stress_zero_when_compressive_or_off():
    rng = np.random.default_rng(9)
    n = 20
    mats = []
    for _ in range(n):
        q = _rotation(rng.normal(size=3), rng.uniform(0, 2 * math.pi))
        mats.append(q @ np.diag(-rng.uniform(0.1, 10.0, 3) * 1e3) @ q.T)
    stress = _pack(np.array(mats))
    _, _, art, _ = _stress_terms(stress, np.full(n, 1000.0), 1000.0, 1e4, 0.3)
    assert np.abs(art).max() < 1e-12 * 1e4 / 1000.0 ** 2 * 0.3
    # eps = 0: R = 0 whatever the stress (and the array is overwritten, not left as NaN)
    stress = _pack(_random_symmetric(rng, n, 1e4))
    _, _, art, _ = _stress_terms(stress, np.full(n, 1000.0), 1000.0, 1e4, 0.0)
    assert np.all(art == 0.0)


# ---- strain energy -----------------------------------------------------------------------------------------

@pytest.mark.parametrize("e, nu", [(E_PAPER, NU_PAPER), (2.0e11, 0.3), (1.0e6, 0.0)])
def test_strain_energy_uniaxial(e, nu):
    """sigma = diag(s, 0, 0): p = -s/3, S = diag(2s/3, -s/3, -s/3); energy density s^2 / (2E) (Hooke)."""
    k, g, _ = material_constants(e, nu, 1000.0)
    s_values = np.array([1e3, -2.5e3, 40.0, 0.0])
    n = len(s_values)
    stress = np.zeros((n, 6))
    stress[:, 0] = 2.0 * s_values / 3.0
    stress[:, 1] = stress[:, 2] = -s_values / 3.0
    pressure = -s_values / 3.0
    rho = np.array([1000.0, 1001.0, 999.0, 1000.0])
    mass = np.array([1e-6, 2e-6, 1e-6, 1e-6])
    energy = strain_energy(mass, rho, stress, pressure, g, k)
    expected = np.sum(mass / rho * s_values ** 2 / (2.0 * e))
    assert energy == pytest.approx(expected, rel=1e-12)


def test_strain_energy_pure_shear_and_hydrostatic():
    k, g, _ = material_constants(E_PAPER, NU_PAPER, 1000.0)
    mass, rho = np.array([1e-6]), np.array([1000.0])
    # pure shear tau: energy density tau^2 / (2 G)
    stress = np.array([[0, 0, 0, 0, 500.0, 0]])
    assert strain_energy(mass, rho, stress, np.zeros(1), g, k) == pytest.approx(1e-9 * 500.0 ** 2 / (2 * g),
                                                                                rel=1e-12)
    # hydrostatic pressure p: p^2 / (2K)
    assert strain_energy(mass, rho, np.zeros((1, 6)), np.array([2e4]), g, k) == pytest.approx(
        1e-9 * 2e4 ** 2 / (2 * k), rel=1e-12)
