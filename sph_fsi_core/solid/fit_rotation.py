"""The quadratic fit's rows turned with each particle's spin (`solid.fit_refresh: rotate`), remade only as it strains.

Not in the paper. The fit of solid/fitted_gradient.py inverts each particle's moment matrix
M_a = sum_b V_b W_ab p(u_ab) p(u_ab)^T at the positions it was made at; as the body moves the rows go stale and are
remade (solid.fit_refresh_turn: a stale fit leaks rotation into the fitted curvature). A bending gate's
neighbourhoods mostly turn: on the paper's gate the remade rows cost as much as the steps themselves. Under a rigid
rotation Q of the neighbourhood the offsets turn, u' = Q u, so p(u') = T(Q) p(u) with

    T(Q) = diag(Q, T_q(Q)),  T_q[(ij), (kk)] = 2 f_ij Q_ik Q_jk,  T_q[(ij), (kl)] = f_ij (Q_ik Q_jl + Q_il Q_jk) (k < l),

f_ii = 1/2 and f_ij = 1 (the basis holds u_i^2 / 2 and u_i u_j), and W_ab and V_b do not change: M' = T M T^T, hence

    M'^-1 = T(Q^T)^T M^-1 T(Q^T):  rows 0..2: Q R_0..2 T(Q^T),   rows 3..8: T_q(Q^T)^T R_3..8 T(Q^T).

Q is the particle's own rotation since its rows were made, dQ/dt = Omega Q with Omega = (L - L^T) / 2 its spin
(Rodrigues' formula per step). A particle's rows are turned once it has turned by solid.fit_refresh_turn since they
were last turned, and all are remade once some particle's neighbourhood has changed shape by it since they were made
(|E|, the Green strain of its deformation since then, dF/dt = L F): what turning cannot follow.
"""
import math

import numpy as np
from numba import njit, prange

# the quadratic basis' pairs (i, j) in the order of fitted_gradient._basis: xx, yy, zz, xy, xz, yz
_PAIRS = ((0, 0), (1, 1), (2, 2), (0, 1), (0, 2), (1, 2))


@njit(cache=True, fastmath=False, error_model="numpy", inline="always")
def _basis_rotation(q, t):
    """t (9, 9) = T(q) of the module docstring."""
    for i in range(9):
        for j in range(9):
            t[i, j] = 0.0
    for i in range(3):
        for j in range(3):
            t[i, j] = q[i, j]
    for r in range(6):
        i, j = _PAIRS[r]
        f = 0.5 if i == j else 1.0
        for c in range(6):
            k, l = _PAIRS[c]
            if k == l:
                t[3 + r, 3 + c] = 2.0 * f * q[i, k] * q[j, k]
            else:
                t[3 + r, 3 + c] = f * (q[i, k] * q[j, l] + q[i, l] * q[j, k])


_CHUNKS = 64


@njit(cache=True, fastmath=False, error_model="numpy", nogil=True)
def _rotate_rows(rows0, q, t, tmp, rows):
    """One particle's rows (R, 9) from the rows0 it was made with and its rotation q since then; t (9, 9) and tmp
    (R, 9) scratch. T is block diagonal (3 x 3, 6 x 6): the products run over the blocks only."""
    qt = q.T
    _basis_rotation(qt, t)
    nr = rows.shape[0]
    for r in range(nr):          # tmp = rows0 T(Q^T)
        for c in range(3):
            tmp[r, c] = rows0[r, 0] * t[0, c] + rows0[r, 1] * t[1, c] + rows0[r, 2] * t[2, c]
        for c in range(3, 9):
            s = 0.0
            for k in range(3, 9):
                s += rows0[r, k] * t[k, c]
            tmp[r, c] = s
    for r in range(3):           # rows 0..2: Q tmp
        for c in range(9):
            rows[r, c] = q[r, 0] * tmp[0, c] + q[r, 1] * tmp[1, c] + q[r, 2] * tmp[2, c]
    for r in range(3, nr):       # rows 3..8: T_q(Q^T)^T tmp
        for c in range(9):
            s = 0.0
            for k in range(3, 9):
                s += t[k, r] * tmp[k, c]
            rows[r, c] = s


