"""Second-order (quadratic moving-least-squares) velocity gradient for the elastic solid, and its paired force.

Not in the paper: an option (`solid.velocity_gradient: quadratic`) that removes the error of the SPH velocity
gradient at free surfaces. The beam of Satake et al. is 4 particles thick, so every particle sits within the
kernel radius of a surface, where

- the plain SPH gradient (Gray 2001, eq. (5)'s companion L^ij) turns a rigid rotation into shear strain and
  underestimates the axial strain of bending (outer fibre: 0.85 dp of 1.5 dp on the paper's lattice), and
- the kernel-corrected gradient L K^-1 (exact for linear fields) still evaluates the strain of a curved field
  at the centroid of the particle's one-sided neighbourhood (outer fibre: 1.20 dp of 1.5 dp), so a bent beam
  comes out 30 % too soft (docs/method.md, the velocity gradient).

Here each particle fits v_b - v_a ~ g . d + d^T H d / 2 over its neighbours with weights V_b W_ab (nine
unknowns, u = d / h keeps the moment matrix well scaled), which is exact for quadratic velocity fields:

    L_a = sum_b (v_b - v_a) (x) G_ab,   G_ab = V_b W_ab R_a p(u_ab) / h,   R_a = rows 0..2 of M_a^-1,
    M_a = sum_b V_b W_ab p(u_ab) p(u_ab)^T,
    p(u) = (u_x, u_y, u_z, u_x^2/2, u_y^2/2, u_z^2/2, u_x u_y, u_x u_z, u_y u_z).

Where the quadratic fit is not determined (fewer than three particle layers in some direction) the particle
falls back to the linear fit (first 3 x 3 block). The force that goes with this strain rate is the one whose
power is the stress power sum_a V_a sigma_a : L_a (variational consistency, as Bonet & Lok 1999 do for the
linear correction): the pair (a, b) exchanges F_ab = V_a sigma_a G_ab - V_b sigma_b G_ba, +F on a and -F on b,
so momentum is conserved to round-off whatever G is. R_a is refreshed with each neighbour-list build; between
builds the particles move less than half the Verlet skin.
"""
import math

import numpy as np
from numba import njit, prange

from ..numerics.kernels import cubic_spline_w, cubic_spline_wf, support_squared
from ..numerics.neighbours import chunk_first_target, unsigned
from ..numerics.periodic import minimum_image
from ..numerics.pair_blocks import (BLOCK, MOTION_COLUMNS, NEIGHBOUR_DENSITY, SEPARATION, STRIDE,
                          gather_motion, gather_tensors, minimum_image_block, pad_block, padded)
from .gradient_integration import basis_dot, quadratic_monomials
from .gray2001 import pair_terms, sum_velocity_chunks, viscous_and_artificial_stress_terms, xsph_pair
from ..numerics.tensors import XX, XY, XZ, YY, YZ, ZZ

N_BASIS = 9
MOMENT_COUNT = N_BASIS * (N_BASIS + 1) // 2   # upper triangle of M, row by row
# A quadratic fit whose Cholesky pivot falls below this fraction of its diagonal entry is not determined. On a
# lattice every particle with three or more layers around it has pivots of at least 0.07 of the diagonal (4-layer
# and 3-layer beams, the 3-layer Antoci gate), and a two-layer direction 1e-16 (u_z and u_z^2 / 2 collinear over
# the neighbours). Bending lifts the latter with the square of the distortion: 1e-6 let a bent two-layer beam's
# particles flip to a "quadratic" fit with rows of 1e3 and more once the fit was remade as the beam moved, and the
# run blew up within 0.3 ms (a 2 mm cantilever); 1e-2 keeps them linear up to ~10 % distortion of the cell.
_PIVOT_TOLERANCE = 1e-2


@njit(cache=True, fastmath=False, error_model="numpy", inline="always")
def _basis(ux, uy, uz, p):
    p[0] = ux
    p[1] = uy
    p[2] = uz
    p[3] = 0.5 * ux * ux
    p[4] = 0.5 * uy * uy
    p[5] = 0.5 * uz * uz
    p[6] = ux * uy
    p[7] = ux * uz
    p[8] = uy * uz


