"""Tests of sph_fsi_core.numerics.tensors: the Jacobi eigen-solver against numpy.linalg.eigh, von Mises stress, packing."""
import inspect
import math

import numpy as np
import pytest

from sph_fsi_core.numerics.tensors import SYM_INDEX, symmetric_eigen, to_matrices, unpack, von_mises


def _rotation(rng, angle=None):
    """A random rotation matrix (Rodrigues), of a given angle if asked."""
    axis = rng.normal(size=3)
    axis /= np.linalg.norm(axis)
    theta = rng.uniform(0, 2 * math.pi) if angle is None else angle
    k = np.array([[0, -axis[2], axis[1]], [axis[2], 0, -axis[0]], [-axis[1], axis[0], 0]])
    return np.eye(3) + math.sin(theta) * k + (1 - math.cos(theta)) * k @ k


def _matrices():
    """200 symmetric matrices: random, repeated eigenvalues, diagonal, zero, very anisotropic, scaled."""
    rng = np.random.default_rng(2024)
    out = []
    for _ in range(60):                                  # general
        m = rng.normal(size=(3, 3)) * 10.0 ** rng.uniform(-6, 8)
        out.append(0.5 * (m + m.T))
    for _ in range(30):                                  # a double eigenvalue, rotated
        lam = rng.normal(size=2) * 10.0 ** rng.uniform(-3, 6)
        q = _rotation(rng)
        out.append(q @ np.diag([lam[0], lam[0], lam[1]]) @ q.T)
    for _ in range(10):                                  # a triple eigenvalue (isotropic), rotated
        q = _rotation(rng)
        out.append(q @ (rng.normal() * np.eye(3)) @ q.T)
    for _ in range(30):                                  # diagonal, incl. repeated entries and zeros
        d = rng.choice([-2.0, 0.0, 1.0, 1.0, 3.5], size=3) * 10.0 ** rng.uniform(-4, 6)
        out.append(np.diag(d))
    out.append(np.zeros((3, 3)))
    out.append(np.diag([0.0, 0.0, 1e-30]))
    for _ in range(38):                                  # very anisotropic: eigenvalues over 12 decades, rotated
        lam = np.array([1.0, 10.0 ** rng.uniform(-12, -6), -(10.0 ** rng.uniform(-12, -3))]) * 10.0 ** rng.uniform(-2, 7)
        q = _rotation(rng)
        out.append(q @ np.diag(lam) @ q.T)
    for _ in range(30):                                  # nearly diagonal (tiny off-diagonals)
        m = np.diag(rng.normal(size=3)) + 1e-9 * rng.normal(size=(3, 3))
        out.append(0.5 * (m + m.T))
    assert len(out) == 200
    return [np.ascontiguousarray(0.5 * (m + m.T)) for m in out]


MATRICES = _matrices()

# symmetric_eigen(a, eigvals, eigvecs[, scratch...]): any parameters after the third are 3x3 scratch arrays
_EXTRA = len(inspect.signature(symmetric_eigen.py_func).parameters) - 3


def _eigen(a, vals, vecs):
    symmetric_eigen(a, vals, vecs, *[np.zeros((3, 3)) for _ in range(_EXTRA)])


def _check(m, vals, vecs, tol=1e-12):
    norm = max(np.linalg.norm(m), 1e-300)
    assert np.linalg.norm(vecs.T @ vecs - np.eye(3)) < 1e-13
    recon = vecs @ np.diag(vals) @ vecs.T
    assert np.linalg.norm(recon - m) <= tol * norm, (m, vals)
    ref = np.linalg.eigvalsh(m)
    assert np.allclose(np.sort(vals), ref, rtol=0, atol=tol * norm), (np.sort(vals), ref)
    # each column is an eigenvector: A v = lambda v
    for i in range(3):
        assert np.linalg.norm(m @ vecs[:, i] - vals[i] * vecs[:, i]) <= tol * norm


@pytest.mark.parametrize("i", range(len(MATRICES)))
def test_symmetric_eigen_cold_start(i):
    m = MATRICES[i]
    a = m.copy()
    vals = np.empty(3)
    vecs = np.eye(3)
    _eigen(a, vals, vecs)
    _check(m, vals, vecs)
    # `a` is overwritten by V^T m V, diagonal = the eigenvalues
    assert np.allclose(np.diag(a), vals, rtol=0, atol=1e-15 * max(np.linalg.norm(m), 1e-300))


def test_symmetric_eigen_warm_start():
    """Start from the exact eigenbasis rotated by a small angle, as from the previous step's eigenvectors."""
    rng = np.random.default_rng(99)
    for m in MATRICES:
        _, v = np.linalg.eigh(m)
        for angle in (0.0, 1e-8, 1e-3, 0.05, 0.3):
            start = _rotation(rng, angle) @ v
            a = m.copy()
            vals = np.empty(3)
            vecs = np.ascontiguousarray(start.copy())
            _eigen(a, vals, vecs)
            _check(m, vals, vecs)


def test_symmetric_eigen_arbitrary_orthonormal_start():
    rng = np.random.default_rng(5)
    for m in MATRICES[::4]:
        a = m.copy()
        vals = np.empty(3)
        vecs = np.ascontiguousarray(_rotation(rng))
        _eigen(a, vals, vecs)
        _check(m, vals, vecs)


def test_von_mises():
    s = np.array([3.0e5, -1.7, 0.0, 42.0])
    # uniaxial
    t = np.zeros((4, 6))
    t[:, 0] = s
    assert np.allclose(von_mises(t), np.abs(s), rtol=1e-14)
    t = np.zeros((4, 6))
    t[:, 2] = s
    assert np.allclose(von_mises(t), np.abs(s), rtol=1e-14)
    # pure shear tau in each off-diagonal component
    for comp in (3, 4, 5):
        t = np.zeros((4, 6))
        t[:, comp] = s
        assert np.allclose(von_mises(t), math.sqrt(3.0) * np.abs(s), rtol=1e-14)
    # pure shear as principal stresses (tau, -tau, 0), and a hydrostatic stress adds nothing
    t = np.zeros((4, 6))
    t[:, 0], t[:, 1] = s, -s
    assert np.allclose(von_mises(t), math.sqrt(3.0) * np.abs(s), rtol=1e-14)
    t[:, :3] += 1e4
    assert np.allclose(von_mises(t), math.sqrt(3.0) * np.abs(s), rtol=1e-10, atol=1e-8)
    # invariance under rotation
    rng = np.random.default_rng(4)
    m = rng.normal(size=(3, 3))
    m = m + m.T
    q = _rotation(rng)
    r = q @ m @ q.T
    pack = lambda x: np.array([[x[0, 0], x[1, 1], x[2, 2], x[0, 1], x[0, 2], x[1, 2]]])
    assert von_mises(pack(m))[0] == pytest.approx(von_mises(pack(r))[0], rel=1e-12)


def test_packing_round_trip():
    rng = np.random.default_rng(8)
    t = rng.normal(size=(5, 6))
    full = to_matrices(t)
    assert full.shape == (5, 3, 3)
    assert np.array_equal(full, np.transpose(full, (0, 2, 1)))
    assert np.array_equal(full[:, 0, 1], t[:, 3]) and np.array_equal(full[:, 0, 2], t[:, 4])
    assert np.array_equal(full[:, 1, 2], t[:, 5]) and np.array_equal(full[:, 2, 2], t[:, 2])
    out = np.empty((3, 3))
    unpack(t[2], out)
    assert np.array_equal(out, full[2])
    assert SYM_INDEX.tolist() == [[0, 3, 4], [3, 1, 5], [4, 5, 2]]
