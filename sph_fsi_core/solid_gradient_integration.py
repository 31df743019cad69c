"""Strain-gradient nodal integration for the quadratic-fit solid (`solid.nodal_integration: gradient`).

Not in the paper. The particle scheme integrates the strain energy at the nodes: sum_a V_a sigma_a : eps_a / 2,
each particle's strain taken at its centre. In bending the strain varies linearly across every particle's cell,
and the centre value misses the cell's own second moment: on the paper's beam (4 layers at +-0.5 and +-1.5 dp)
sum z^2 = 5 dp^2 against H^3 / 12 = 5.33 dp^2, so EI comes out 6 % short and the frequency 3.2 %
(docs/validation/FINDINGS.md). A Taylor expansion of the strain over the cell (a cube of side dp: second moment
m = dp^2 / 12 in each direction) adds

    sum_a V_a m sum_k (d_k S_a : d_k eps_a) / 2,

which makes the (deviatoric) energy exact for strain linear across each cell (the gradient terms of naturally
stabilized nodal integration, Hillman & Chen 2016, IJNME 107). Only the deviatoric stress S gets the term: in
bending it carries all but 1 % of the energy at nu = 0.49 (87 % at nu = 0.3), while the volumetric one, with
K = 50 G at nu = 0.49, penalised the fit's volumetric strain gradient so hard that the paper's beam came out 5 %
stiff with its first mode trading energy away within a period (docs/validation/FINDINGS.md).

The quadratic fit of solid_mls.py already determines the velocity's second derivatives: with rows 3..8 of M_a^-1,
    d_j d_k v_a = sum_b (v_b - v_a) Gh_ab[jk],   Gh_ab = V_b W_ab (rows 3..8 of M_a^-1) p(u_ab) / h^2
(six entries xx, yy, zz, xy, xz, yz). The stress gradient T_a[k] = d_k S_a (three traceless symmetric tensors) is
state:
    dT[k]/dt = 2 G dev(e_k) + Jaumann spin on k, i and j,   e_k = d_k of the strain rate,
and its force is the one whose power is sum_a V_a m sum_k T_a[k] : d_k L_a (as F_ab of solid_mls.py):
    F_ab,i = Phi_ab,i - Phi_ba,i,   Phi_ab,i = V_a m sum_jk T_a[k]_ij Gh_ab[jk],   +F on a, -F on b,
so momentum is conserved to round-off and the energy stored is the work done. Particles whose fit fell back to
linear (fewer than three layers) have zero Hessian rows and no correction.
"""
import math

import numpy as np
from numba import njit, prange

from .kernels import cubic_spline_w
from .neighbours import minimum_image
from .tensors import XX, XY, XZ, YY, YZ, ZZ

HESSIAN_ROWS = 6
# Hessian entry q of the symmetric pair (j, k): xx, yy, zz, xy, xz, yz
_Q = ((0, 3, 4), (3, 1, 5), (4, 5, 2))
# stress component (i, j) of the 6-vector
_C = ((XX, XY, XZ), (XY, YY, YZ), (XZ, YZ, ZZ))


@njit(cache=True, fastmath=False, error_model="numpy", inline="always")
def _hessian_weights(rows_a, lx, ly, lz, qxx, qyy, qzz, qxy, qxz, qyz, scale, out, s, offset):
    """out[s, offset + q] = scale * (row 3 + q of M_a^-1) . p, q = 0..5."""
    for q in range(HESSIAN_ROWS):
        r = rows_a[3 + q]
        out[s, offset + q] = scale * ((r[0] * lx + r[1] * ly + r[2] * lz)
                                      + (r[3] * qxx + r[4] * qyy + r[5] * qzz)
                                      + (r[6] * qxy + r[7] * qxz + r[8] * qyz))


@njit(cache=True, fastmath=False, error_model="numpy", inline="always")
def _phi(tv, a, gh, s, offset):
    """Phi_i = sum_jk tv[a, k, (i, j)] Gh[s, offset + q(j, k)], as three scalars."""
    p0 = p1 = p2 = 0.0
    for k in range(3):
        for j in range(3):
            g = gh[s, offset + _Q[j][k]]
            p0 += tv[a, k, _C[0][j]] * g
            p1 += tv[a, k, _C[1][j]] * g
            p2 += tv[a, k, _C[2][j]] * g
    return p0, p1, p2