@njit(cache=True, fastmath=False, error_model="numpy", inline="always")
def _scaled_offset_and_weight(pos, a, b, period, half_period, h, inv_h):
    """u_ab = (x_b - x_a) / h (minimum image) and W_ab: what the fit's moments and its pair weights are built from."""
    ux = -minimum_image(pos[a, 0] - pos[b, 0], period[0], half_period[0]) * inv_h
    uy = -minimum_image(pos[a, 1] - pos[b, 1], period[1], half_period[1]) * inv_h
    uz = -minimum_image(pos[a, 2] - pos[b, 2], period[2], half_period[2]) * inv_h
    return ux, uy, uz, cubic_spline_w(math.sqrt(ux * ux + uy * uy + uz * uz) * h, h)


@njit(cache=True, fastmath=False, error_model="numpy", inline="always")
def _cholesky_solve_rows(m, rows, nb):
    """Rows of m^-1 for the leading nb x nb block of the symmetric m (destroyed); False if not SPD enough.

    rows (R, 9): rows 0..R-1 of the inverse for the full quadratic block (R = 3, or 9 when the Hessian rows are
    wanted too); rows 0..2 for the linear block, the rest zero.
    """
    for j in range(nb):
        d = m[j, j]
        for k in range(j):
            d -= m[j, k] * m[j, k]
        if d <= _PIVOT_TOLERANCE * m[j, j] or d <= 0.0:
            return False
        d = math.sqrt(d)
        m[j, j] = d
        for i in range(j + 1, nb):
            s = m[i, j]
            for k in range(j):
                s -= m[i, k] * m[j, k]
            m[i, j] = s / d
    # solve L L^T x = e_r for r = 0, 1, ...; m^-1 is symmetric, so column r is row r
    nr = rows.shape[0] if nb == N_BASIS else 3
    for r in range(nr):
        for i in range(nb):
            s = 1.0 if i == r else 0.0
            for k in range(i):
                s -= m[i, k] * rows[r, k]
            rows[r, i] = s / m[i, i]
        for i in range(nb - 1, -1, -1):
            s = rows[r, i]
            for k in range(i + 1, nb):
                s -= m[k, i] * rows[r, k]
            rows[r, i] = s / m[i, i]
    for r in range(nr):
        for i in range(nb, N_BASIS):
            rows[r, i] = 0.0
    for r in range(nr, rows.shape[0]):
        for i in range(N_BASIS):
            rows[r, i] = 0.0
    return True


@njit(cache=True, fastmath=False, error_model="numpy", nogil=True)
def _fit_moments_chunk(c, chunks, pos, period, mass, rho, start, index, h, moment_buf):
    """mls_fit_rows' pair pass for chunk c of the half list's targets: its moment sums into moment_buf[c]."""
    half_period = 0.5 * period
    inv_h = 1.0 / h
    out = moment_buf[c]
    out[:, :] = 0.0
    p = np.empty(N_BASIS)
    for a in range(chunk_first_target(start, c, chunks), chunk_first_target(start, c + 1, chunks)):
        va = mass[a] / rho[a]
        for s in range(unsigned(start[a]), unsigned(start[a + 1])):
            b = index[s]
            ux, uy, uz, wab = _scaled_offset_and_weight(pos, a, b, period, half_period, h, inv_h)
            _basis(ux, uy, uz, p)
            wa = mass[b] / rho[b] * wab
            wb = va * wab
            k = 0
            for i in range(N_BASIS):
                for j in range(i, N_BASIS):
                    # p(-u) p(-u)^T differs from p(u) p(u)^T by the sign of linear x quadratic entries
                    pp = p[i] * p[j]
                    out[a, k] += wa * pp
                    out[b, k] += wb * (-pp if (i < 3) != (j < 3) else pp)
                    k += 1


@njit(cache=True, fastmath=False, error_model="numpy", nogil=True)
def _fit_rows_range(first, last, rows, order, moment_buf):
    """mls_fit_rows' solve for particles first..last-1: each one's moments summed over the chunks, then Cholesky."""
    chunks = moment_buf.shape[0]
    for a in range(first, last):
        m = np.empty((N_BASIS, N_BASIS))
        k = 0
        for i in range(N_BASIS):
            for j in range(i, N_BASIS):
                total = 0.0
                for c in range(chunks):
                    total += moment_buf[c, a, k]
                m[i, j] = total
                m[j, i] = total
                k += 1
        saved = m[:3, :3].copy()
        if _cholesky_solve_rows(m, rows[a], N_BASIS):
            order[a] = 2
            continue
        m[:3, :3] = saved
        if _cholesky_solve_rows(m, rows[a], 3):
            order[a] = 1
        else:   # an isolated particle: no gradient at all
            order[a] = 0
            for r in range(rows.shape[1]):
                for i in range(N_BASIS):
                    rows[a, r, i] = 0.0