@njit(cache=True, fastmath=False, error_model="numpy", parallel=True, nogil=True)
def rotate_fit_rows(rows0, rotation, spin, limit, rows):
    """rows (N, R, 9) of the particles that have turned by more than `limit` since their rows were last turned
    (spin, reset for those) = the rows0 they were made with, turned by their rotation (N, 3, 3) since then (R = 3:
    the gradient's rows; R = 9: and the Hessian's). limit 0 turns every particle's."""
    n = rows.shape[0]
    chunks = min(n, _CHUNKS)
    for c in prange(chunks):
        t = np.empty((9, 9))
        tmp = np.empty((rows.shape[1], 9))
        for a in range(c * n // chunks, (c + 1) * n // chunks):
            if spin[a] > limit or limit == 0.0:
                _rotate_rows(rows0[a], rotation[a], t, tmp, rows[a])
                spin[a] = 0.0


@njit(cache=True, fastmath=False, error_model="numpy", parallel=True, nogil=True)
def follow_spin(grad_v, dt, rotation, deformation, strain, spin):
    """One step of each particle's rotation since its rows were made (Rodrigues, rotation <- exp(Omega dt) rotation)
    and of its deformation since then (deformation <- (I + L dt) deformation); strain = |E|, the Frobenius norm of the
    Green strain (F^T F - I) / 2 of that deformation: how far its neighbourhood has changed shape, whatever way it got
    there (a sum of |D| dt would also count the strain of every vibration back and forth); spin += |w| dt, its turn
    since its rows were last turned. Returns the largest strain and spin."""
    n = grad_v.shape[0]
    worst_strain = 0.0
    worst_spin = 0.0
    for a in prange(n):
        g = grad_v[a]
        f = deformation[a]
        for j in range(3):
            f0, f1, f2 = f[0, j], f[1, j], f[2, j]
            f[0, j] = f0 + dt * (g[0, 0] * f0 + g[0, 1] * f1 + g[0, 2] * f2)
            f[1, j] = f1 + dt * (g[1, 0] * f0 + g[1, 1] * f1 + g[1, 2] * f2)
            f[2, j] = f2 + dt * (g[2, 0] * f0 + g[2, 1] * f1 + g[2, 2] * f2)
        e2 = 0.0
        for i in range(3):
            for j in range(3):
                c = f[0, i] * f[0, j] + f[1, i] * f[1, j] + f[2, i] * f[2, j] - (1.0 if i == j else 0.0)
                e2 += 0.25 * c * c
        strain[a] = math.sqrt(e2)
        # Omega = [w]x: w = (Omega_zy, Omega_xz, Omega_yx)
        wx = 0.5 * (g[2, 1] - g[1, 2]) * dt
        wy = 0.5 * (g[0, 2] - g[2, 0]) * dt
        wz = 0.5 * (g[1, 0] - g[0, 1]) * dt
        angle = math.sqrt(wx * wx + wy * wy + wz * wz)
        spin[a] += angle
        worst_strain = max(worst_strain, strain[a])
        worst_spin = max(worst_spin, spin[a])
        if angle > 0.0:
            s = math.sin(angle) / angle
            c = (1.0 - math.cos(angle)) / (angle * angle)
            # exp([w]x) = I + s [w]x + c [w]x^2
            e00 = 1.0 - c * (wy * wy + wz * wz)
            e11 = 1.0 - c * (wx * wx + wz * wz)
            e22 = 1.0 - c * (wx * wx + wy * wy)
            e01 = -s * wz + c * wx * wy
            e10 = s * wz + c * wx * wy
            e02 = s * wy + c * wx * wz
            e20 = -s * wy + c * wx * wz
            e12 = -s * wx + c * wy * wz
            e21 = s * wx + c * wy * wz
            q = rotation[a]
            for j in range(3):
                q0, q1, q2 = q[0, j], q[1, j], q[2, j]
                q[0, j] = e00 * q0 + e01 * q1 + e02 * q2
                q[1, j] = e10 * q0 + e11 * q1 + e12 * q2
                q[2, j] = e20 * q0 + e21 * q1 + e22 * q2
    return worst_strain, worst_spin