@njit(cache=True, fastmath=False, error_model="numpy", parallel=True, nogil=True)
def gradient_stress_force(pos, period, mass, movable, rho, stress_gradient, cell_moment, start, index, h, rows,
                          hweights, tv, acc, buf):
    """Adds the force of the stress gradient (module doc) to `acc`, refreshing the Hessian weights (pairs, 12:
    Gh_ab then Gh_ba) at the current positions for the next step's Hessian pass. `tv` (N, 3, 6) is scratch."""
    n = pos.shape[0]
    inv_h = 1.0 / h
    support2 = 4.0 * h * h
    for a in prange(n):
        scale = mass[a] / rho[a] * cell_moment
        for k in range(3):
            for c in range(6):
                tv[a, k, c] = scale * stress_gradient[a, k, c]
    chunks = buf.shape[0]
    for c in prange(chunks):
        out = buf[c]
        out[:, 0:3] = 0.0
        for a in range(c * n // chunks, (c + 1) * n // chunks):
            va = mass[a] / rho[a]
            fax = fay = faz = 0.0
            for s in range(start[a], start[a + 1]):
                b = index[s]
                ux = -minimum_image(pos[a, 0] - pos[b, 0], period[0]) * inv_h
                uy = -minimum_image(pos[a, 1] - pos[b, 1], period[1]) * inv_h
                uz = -minimum_image(pos[a, 2] - pos[b, 2], period[2]) * inv_h
                r2 = (ux * ux + uy * uy + uz * uz) * h * h
                if r2 >= support2:
                    for q in range(2 * HESSIAN_ROWS):
                        hweights[s, q] = 0.0
                    continue
                wab = cubic_spline_w(math.sqrt(r2), h)
                qxx = 0.5 * ux * ux
                qyy = 0.5 * uy * uy
                qzz = 0.5 * uz * uz
                qxy = ux * uy
                qxz = ux * uz
                qyz = uy * uz
                _hessian_weights(rows[a], ux, uy, uz, qxx, qyy, qzz, qxy, qxz, qyz,
                                 mass[b] / rho[b] * wab * inv_h * inv_h, hweights, s, 0)
                _hessian_weights(rows[b], -ux, -uy, -uz, qxx, qyy, qzz, qxy, qxz, qyz, va * wab * inv_h * inv_h,
                                 hweights, s, HESSIAN_ROWS)
                if not (movable[a] or movable[b]):
                    continue
                pa0, pa1, pa2 = _phi(tv, a, hweights, s, 0)
                pb0, pb1, pb2 = _phi(tv, b, hweights, s, HESSIAN_ROWS)
                fax += pa0 - pb0
                fay += pa1 - pb1
                faz += pa2 - pb2
                out[b, 0] -= pa0 - pb0
                out[b, 1] -= pa1 - pb1
                out[b, 2] -= pa2 - pb2
            out[a, 0] += fax
            out[a, 1] += fay
            out[a, 2] += faz
    for a in prange(n):
        inv_m = 1.0 / mass[a]
        for k in range(3):
            total = 0.0
            for c in range(chunks):
                total += buf[c, a, k]
            acc[a, k] += total * inv_m


@njit(cache=True, fastmath=False, error_model="numpy", parallel=True, nogil=True)
def velocity_hessian(vel, start, index, hweights, hessian, buf):
    """hessian (N, 3, 6): d_j d_k v_i of the quadratic fit, entry [i, q(j, k)], from the cached weights."""
    n = vel.shape[0]
    chunks = buf.shape[0]
    for c in prange(chunks):
        out = buf[c]
        out[:, 0:18] = 0.0
        for a in range(c * n // chunks, (c + 1) * n // chunks):
            for s in range(start[a], start[a + 1]):
                b = index[s]
                for i in range(3):
                    dv = vel[b, i] - vel[a, i]
                    for q in range(HESSIAN_ROWS):
                        out[a, 6 * i + q] += dv * hweights[s, q]
                        out[b, 6 * i + q] -= dv * hweights[s, HESSIAN_ROWS + q]
    for a in prange(n):
        for i in range(3):
            for q in range(HESSIAN_ROWS):
                total = 0.0
                for c in range(chunks):
                    total += buf[c, a, 6 * i + q]
                hessian[a, i, q] = total


@njit(cache=True, fastmath=False, error_model="numpy", parallel=True, nogil=True)
def stress_gradient_rate(hessian, grad_v, stress_gradient, shear_modulus, rate):
    """dT[k]/dt = 2G dev(e_k) + (W T)[k] for T[k] = d_k S (deviatoric), e_k = d_k of the strain rate.

    The spin W = (L - L^T) / 2 turns all three indices of T: Omega_kl T[l]_ij + Omega_il T[k]_lj + Omega_jl T[k]_il,
    so a rigidly rotating bent body keeps its stress gradient (the Jaumann rate of solid_gray2001.py, one index more).
    """
    for a in prange(hessian.shape[0]):
        om = np.empty((3, 3))
        for i in range(3):
            for j in range(3):
                om[i, j] = 0.5 * (grad_v[a, i, j] - grad_v[a, j, i])
        t = np.empty((3, 3, 3))
        for k in range(3):
            for i in range(3):
                for j in range(3):
                    t[k, i, j] = stress_gradient[a, k, _C[i][j]]
        for k in range(3):
            e = np.empty((3, 3))
            for i in range(3):
                for j in range(3):
                    e[i, j] = 0.5 * (hessian[a, i, _Q[j][k]] + hessian[a, j, _Q[i][k]])
            tr = e[0, 0] + e[1, 1] + e[2, 2]
            for i in range(3):
                for j in range(i, 3):
                    value = 2.0 * shear_modulus * e[i, j]
                    if i == j:
                        value -= 2.0 * shear_modulus / 3.0 * tr
                    for m in range(3):
                        value += om[k, m] * t[m, i, j] + om[i, m] * t[k, m, j] + om[j, m] * t[k, i, m]
                    rate[a, k, _C[i][j]] = value


@njit(cache=True, fastmath=False, error_model="numpy", nogil=True)
def gradient_strain_energy(mass, rho, stress_gradient, cell_moment, shear_modulus):
    """sum_a V_a m sum_k T[k] : T[k] / (4G), the deviatoric energy of the stress gradient (T is traceless)."""
    total = 0.0
    for a in range(mass.shape[0]):
        for k in range(3):
            t = stress_gradient[a, k]
            tt = t[XX] ** 2 + t[YY] ** 2 + t[ZZ] ** 2 + 2.0 * (t[XY] ** 2 + t[XZ] ** 2 + t[YZ] ** 2)
            total += mass[a] / rho[a] * cell_moment * tt / (4.0 * shear_modulus)
    return total


@njit(cache=True, fastmath=False, error_model="numpy", parallel=True, nogil=True)
def hessian_pair_weights(pos, period, mass, rho, start, index, h, rows, hweights):
    """The pair cache `hweights` (pairs, 12) = (Gh_ab, Gh_ba) at the current positions (after a list build)."""
    inv_h = 1.0 / h
    for a in prange(pos.shape[0]):
        va = mass[a] / rho[a]
        for s in range(start[a], start[a + 1]):
            b = index[s]
            ux = -minimum_image(pos[a, 0] - pos[b, 0], period[0]) * inv_h
            uy = -minimum_image(pos[a, 1] - pos[b, 1], period[1]) * inv_h
            uz = -minimum_image(pos[a, 2] - pos[b, 2], period[2]) * inv_h
            wab = cubic_spline_w(math.sqrt(ux * ux + uy * uy + uz * uz) * h, h)
            qxx = 0.5 * ux * ux
            qyy = 0.5 * uy * uy
            qzz = 0.5 * uz * uz
            qxy = ux * uy
            qxz = ux * uz
            qyz = uy * uz
            _hessian_weights(rows[a], ux, uy, uz, qxx, qyy, qzz, qxy, qxz, qyz,
                             mass[b] / rho[b] * wab * inv_h * inv_h, hweights, s, 0)
            _hessian_weights(rows[b], -ux, -uy, -uz, qxx, qyy, qzz, qxy, qxz, qyz, va * wab * inv_h * inv_h,
                             hweights, s, HESSIAN_ROWS)