@njit(cache=True, fastmath=False, error_model="numpy", parallel=True, nogil=True)
def mls_fit_rows(pos, period, mass, rho, start, index, h, rows, order, moment_buf):
    """R_a (N, R, 9): rows 0..R-1 of the inverse weighted moment matrix M_a (R = 3: the gradient; R = 9: and the
    Hessian, solid/gradient_integration.py); order[a] = 2 (quadratic) or 1 (linear).

    One pass over the half list into per-chunk moment sums `moment_buf` (chunks, N, 45), then one small
    Cholesky solve per particle. Call after every neighbour-list build. Each parallel loop's body is one call
    to a serial function, its chunk as an int64 (docs/method.md, "Performance design": the compile).
    """
    n = pos.shape[0]
    chunks = moment_buf.shape[0]
    for c in prange(chunks):
        _fit_moments_chunk(np.int64(c), chunks, pos, period, mass, rho, start, index, h, moment_buf)
    for c in prange(chunks):
        _fit_rows_range(n * c // chunks, n * (c + 1) // chunks, rows, order, moment_buf)


@njit(cache=True, fastmath=False, error_model="numpy", inline="always")
def _pair_weight_vector(rows_a, lx, ly, lz, qxx, qyy, qzz, qxy, qxz, qyz, scale):
    """scale * R_a p for p = (l, q) given as scalars, returned as three scalars (kept in registers)."""
    # summed as a tree: three short dependency chains instead of one of nine additions
    g0 = ((rows_a[0][0] * lx + rows_a[0][1] * ly + rows_a[0][2] * lz)
          + (rows_a[0][3] * qxx + rows_a[0][4] * qyy + rows_a[0][5] * qzz)
          + (rows_a[0][6] * qxy + rows_a[0][7] * qxz + rows_a[0][8] * qyz))
    g1 = ((rows_a[1][0] * lx + rows_a[1][1] * ly + rows_a[1][2] * lz)
          + (rows_a[1][3] * qxx + rows_a[1][4] * qyy + rows_a[1][5] * qzz)
          + (rows_a[1][6] * qxy + rows_a[1][7] * qxz + rows_a[1][8] * qyz))
    g2 = ((rows_a[2][0] * lx + rows_a[2][1] * ly + rows_a[2][2] * lz)
          + (rows_a[2][3] * qxx + rows_a[2][4] * qyy + rows_a[2][5] * qzz)
          + (rows_a[2][6] * qxy + rows_a[2][7] * qxz + rows_a[2][8] * qyz))
    return scale * g0, scale * g1, scale * g2


@njit(cache=True, fastmath=False, error_model="numpy", inline="always")
def _store_pair_weights(rows, a, b, ux, uy, uz, scale_ab, scale_ba, weights, s):
    """The pair's G_ab = scale_ab R_a p(u) and G_ba = scale_ba R_b p(-u) into weights[s], also returned as six
    scalars; u = (x_b - x_a) / h, the scales carry V W_ab / h of the other particle."""
    qxx, qyy, qzz, qxy, qxz, qyz = quadratic_monomials(ux, uy, uz)
    gab0, gab1, gab2 = _pair_weight_vector(rows[a], ux, uy, uz, qxx, qyy, qzz, qxy, qxz, qyz, scale_ab)
    gba0, gba1, gba2 = _pair_weight_vector(rows[b], -ux, -uy, -uz, qxx, qyy, qzz, qxy, qxz, qyz, scale_ba)
    weights[s, 0] = gab0
    weights[s, 1] = gab1
    weights[s, 2] = gab2
    weights[s, 3] = gba0
    weights[s, 4] = gba1
    weights[s, 5] = gba2
    return gab0, gab1, gab2, gba0, gba1, gba2


@njit(cache=True, fastmath=False, error_model="numpy", inline="always")
def _fitted_gradient_pair(out, b, s, weights, dvx, dvy, dvz, l):
    """The pair's terms of L: dv (x) G_ab added to a's nine sums `l` (returned), -dv (x) G_ba to b's, columns 3-11
    of its chunk buffer row; dv = v_b - v_a, `weights` (pairs, 6) the pair cache (G_ab, G_ba)."""
    g0 = weights[s, 0]
    g1 = weights[s, 1]
    g2 = weights[s, 2]
    l = (l[0] + dvx * g0, l[1] + dvx * g1, l[2] + dvx * g2, l[3] + dvy * g0, l[4] + dvy * g1, l[5] + dvy * g2,
         l[6] + dvz * g0, l[7] + dvz * g1, l[8] + dvz * g2)
    g0 = weights[s, 3]
    g1 = weights[s, 4]
    g2 = weights[s, 5]
    out[b, 3] -= dvx * g0
    out[b, 4] -= dvx * g1
    out[b, 5] -= dvx * g2
    out[b, 6] -= dvy * g0
    out[b, 7] -= dvy * g1
    out[b, 8] -= dvy * g2
    out[b, 9] -= dvz * g0
    out[b, 10] -= dvz * g1
    out[b, 11] -= dvz * g2
    return l


@njit(cache=True, fastmath=False, error_model="numpy", parallel=True, nogil=True)
def xsph_velocity_and_mls_gradient(state, neighbours, prm, work):
    """XSPH velocity, eq. (4), and the quadratic-fit velocity gradient L_a = sum_b (v_b - v_a) (x) G_ab, into
    work.vhat and work.grad_v.

    Half list with per-chunk buffers (work.buf, chunks x N x >= 12), as gray2001.xsph_velocity_and_gradient;
    work.w and work.mls_weights (pairs, 6: G_ab then G_ba) are the pair caches at the current positions
    (mls_pair_weights, momentum_rate_mls). `state`: solid.stepper.SolidArrays, `neighbours`: SolidNeighbours,
    `prm`: SolidParams, `work`: SolidBuffers.
    """
    mass = state.mass
    rho = state.rho
    vel = state.vel
    w = work.w
    weights = work.mls_weights
    vhat = work.vhat
    grad_v = work.grad_v
    buf = work.buf
    start = neighbours.start
    index = neighbours.index
    xsph_eps = prm.xsph_eps
    n = vel.shape[0]
    chunks = buf.shape[0]
    for c in prange(chunks):
        out = buf[c]
        out[:, 0:12] = 0.0
        for a in range(chunk_first_target(start, c, chunks), chunk_first_target(start, c + 1, chunks)):
            # particle a's sums stay in registers; only b's go through the chunk buffer
            xa = ya = za = 0.0
            zero = 0.0
            l = (zero, zero, zero, zero, zero, zero, zero, zero, zero)
            for s in range(unsigned(start[a]), unsigned(start[a + 1])):
                b = index[s]
                dvx = vel[b, 0] - vel[a, 0]
                dvy = vel[b, 1] - vel[a, 1]
                dvz = vel[b, 2] - vel[a, 2]
                xa, ya, za = xsph_pair(out, a, b, mass, rho, w[s], dvx, dvy, dvz, xa, ya, za)
                l = _fitted_gradient_pair(out, b, s, weights, dvx, dvy, dvz, l)
            out[a, 0] += xa
            out[a, 1] += ya
            out[a, 2] += za
            out[a, 3] += l[0]
            out[a, 4] += l[1]
            out[a, 5] += l[2]
            out[a, 6] += l[3]
            out[a, 7] += l[4]
            out[a, 8] += l[5]
            out[a, 9] += l[6]
            out[a, 10] += l[7]
            out[a, 11] += l[8]
    for a in prange(n):
        sum_velocity_chunks(buf, a, vel, xsph_eps, vhat, grad_v)


@njit(cache=True, fastmath=False, error_model="numpy", parallel=True, nogil=True)
def mls_pair_weights(pos, period, mass, rho, start, index, h, rows, weights):
    """The pair cache `weights` (pairs, 6) = (G_ab, G_ba) at the current positions (after a list build)."""
    half_period = 0.5 * period
    inv_h = 1.0 / h
    for a in prange(pos.shape[0]):
        va = mass[a] / rho[a]
        for s in range(unsigned(start[a]), unsigned(start[a + 1])):
            b = index[s]
            ux, uy, uz, wab = _scaled_offset_and_weight(pos, a, b, period, half_period, h, inv_h)
            _store_pair_weights(rows, a, b, ux, uy, uz, mass[b] / rho[b] * wab * inv_h, va * wab * inv_h, weights, s)


@njit(cache=True, fastmath=False, error_model="numpy", parallel=True, nogil=True)
def velocity_divergence_rate(rho, grad_v, drho):
    """Eq. (3) with the fitted gradient: d rho_a/dt = -rho_a tr(L_a)."""
    for a in prange(rho.shape[0]):
        drho[a] = -rho[a] * (grad_v[a, 0, 0] + grad_v[a, 1, 1] + grad_v[a, 2, 2])


# block columns of the momentum pass (pair_blocks.py): the pair's motion, b's mass and R_b, then the pair's results
_RX, _RY, _RZ = SEPARATION, SEPARATION + 1, SEPARATION + 2
_RHO_B = NEIGHBOUR_DENSITY
(_MASS_B, _R_B, _R2, _W, _F, _G_AB, _F_A, _F_AV, _F_GRAD_A) = tuple(MOTION_COLUMNS + k for k in (0, 1, 7, 8, 9, 10,
                                                                                               13, 16, 19))
MOMENTUM_BLOCK_COLUMNS = 29   # _R_B: six columns (R_b); _G_AB, _F_A, _F_AV, _F_GRAD_A: three each


@njit(cache=True, fastmath=False, error_model="numpy", inline="always")
def _rows_tuple(r):
    """Rows 0..2 of a particle's fit (3 x 9) as nested tuples: values the compiler keeps in registers."""
    return ((r[0, 0], r[0, 1], r[0, 2], r[0, 3], r[0, 4], r[0, 5], r[0, 6], r[0, 7], r[0, 8]),
            (r[1, 0], r[1, 1], r[1, 2], r[1, 3], r[1, 4], r[1, 5], r[1, 6], r[1, 7], r[1, 8]),
            (r[2, 0], r[2, 1], r[2, 2], r[2, 3], r[2, 4], r[2, 5], r[2, 6], r[2, 7], r[2, 8]))


@njit(cache=True, fastmath=False, error_model="numpy", inline="always")
def _mls_pair(block, j, rows_a, sa, ra, force_rows_a, mass_a, rho_a, ka, terms, art_exponent, gradient_integration):
    """Pair j of a block in _mls_pair_block; rows_a, sa, ra: particle a's fit rows, sigma / rho^2 and R_a as
    tuples (values kept in registers); `terms`: gray2001.PairTerms."""
    inv_h = terms.inv_h
    sa0, sa1, sa2, sa3, sa4, sa5 = sa
    rx = block[_RX * STRIDE + j]
    ry = block[_RY * STRIDE + j]
    rz = block[_RZ * STRIDE + j]
    r2 = rx * rx + ry * ry + rz * rz
    block[_R2 * STRIDE + j] = r2
    wab, fab = cubic_spline_wf(math.sqrt(r2), inv_h, terms.sigma)
    block[_W * STRIDE + j] = wab
    block[_F * STRIDE + j] = fab
    ux = -rx * inv_h
    uy = -ry * inv_h
    uz = -rz * inv_h
    qxx, qyy, qzz, qxy, qxz, qyz = quadratic_monomials(ux, uy, uz)
    v_b = block[_MASS_B * STRIDE + j] / block[_RHO_B * STRIDE + j]
    gab0, gab1, gab2 = _pair_weight_vector(rows_a, ux, uy, uz, qxx, qyy, qzz, qxy, qxz, qyz, v_b * wab * inv_h)
    block[_G_AB * STRIDE + j] = gab0
    block[(_G_AB + 1) * STRIDE + j] = gab1
    block[(_G_AB + 2) * STRIDE + j] = gab2
    # V sigma = m rho (sigma / rho^2)
    block[_F_A * STRIDE + j] = ka * (sa0 * gab0 + sa3 * gab1 + sa4 * gab2)
    block[(_F_A + 1) * STRIDE + j] = ka * (sa3 * gab0 + sa1 * gab1 + sa5 * gab2)
    block[(_F_A + 2) * STRIDE + j] = ka * (sa4 * gab0 + sa5 * gab1 + sa2 * gab2)
    txx, tyy, tzz, txy, txz, tyz = viscous_and_artificial_stress_terms(block, j, _R_B, ra, rho_a, rx, ry, rz, r2, wab,
                                                                       terms, art_exponent)
    mm = mass_a * block[_MASS_B * STRIDE + j]
    gx = fab * rx
    gy = fab * ry
    gz = fab * rz
    block[_F_AV * STRIDE + j] = mm * (txx * gx + txy * gy + txz * gz)
    block[(_F_AV + 1) * STRIDE + j] = mm * (txy * gx + tyy * gy + tyz * gz)
    block[(_F_AV + 2) * STRIDE + j] = mm * (txz * gx + tyz * gy + tzz * gz)
    if gradient_integration:
        s_ab = v_b * wab * inv_h * inv_h
        block[_F_GRAD_A * STRIDE + j] = s_ab * basis_dot(force_rows_a[0], ux, uy, uz)
        block[(_F_GRAD_A + 1) * STRIDE + j] = s_ab * basis_dot(force_rows_a[1], ux, uy, uz)
        block[(_F_GRAD_A + 2) * STRIDE + j] = s_ab * basis_dot(force_rows_a[2], ux, uy, uz)


def pair_variant(gradient_integration, art_exponent):
    """The momentum pass's setting as a type, for _mls_pair_block: a tuple of zeros whose length says whether the
    strain-gradient integration is on (lengths 0-2) or off (3-5) and which artificial stress (none, Gray's n = 4,
    another n). Numba compiles a function once per argument type, and the length of a tuple is part of its type,
    so a run compiles the one loop its setting takes rather than all six (31.8 of a cold 211 s, 2026-12-04)."""
    art = 0 if art_exponent == 0 else 1 if art_exponent == 4 else 2
    return (0,) * ((0 if gradient_integration else 3) + art)


@njit(cache=True, fastmath=False, error_model="numpy", nogil=True)
def _mls_pair_block(block, m, rows_a, sa, ra, force_rows_a, mass_a, rho_a, ka, terms, art_exponent, variant):
    """What particle a contributes to the pair terms of momentum_rate_mls, for the m pairs of a block: r^2, W_ab,
    F_ab, G_ab = (V_b W_ab / h) R_a p(u), a's stress part V_a sigma_a G_ab (_F_A), the viscosity and artificial
    stress part (_F_AV) and a's half of the stress gradient's force (_F_GRAD_A). b's parts need b's fit rows and
    are added per pair in the scatter loop.

    One loop per setting (`variant`, pair_variant: no artificial stress, Gray's n = 4, another n; with or without
    the gradient integration), each with its options as constants: a branch inside a SIMD loop runs both sides on
    every pair. The setting is the tuple's length, a constant of its type, so only its own loop is compiled.
    `terms`: gray2001.PairTerms."""
    sa = (sa[XX], sa[YY], sa[ZZ], sa[XY], sa[XZ], sa[YZ])
    ra = (ra[XX], ra[YY], ra[ZZ], ra[XY], ra[XZ], ra[YZ])
    rows_a = _rows_tuple(rows_a)
    if len(variant) == 0:
        for j in range(m):
            _mls_pair(block, j, rows_a, sa, ra, force_rows_a, mass_a, rho_a, ka, terms, 0, True)
    elif len(variant) == 1:
        for j in range(m):
            _mls_pair(block, j, rows_a, sa, ra, force_rows_a, mass_a, rho_a, ka, terms, 4, True)
    elif len(variant) == 2:
        for j in range(m):
            _mls_pair(block, j, rows_a, sa, ra, force_rows_a, mass_a, rho_a, ka, terms, art_exponent, True)
    elif len(variant) == 3:
        for j in range(m):
            _mls_pair(block, j, rows_a, sa, ra, force_rows_a, mass_a, rho_a, ka, terms, 0, False)
    elif len(variant) == 4:
        for j in range(m):
            _mls_pair(block, j, rows_a, sa, ra, force_rows_a, mass_a, rho_a, ka, terms, 4, False)
    else:
        for j in range(m):
            _mls_pair(block, j, rows_a, sa, ra, force_rows_a, mass_a, rho_a, ka, terms, art_exponent, False)


@njit(cache=True, fastmath=False, error_model="numpy", inline="always")
def _gather_mls_block(block, a, lo, m, state, neighbours, half_period, work, h, art_exponent):
    """Pairs lo..lo+m-1 of a's row into the block's columns (pair_blocks.py): the pair's motion, b's mass and R_b
    (with the artificial stress); r_a - r_b through the minimum image on a row that may need it
    (NeighbourList.crossing)."""
    pos = state.pos
    vel = state.vel
    mass = state.mass
    index = neighbours.index
    period = neighbours.period
    gather_motion(block, index, lo, m, a, pos, vel, state.rho, h)
    for j in range(m):
        block[_MASS_B * STRIDE + j] = mass[index[unsigned(lo + j)]]
    pad_block(block, m, _MASS_B, 0.0, 0, 0, 0.0)
    if art_exponent > 0:
        gather_tensors(block, _R_B, index, lo, m, work.art_stress)
    if (period[0] > 0.0 or period[1] > 0.0 or period[2] > 0.0) and neighbours.crossing[a]:
        minimum_image_block(block, _RX, m, period, half_period)


@njit(cache=True, fastmath=False, error_model="numpy", inline="always")
def _pair_weights_ba(block, j, s, rows_b, va, inv_h, weights):
    """The pair's weights G_ab (from the block) and G_ba = (V_a W_ab / h) R_b p(-u) into the pair cache `weights`
    (pairs, 6); returns u = (x_b - x_a) / h, W_ab and G_ba."""
    wab = block[_W * STRIDE + j]
    ux = -block[_RX * STRIDE + j] * inv_h
    uy = -block[_RY * STRIDE + j] * inv_h
    uz = -block[_RZ * STRIDE + j] * inv_h
    qxx, qyy, qzz, qxy, qxz, qyz = quadratic_monomials(ux, uy, uz)
    gba0, gba1, gba2 = _pair_weight_vector(rows_b, -ux, -uy, -uz, qxx, qyy, qzz, qxy, qxz, qyz, va * wab * inv_h)
    weights[s, 0] = block[_G_AB * STRIDE + j]
    weights[s, 1] = block[(_G_AB + 1) * STRIDE + j]
    weights[s, 2] = block[(_G_AB + 2) * STRIDE + j]
    weights[s, 3] = gba0
    weights[s, 4] = gba1
    weights[s, 5] = gba2
    return ux, uy, uz, wab, gba0, gba1, gba2


@njit(cache=True, fastmath=False, error_model="numpy", inline="always")
def _pair_force(block, j, kb, sb, gba0, gba1, gba2):
    """The pair's force F_ab on a: the stress part V_a sigma_a G_ab - V_b sigma_b G_ba (a's from the block, b's
    with kb = m_b rho_b, V_b sigma_b = kb sigma_b / rho_b^2 = kb sb) plus the viscosity and artificial stress."""
    fx = (block[_F_A * STRIDE + j] - kb * (sb[XX] * gba0 + sb[XY] * gba1 + sb[XZ] * gba2))
    fy = (block[(_F_A + 1) * STRIDE + j] - kb * (sb[XY] * gba0 + sb[YY] * gba1 + sb[YZ] * gba2))
    fz = (block[(_F_A + 2) * STRIDE + j] - kb * (sb[XZ] * gba0 + sb[YZ] * gba1 + sb[ZZ] * gba2))
    fx += block[_F_AV * STRIDE + j]
    fy += block[(_F_AV + 1) * STRIDE + j]
    fz += block[(_F_AV + 2) * STRIDE + j]
    return fx, fy, fz


@njit(cache=True, fastmath=False, error_model="numpy", inline="always")
def _gradient_force(block, j, s_ba, force_rows_b, ux, uy, uz, fx, fy, fz):
    """The stress gradient's pair force Phi_ab - Phi_ba added to (fx, fy, fz): a's half from the block, b's
    s_ba A_b[i] . p(-u) (solid/gradient_integration.py)."""
    fx += block[_F_GRAD_A * STRIDE + j] - s_ba * basis_dot(force_rows_b[0], -ux, -uy, -uz)
    fy += block[(_F_GRAD_A + 1) * STRIDE + j] - s_ba * basis_dot(force_rows_b[1], -ux, -uy, -uz)
    fz += block[(_F_GRAD_A + 2) * STRIDE + j] - s_ba * basis_dot(force_rows_b[2], -ux, -uy, -uz)
    return fx, fy, fz


@njit(cache=True, fastmath=False, error_model="numpy", inline="always")
def _scatter_mls_block(block, a, lo, m, state, index, work, va, inv_h, support2, gradient_integration, out, fax, fay,
                       faz):
    """The block's pairs as b sees them: the pair caches (w, f and the weights G_ab, G_ba; zeros for a pair in the
    list's skin beyond the support), the pair force F_ab added to a's sums (returned) and -F_ab to b's chunk buffer
    row; pairs of two clamp particles only refresh the caches."""
    mass = state.mass
    rho = state.rho
    movable = state.movable
    w = work.w
    f = work.f
    weights = work.mls_weights
    rows = work.mls_rows
    sigma_over_rho2 = work.sigma_over_rho2
    force_rows = work.force_rows
    movable_a = movable[a]
    for j in range(m):
        s = unsigned(lo + j)
        if block[_R2 * STRIDE + j] >= support2:   # in the list's skin, outside the kernel: idle
            w[s] = 0.0
            f[s] = 0.0
            for k in range(6):
                weights[s, k] = 0.0
            continue
        b = index[s]
        w[s] = block[_W * STRIDE + j]
        f[s] = block[_F * STRIDE + j]
        ux, uy, uz, wab, gba0, gba1, gba2 = _pair_weights_ba(block, j, s, rows[b], va, inv_h, weights)
        if not (movable_a or movable[b]):
            continue
        fx, fy, fz = _pair_force(block, j, mass[b] * rho[b], sigma_over_rho2[b], gba0, gba1, gba2)
        if gradient_integration:
            fx, fy, fz = _gradient_force(block, j, va * wab * inv_h * inv_h, force_rows[b], ux, uy, uz, fx, fy, fz)
        # forces here, accelerations once per particle below (one division instead of six per pair)
        fax += fx
        fay += fy
        faz += fz
        out[b, 0] -= fx
        out[b, 1] -= fy
        out[b, 2] -= fz
    return fax, fay, faz


@njit(cache=True, fastmath=False, error_model="numpy", parallel=True, nogil=True)
def momentum_rate_mls(state, neighbours, prm, work, body_acc, variant):
    """Eq. (5) with the stress acting through the fitted gradient weights (the force paired with L_a above), into
    state.acc (body_acc added).

    Stress part of the pair: F_ab = V_a sigma_a G_ab - V_b sigma_b G_ba (+F on a, -F on b). The artificial
    viscosity and artificial stress keep Gray's pair form m_a m_b (-Pi_ab I + R_ab f_ab^n) . grad_a W_ab.
    work.sigma_over_rho2 is sigma / rho^2, so V sigma = m rho (sigma / rho^2). Refreshes the pair caches (work.w,
    work.f and the weights G_ab, G_ba in work.mls_weights) for the next step's gradient pass. Pairs in the list's
    skin but beyond the kernel's support get zeros in the caches and no force; so do pairs of two clamp particles
    (state.movable False), whose forces act on no moving particle (with the mirrored clamp they would move the
    ghosts' images: the ghosts' relative motion is not the material's). Forces are summed per pair and divided by
    the mass once per particle. With the strain-gradient nodal integration (work.force_rows (N, 3, 9) from
    gradient_force_rows; empty when it is off) the pair also carries the stress gradient's force (Phi_ab - Phi_ba of
    solid/gradient_integration.py), here where u and W_ab are at hand rather than in a pass of its own.

    In blocks (pair_blocks.py; work.blocks: per-chunk scratch of MOMENTUM_BLOCK_COLUMNS columns): what needs only
    particle a's rows and stress runs in SIMD lanes (_mls_pair_block); b's weights G_ba, its stress part and its
    half of the gradient force, which need b's 27 fit numbers (27 more with the gradient integration), per pair in
    the scatter loop, where they are read in place. `variant`: pair_variant(gradient integration on,
    art_exponent), the setting as a type (stepper.driver_variant). Arguments as in xsph_velocity_and_mls_gradient.
    """
    mass = state.mass
    rho = state.rho
    acc = state.acc
    sigma_over_rho2 = work.sigma_over_rho2
    art_stress = work.art_stress
    rows = work.mls_rows
    force_rows = work.force_rows
    buf = work.vector_buf
    blocks = work.blocks
    start = neighbours.start
    index = neighbours.index
    h = prm.h
    art_exponent = prm.art_exponent
    terms = pair_terms(prm)
    inv_h = terms.inv_h
    support2 = support_squared(h)
    half_period = 0.5 * neighbours.period
    n = mass.shape[0]
    gradient_integration = force_rows.shape[0] == n
    if gradient_integration != (len(variant) < 3):
        raise ValueError("momentum_rate_mls: the pair variant does not match force_rows (pair_variant)")
    chunks = buf.shape[0]
    for c in prange(chunks):
        out = buf[c]
        block = blocks[c]
        out[:, 0:3] = 0.0
        for a in range(chunk_first_target(start, c, chunks), chunk_first_target(start, c + 1, chunks)):
            va = mass[a] / rho[a]
            fax = fay = faz = 0.0
            for lo in range(start[a], start[a + 1], BLOCK):
                m = min(BLOCK, start[a + 1] - lo)
                _gather_mls_block(block, a, lo, m, state, neighbours, half_period, work, h, art_exponent)
                _mls_pair_block(block, padded(m), rows[a], sigma_over_rho2[a], art_stress[a],
                                force_rows[a] if gradient_integration else rows[a], mass[a], rho[a],
                                mass[a] * rho[a], terms, art_exponent, variant)
                fax, fay, faz = _scatter_mls_block(block, a, lo, m, state, index, work, va, inv_h, support2,
                                                   gradient_integration, out, fax, fay, faz)
            out[a, 0] += fax
            out[a, 1] += fay
            out[a, 2] += faz
    for a in prange(n):
        inv_m = 1.0 / mass[a]
        for k in range(3):
            total = 0.0
            for c in range(chunks):
                total += buf[c, a, k]
            acc[a, k] = body_acc[k] + total * inv_m
