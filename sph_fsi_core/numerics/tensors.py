"""Symmetric 3x3 tensors stored as 6 components, and a Numba Jacobi eigen-solver (no SciPy inside njit).

Component order (used by every array of shape (N, 6) in sph_fsi): XX, YY, ZZ, XY, XZ, YZ.
"""
import math

import numpy as np
from numba import njit

XX, YY, ZZ, XY, XZ, YZ = range(6)
COMPONENT_NAMES = ("xx", "yy", "zz", "xy", "xz", "yz")
# (row, column) -> component, for both triangles
SYM_INDEX = np.array([[XX, XY, XZ], [XY, YY, YZ], [XZ, YZ, ZZ]], dtype=np.int64)


@njit(cache=True, fastmath=False, error_model="numpy", inline="always")
def unpack(t, out):
    """Six components -> full 3x3 matrix `out`."""
    out[0, 0] = t[XX]
    out[1, 1] = t[YY]
    out[2, 2] = t[ZZ]
    out[0, 1] = out[1, 0] = t[XY]
    out[0, 2] = out[2, 0] = t[XZ]
    out[1, 2] = out[2, 1] = t[YZ]


@njit(cache=True, fastmath=False, error_model="numpy", nogil=True)
def symmetric_eigen(a, eigvals, eigvecs, rot):
    """Eigenvalues and column eigenvectors of the symmetric 3x3 matrix `a` by cyclic Jacobi rotations.

    `eigvecs` holds an orthonormal starting guess on entry (the identity, or the previous step's eigenvectors:
    stress turns slowly, so a warm start usually needs a single sweep). `a` is overwritten by V^T a V; `rot`
    (3x3) is scratch.
    """
    # a <- V^T a V (a is symmetric, so a[i, j] for j >= i is enough)
    for i in range(3):
        for j in range(i, 3):
            acc = 0.0
            for k in range(3):
                av = a[k, 0] * eigvecs[0, j] + a[k, 1] * eigvecs[1, j] + a[k, 2] * eigvecs[2, j]
                acc += eigvecs[k, i] * av
            rot[i, j] = acc
    for i in range(3):
        for j in range(i, 3):
            a[i, j] = rot[i, j]
            a[j, i] = rot[i, j]
    for _sweep in range(12):
        off = a[0, 1] * a[0, 1] + a[0, 2] * a[0, 2] + a[1, 2] * a[1, 2]
        scale = a[0, 0] * a[0, 0] + a[1, 1] * a[1, 1] + a[2, 2] * a[2, 2]
        if off <= 1e-30 * scale or off == 0.0:
            break
        for p in range(2):
            for q in range(p + 1, 3):
                apq = a[p, q]
                if apq == 0.0:
                    continue
                theta = (a[q, q] - a[p, p]) / (2.0 * apq)
                t = (1.0 if theta >= 0.0 else -1.0) / (abs(theta) + math.sqrt(theta * theta + 1.0))
                c = 1.0 / math.sqrt(t * t + 1.0)
                s = t * c
                for k in range(3):
                    akp = a[k, p]
                    akq = a[k, q]
                    a[k, p] = c * akp - s * akq
                    a[k, q] = s * akp + c * akq
                for k in range(3):
                    apk = a[p, k]
                    aqk = a[q, k]
                    a[p, k] = c * apk - s * aqk
                    a[q, k] = s * apk + c * aqk
                for k in range(3):
                    vkp = eigvecs[k, p]
                    vkq = eigvecs[k, q]
                    eigvecs[k, p] = c * vkp - s * vkq
                    eigvecs[k, q] = s * vkp + c * vkq
    for i in range(3):
        eigvals[i] = a[i, i]


def to_matrices(t):
    """(N, 6) -> (N, 3, 3), for tests and outputs."""
    return np.asarray(t)[:, SYM_INDEX]


def von_mises(t):
    """Von Mises equivalent stress of (N, 6) stress tensors."""
    t = np.ascontiguousarray(t, dtype=np.float64)
    out = np.empty(len(t))
    _von_mises_rows(t, out)
    return out


@njit(cache=True, fastmath=False, nogil=True)
def _von_mises_rows(t, out):
    """sqrt(3 J2) per row: one pass, no temporaries (it runs on the node's simulation thread for every frame)."""
    for a in range(t.shape[0]):
        mean = (t[a, XX] + t[a, YY] + t[a, ZZ]) / 3.0
        dx, dy, dz = t[a, XX] - mean, t[a, YY] - mean, t[a, ZZ] - mean
        j2 = 0.5 * (dx * dx + dy * dy + dz * dz) + t[a, XY] ** 2 + t[a, XZ] ** 2 + t[a, YZ] ** 2
        out[a] = math.sqrt(3.0 * j2)
