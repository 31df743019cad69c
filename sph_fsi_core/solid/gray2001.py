"""Elastic solid of Gray, Monaghan & Swift (2001) in 3D, as used by Satake et al. (sec. 2.1, eqs. (3)-(5)).

Each function is one pass: an equation's right-hand side over the half pair list (each pair once, b > a; see
neighbours.py), or one per-particle update. State per solid particle: position, velocity, density rho, deviatoric
stress S (N, 6 in the XX, YY, ZZ, XY, XZ, YZ order of tensors.py). The full stress is sigma = -p I + S with
p = c0^2 (rho - rho0).

Sign of the artificial viscosity (METHOD 'Open (sign)'): Pi_ab here is Monaghan's, (-alpha cbar mu + beta mu^2)
/ rhobar with mu = h v_ab.r_ab / (r_ab^2 + 0.01 h^2) for approaching pairs (v_ab.r_ab < 0), so Pi_ab >= 0. It
must act like a pressure, so it enters eq. (5)'s bracket as -Pi_ab delta^ij next to sigma/rho^2 = -p/rho^2 I.
(The paper's "+Pi delta" is Gray's convention, whose Pi carries the opposite sign.) test_solid_physics checks
that it removes energy.
"""
import math
from typing import NamedTuple

from numba import njit, prange

from ..numerics.kernels import cubic_spline_wf, kernel_normalisation
from ..numerics.neighbours import chunk_first_target, unsigned
from ..numerics.periodic import pair_separation
from ..numerics.pair_blocks import (BLOCK, MOTION_COLUMNS, NEIGHBOUR_DENSITY, SEPARATION, STRIDE, VELOCITY_DIFFERENCE,
                          gather_motion, gather_tensors, minimum_image_block, pad_block, padded)
from ..numerics.tensors import XX, XY, XZ, YY, YZ, ZZ, symmetric_eigen


@njit(cache=True, fastmath=False, error_model="numpy", nogil=True)
def material_constants(young_modulus, poisson_ratio, density):
    """Bulk modulus K = E/(3(1-2nu)), shear modulus G = E/(2(1+nu)), sound speed c0 = sqrt(K/rho0)."""
    bulk = young_modulus / (3.0 * (1.0 - 2.0 * poisson_ratio))
    shear = young_modulus / (2.0 * (1.0 + poisson_ratio))
    return bulk, shear, math.sqrt(bulk / density)


@njit(cache=True, fastmath=False, error_model="numpy", inline="always")
def sum_velocity_chunks(buf, a, vel, xsph_eps, vhat, grad_v):
    """Particle a's XSPH velocity (columns 0-2) and velocity gradient (3-11) from the per-chunk sums in `buf`."""
    chunks = buf.shape[0]
    for k in range(3):
        acc = 0.0
        for c in range(chunks):
            acc += buf[c, a, k]
        vhat[a, k] = vel[a, k] + xsph_eps * acc
    for i in range(3):
        for j in range(3):
            acc = 0.0
            for c in range(chunks):
                acc += buf[c, a, 3 + 3 * i + j]
            grad_v[a, i, j] = acc


@njit(cache=True, fastmath=False, error_model="numpy", inline="always")
def xsph_pair(out, a, b, mass, rho, w_ab, dvx, dvy, dvz, x0, x1, x2):
    """Eq. (4)'s pair term m_b W_ab / rhobar (v_b - v_a) added to a's sums (x0, x1, x2, returned) and, with m_a and
    the opposite sign, to b's in columns 0-2 of its chunk buffer row; dv = v_b - v_a."""
    k = w_ab / (0.5 * (rho[a] + rho[b]))
    out[b, 0] -= mass[a] * k * dvx
    out[b, 1] -= mass[a] * k * dvy
    out[b, 2] -= mass[a] * k * dvz
    return x0 + mass[b] * k * dvx, x1 + mass[b] * k * dvy, x2 + mass[b] * k * dvz


@njit(cache=True, fastmath=False, error_model="numpy", inline="always")
def _gradient_pair(out, b, va, vb, dvx, dvy, dvz, gx, gy, gz, l):
    """The velocity gradient's pair term dv (x) g, g = grad_a W_ab: V_b times it added to a's nine sums `l`
    (returned) and V_a times it to b's, columns 3-11 of its chunk buffer row (grad_b W_ba = -g, v_a - v_b = -dv)."""
    o00 = dvx * gx
    o01 = dvx * gy
    o02 = dvx * gz
    o10 = dvy * gx
    o11 = dvy * gy
    o12 = dvy * gz
    o20 = dvz * gx
    o21 = dvz * gy
    o22 = dvz * gz
    out[b, 3] += va * o00
    out[b, 4] += va * o01
    out[b, 5] += va * o02
    out[b, 6] += va * o10
    out[b, 7] += va * o11
    out[b, 8] += va * o12
    out[b, 9] += va * o20
    out[b, 10] += va * o21
    out[b, 11] += va * o22
    return (l[0] + vb * o00, l[1] + vb * o01, l[2] + vb * o02, l[3] + vb * o10, l[4] + vb * o11, l[5] + vb * o12,
            l[6] + vb * o20, l[7] + vb * o21, l[8] + vb * o22)


@njit(cache=True, fastmath=False, error_model="numpy", inline="always")
def _correction_pair(out, b, va, vb, rx, ry, rz, gx, gy, gz, k):
    """The pair's term of K_a = sum_b V_b (r_b - r_a) (x) grad_a W_ab, -(r_ab (x) g), the same seen from both sides
    (r_ab (x) g is symmetric): V_b times it added to a's six sums `k` (returned), V_a times it to b's, columns
    12-17 of its chunk buffer row."""
    q00 = -rx * gx
    q01 = -rx * gy
    q02 = -rx * gz
    q11 = -ry * gy
    q12 = -ry * gz
    q22 = -rz * gz
    out[b, 12] += va * q00
    out[b, 13] += va * q01
    out[b, 14] += va * q02
    out[b, 15] += va * q11
    out[b, 16] += va * q12
    out[b, 17] += va * q22
    return k[0] + vb * q00, k[1] + vb * q01, k[2] + vb * q02, k[3] + vb * q11, k[4] + vb * q12, k[5] + vb * q22


@njit(cache=True, fastmath=False, error_model="numpy", inline="always")
def _gradient_row(a, out, pos, half_period, mass, rho, volume, vel, neighbours, w, f, correct_gradient):
    """Target a's row of xsph_velocity_and_gradient: its sums stay in registers, b's go through the chunk buffer
    `out`, and a's are added to it at the end (columns 0-2 XSPH, 3-11 L, 12-17 K)."""
    start = neighbours.start
    index = neighbours.index
    period = neighbours.period
    va = volume[a]
    wrap = neighbours.crossing[a]
    x0 = x1 = x2 = 0.0
    zero = 0.0
    l = (zero, zero, zero, zero, zero, zero, zero, zero, zero)
    k = (zero, zero, zero, zero, zero, zero)
    for s in range(unsigned(start[a]), unsigned(start[a + 1])):
        b = index[s]
        vb = volume[b]
        fs = f[s]
        rx, ry, rz = pair_separation(pos, a, b, period, half_period, wrap)
        gx = fs * rx
        gy = fs * ry
        gz = fs * rz
        dvx = vel[b, 0] - vel[a, 0]
        dvy = vel[b, 1] - vel[a, 1]
        dvz = vel[b, 2] - vel[a, 2]
        x0, x1, x2 = xsph_pair(out, a, b, mass, rho, w[s], dvx, dvy, dvz, x0, x1, x2)
        l = _gradient_pair(out, b, va, vb, dvx, dvy, dvz, gx, gy, gz, l)
        if correct_gradient:
            k = _correction_pair(out, b, va, vb, rx, ry, rz, gx, gy, gz, k)
    out[a, 0] += x0
    out[a, 1] += x1
    out[a, 2] += x2
    out[a, 3] += l[0]
    out[a, 4] += l[1]
    out[a, 5] += l[2]
    out[a, 6] += l[3]
    out[a, 7] += l[4]
    out[a, 8] += l[5]
    out[a, 9] += l[6]
    out[a, 10] += l[7]
    out[a, 11] += l[8]
    if correct_gradient:
        out[a, 12] += k[0]
        out[a, 13] += k[1]
        out[a, 14] += k[2]
        out[a, 15] += k[3]
        out[a, 16] += k[4]
        out[a, 17] += k[5]


@njit(cache=True, fastmath=False, error_model="numpy", inline="always")
def _corrected_gradient(buf, a, grad_v, kinv):
    """K_a^-1 (symmetric, from its six per-chunk sums in columns 12-17 of `buf`) into kinv[a], and L_a K_a^-1 in
    place of L_a: the gradient exact for linear fields (Bonet & Lok 1999). A particle with too few neighbours
    (|det K| <= 1e-3) keeps the plain gradient, K^-1 = I."""
    chunks = buf.shape[0]
    k00 = k01 = k02 = k11 = k12 = k22 = 0.0
    for c in range(chunks):
        k00 += buf[c, a, 12]
        k01 += buf[c, a, 13]
        k02 += buf[c, a, 14]
        k11 += buf[c, a, 15]
        k12 += buf[c, a, 16]
        k22 += buf[c, a, 17]
    c00 = k11 * k22 - k12 * k12
    c01 = k02 * k12 - k01 * k22
    c02 = k01 * k12 - k02 * k11
    det = k00 * c00 + k01 * c01 + k02 * c02
    if abs(det) > 1e-3:
        kinv[a, 0, 0] = c00 / det
        kinv[a, 0, 1] = kinv[a, 1, 0] = c01 / det
        kinv[a, 0, 2] = kinv[a, 2, 0] = c02 / det
        kinv[a, 1, 1] = (k00 * k22 - k02 * k02) / det
        kinv[a, 1, 2] = kinv[a, 2, 1] = (k01 * k02 - k00 * k12) / det
        kinv[a, 2, 2] = (k00 * k11 - k01 * k01) / det
        for i in range(3):
            l0 = grad_v[a, i, 0]
            l1 = grad_v[a, i, 1]
            l2 = grad_v[a, i, 2]
            for j in range(3):
                grad_v[a, i, j] = l0 * kinv[a, 0, j] + l1 * kinv[a, 1, j] + l2 * kinv[a, 2, j]
    else:
        for i in range(3):
            for j in range(3):
                kinv[a, i, j] = 1.0 if i == j else 0.0


@njit(cache=True, fastmath=False, error_model="numpy", parallel=True, nogil=True)
def xsph_velocity_and_gradient(state, neighbours, prm, work):
    """XSPH-averaged velocity, eq. (4), and the velocity gradient
    L^ij_a = sum_b (m_b/rho_b)(v_b^i - v_a^i) dW_ab/dx_a^j, into work.vhat and work.grad_v.

    One pass over the half list (each pair once): with g = grad_a W_ab and dv = v_b - v_a, the pair adds
    V_b dv (x) g to L_a and V_a dv (x) g to L_b (grad_b W_ba = -g and v_a - v_b = -dv), and m/rhobar W dv with
    opposite signs to the two XSPH sums. Each chunk of rows accumulates into its own slice of work.buf
    (chunks, N, 21), so there are no write races; a second loop sums the chunks. work.volume: V = m / rho per
    particle (solid.stepper.particle_volumes); work.w, work.f: the pair cache.

    With prm.gradient_order 1 (the corrected gradient) also sum K_a = sum_b V_b (r_b - r_a) (x) grad_a W_ab and
    return L K^-1, the velocity gradient that is exact for linear fields also where the kernel is truncated (free
    surfaces); K^-1 is left in work.kinv (N, 3, 3) for the momentum pass. Not in the paper (Gray 2001 uses the plain
    sum); a scene option.

    `state`: solid.stepper.SolidArrays, `neighbours`: SolidNeighbours (its `crossing`: per row, whether its pairs
    may need the minimum image; the other rows take plain differences, the same bits), `prm`: SolidParams, `work`:
    SolidBuffers.
    """
    pos = state.pos
    mass = state.mass
    rho = state.rho
    vel = state.vel
    volume = work.volume
    w = work.w
    f = work.f
    vhat = work.vhat
    grad_v = work.grad_v
    buf = work.buf
    kinv = work.kinv
    start = neighbours.start
    correct_gradient = prm.gradient_order == 1
    xsph_eps = prm.xsph_eps
    half_period = 0.5 * neighbours.period
    n = vel.shape[0]
    chunks = buf.shape[0]
    for c in prange(chunks):
        out = buf[c]
        out[:, 0:18 if correct_gradient else 12] = 0.0
        for a in range(chunk_first_target(start, c, chunks), chunk_first_target(start, c + 1, chunks)):
            _gradient_row(a, out, pos, half_period, mass, rho, volume, vel, neighbours, w, f, correct_gradient)
    for a in prange(n):
        sum_velocity_chunks(buf, a, vel, xsph_eps, vhat, grad_v)
        if correct_gradient:
            _corrected_gradient(buf, a, grad_v, kinv)


@njit(cache=True, fastmath=False, error_model="numpy", parallel=True, nogil=True)
def continuity_rate(state, neighbours, work):
    """Eq. (3): d rho_a/dt = rho_a sum_b (m_b/rho_b) (vhat_a - vhat_b) . grad_a W_ab, into work.drho.

    Half list: the pair's (vhat_a - vhat_b) . grad_a W_ab is the same seen from b, so it adds V_b times it to a's
    sum and V_a times it to b's (chunked buffers as in xsph_velocity_and_gradient, here work.scalar_buf (chunks, N):
    a column of the wide buffer would pull all of it through the cache for one number per particle). work.volume:
    V = m / rho per particle, divided once per step rather than once per pair (solid.stepper.particle_volumes).
    Arguments as in xsph_velocity_and_gradient.
    """
    pos = state.pos
    rho = state.rho
    volume = work.volume
    vhat = work.vhat
    f = work.f
    drho = work.drho
    buf = work.scalar_buf
    start = neighbours.start
    index = neighbours.index
    crossing = neighbours.crossing
    period = neighbours.period
    half_period = 0.5 * period
    n = vhat.shape[0]
    chunks = buf.shape[0]
    for c in prange(chunks):
        out = buf[c]
        out[:] = 0.0
        for a in range(chunk_first_target(start, c, chunks), chunk_first_target(start, c + 1, chunks)):
            va = volume[a]
            wrap = crossing[a]
            da = 0.0
            for s in range(unsigned(start[a]), unsigned(start[a + 1])):
                b = index[s]
                rx, ry, rz = pair_separation(pos, a, b, period, half_period, wrap)
                d = f[s] * ((vhat[a, 0] - vhat[b, 0]) * rx + (vhat[a, 1] - vhat[b, 1]) * ry
                            + (vhat[a, 2] - vhat[b, 2]) * rz)
                da += volume[b] * d
                out[b] += va * d
            out[a] += da
    for a in prange(n):
        acc = 0.0
        for c in range(chunks):
            acc += buf[c, a]
        drho[a] = rho[a] * acc


@njit(cache=True, fastmath=False, error_model="numpy", parallel=True, nogil=True)
def jaumann_stress_rate(grad_v, stress, shear_modulus, dstress):
    """Hooke's law in Jaumann-rate form (Gray 2001, eq. (9)-(10) there; METHOD sec. 1):

    dS/dt = 2G (epsdot - tr(epsdot) I / 3) + S Omega^T + Omega S,
    epsdot = (L + L^T)/2, Omega = (L - L^T)/2.
    """
    for a in prange(stress.shape[0]):
        L = grad_v[a]
        exx = L[0, 0]
        eyy = L[1, 1]
        ezz = L[2, 2]
        exy = 0.5 * (L[0, 1] + L[1, 0])
        exz = 0.5 * (L[0, 2] + L[2, 0])
        eyz = 0.5 * (L[1, 2] + L[2, 1])
        wxy = 0.5 * (L[0, 1] - L[1, 0])
        wxz = 0.5 * (L[0, 2] - L[2, 0])
        wyz = 0.5 * (L[1, 2] - L[2, 1])
        trace3 = (exx + eyy + ezz) / 3.0
        sxx = stress[a, XX]
        syy = stress[a, YY]
        szz = stress[a, ZZ]
        sxy = stress[a, XY]
        sxz = stress[a, XZ]
        syz = stress[a, YZ]
        # S Omega^T + Omega S = Omega S - S Omega, written out for
        # Omega = [[0, wxy, wxz], [-wxy, 0, wyz], [-wxz, -wyz, 0]] (checked against NumPy in the tests).
        rxx = 2.0 * (wxy * sxy + wxz * sxz)
        ryy = 2.0 * (-wxy * sxy + wyz * syz)
        rzz = 2.0 * (-wxz * sxz - wyz * syz)
        rxy = wxy * syy + wxz * syz - sxx * wxy + sxz * wyz
        rxz = wxy * syz + wxz * szz - sxx * wxz - sxy * wyz
        ryz = -wxy * sxz + wyz * szz - sxy * wxz - syy * wyz
        dstress[a, XX] = 2.0 * shear_modulus * (exx - trace3) + rxx
        dstress[a, YY] = 2.0 * shear_modulus * (eyy - trace3) + ryy
        dstress[a, ZZ] = 2.0 * shear_modulus * (ezz - trace3) + rzz
        dstress[a, XY] = 2.0 * shear_modulus * exy + rxy
        dstress[a, XZ] = 2.0 * shear_modulus * exz + rxz
        dstress[a, YZ] = 2.0 * shear_modulus * eyz + ryz


@njit(cache=True, fastmath=False, error_model="numpy", parallel=True, nogil=True)
def stress_terms(stress, rho, rho0, c0_squared, art_eps, pressure, sigma_over_rho2, art_stress, eig_work):
    """Per particle: p = c0^2 (rho - rho0); sigma/rho^2 with sigma = -pI + S; Gray's artificial stress R_a.

    R_a: in the principal frame of sigma_a, Rbar^ii = -eps sigma^ii / rho^2 where sigma^ii > 0 (tension), else 0,
    rotated back to x, y, z (Gray 2001 sec. 4; METHOD sec. 1). `eig_work` (N, 10, 3) is scratch for the
    eigen-solver (matrix, eigenvectors, eigenvalues, scratch), so the loop allocates nothing; the eigenvectors are
    kept as the next call's warm start.
    """
    for a in prange(stress.shape[0]):
        p = c0_squared * (rho[a] - rho0)
        pressure[a] = p
        inv_r2 = 1.0 / (rho[a] * rho[a])
        sxx = stress[a, XX] - p
        syy = stress[a, YY] - p
        szz = stress[a, ZZ] - p
        sigma_over_rho2[a, XX] = sxx * inv_r2
        sigma_over_rho2[a, YY] = syy * inv_r2
        sigma_over_rho2[a, ZZ] = szz * inv_r2
        sigma_over_rho2[a, XY] = stress[a, XY] * inv_r2
        sigma_over_rho2[a, XZ] = stress[a, XZ] * inv_r2
        sigma_over_rho2[a, YZ] = stress[a, YZ] * inv_r2
        if art_eps == 0.0:
            for k in range(6):
                art_stress[a, k] = 0.0
            continue
        m = eig_work[a, 0:3]
        q = eig_work[a, 3:6]
        lam = eig_work[a, 6]
        rot = eig_work[a, 7:10]
        m[0, 0] = sxx
        m[1, 1] = syy
        m[2, 2] = szz
        m[0, 1] = m[1, 0] = stress[a, XY]
        m[0, 2] = m[2, 0] = stress[a, XZ]
        m[1, 2] = m[2, 1] = stress[a, YZ]
        symmetric_eigen(m, lam, q, rot)
        for k in range(3):
            lam[k] = -art_eps * lam[k] * inv_r2 if lam[k] > 0.0 else 0.0
        rbar = lam
        # R = Q diag(rbar) Q^T
        art_stress[a, XX] = q[0, 0] * q[0, 0] * rbar[0] + q[0, 1] * q[0, 1] * rbar[1] + q[0, 2] * q[0, 2] * rbar[2]
        art_stress[a, YY] = q[1, 0] * q[1, 0] * rbar[0] + q[1, 1] * q[1, 1] * rbar[1] + q[1, 2] * q[1, 2] * rbar[2]
        art_stress[a, ZZ] = q[2, 0] * q[2, 0] * rbar[0] + q[2, 1] * q[2, 1] * rbar[1] + q[2, 2] * q[2, 2] * rbar[2]
        art_stress[a, XY] = q[0, 0] * q[1, 0] * rbar[0] + q[0, 1] * q[1, 1] * rbar[1] + q[0, 2] * q[1, 2] * rbar[2]
        art_stress[a, XZ] = q[0, 0] * q[2, 0] * rbar[0] + q[0, 1] * q[2, 1] * rbar[1] + q[0, 2] * q[2, 2] * rbar[2]
        art_stress[a, YZ] = q[1, 0] * q[2, 0] * rbar[0] + q[1, 1] * q[2, 1] * rbar[1] + q[1, 2] * q[2, 2] * rbar[2]


@njit(cache=True, fastmath=False, error_model="numpy", inline="always")
def integer_power(x, n):
    """x^n for 0 <= n < 16 by squaring (solid.artificial_stress_exponent is at most MAX_ART_EXPONENT = 12): the
    same steps whatever n is, so a pass computing many pairs at once runs them in SIMD lanes (before session 11, n
    products in a row: the same to the bit for n <= 4, x (x x) = (x x) x; larger n round differently, by an ulp
    or so). Written out: a loop over the bits kept the pass that inlines it from being vectorized."""
    result = 1.0
    if n & 1:
        result *= x
    x2 = x * x
    if n & 2:
        result *= x2
    x4 = x2 * x2
    if n & 4:
        result *= x4
    if n & 8:
        result *= x4 * x4
    return result


class PairTerms(NamedTuple):
    """A momentum pass's constants for its pair terms (pair_terms): the kernel's, Monaghan's viscosity's and Gray's
    artificial stress's, one argument of the block kernels (values, kept in registers)."""
    inv_h: float          # 1 / h
    sigma: float          # 1 / (pi h^3), numerics.kernels.kernel_normalisation
    h: float
    eta2: float           # 0.01 h^2, mu's regulariser
    sound_speed: float    # c of Monaghan's viscosity
    alpha: float
    beta: float
    inv_w_dp: float       # 1 / W(dp), Gray's f_ab = W_ab / W(dp)


@njit(cache=True, fastmath=False, error_model="numpy", inline="always")
def pair_terms(prm):
    """The PairTerms of a solid.stepper.SolidParams."""
    h = prm.h
    return PairTerms(1.0 / h, kernel_normalisation(h), h, 0.01 * h * h, prm.c0, prm.alpha, prm.beta, prm.inv_w_dp)


@njit(cache=True, fastmath=False, error_model="numpy", inline="always")
def viscous_and_artificial_stress_terms(block, j, col_r, ra, rho_a, rx, ry, rz, r2, wab, terms, art_exponent):
    """Pair j's -Pi_ab I + R_ab f_ab^n in eq. (5)'s bracket, as (XX, YY, ZZ, XY, XZ, YZ), for both momentum passes.

    From the pair's block columns (pair_blocks.py): v_a - v_b and rho_b (the motion columns) and R_b (six columns
    from col_r, read when art_exponent > 0); r_a - r_b = (rx, ry, rz), r2 its square; ra: R_a as six numbers;
    `terms`: PairTerms.
    """
    vr = (block[VELOCITY_DIFFERENCE * STRIDE + j] * rx + block[(VELOCITY_DIFFERENCE + 1) * STRIDE + j] * ry
          + block[(VELOCITY_DIFFERENCE + 2) * STRIDE + j] * rz)
    rho_b = block[NEIGHBOUR_DENSITY * STRIDE + j]
    txy = txz = tyz = 0.0
    # branch-free (receding pairs give mu = 0): approaching and receding pairs alternate unpredictably
    mu = terms.h * (vr if vr < 0.0 else 0.0) / (r2 + terms.eta2)   # min(vr, 0) as a select (kernels.positive_part)
    pi_ab = (-terms.alpha * terms.sound_speed * mu + terms.beta * mu * mu) / (0.5 * (rho_a + rho_b))
    txx = tyy = tzz = -pi_ab
    if art_exponent > 0:
        rxx = ra[0] + block[(col_r + XX) * STRIDE + j]
        ryy = ra[1] + block[(col_r + YY) * STRIDE + j]
        rzz = ra[2] + block[(col_r + ZZ) * STRIDE + j]
        rxy = ra[3] + block[(col_r + XY) * STRIDE + j]
        rxz = ra[4] + block[(col_r + XZ) * STRIDE + j]
        ryz = ra[5] + block[(col_r + YZ) * STRIDE + j]
        ratio = wab * terms.inv_w_dp
        if art_exponent == 4:   # Gray's n, the default: two multiplications
            fn = ratio * ratio
            fn *= fn
        else:
            fn = integer_power(ratio, art_exponent)
        txx += rxx * fn
        tyy += ryy * fn
        tzz += rzz * fn
        txy += rxy * fn
        txz += rxz * fn
        tyz += ryz * fn
    return txx, tyy, tzz, txy, txz, tyz


# block columns of the momentum pass (pair_blocks.py): the pair's motion, b's tensors, then the pair's results
_RX, _RY, _RZ = SEPARATION, SEPARATION + 1, SEPARATION + 2
(_S_B, _R_B, _K_B, _GX, _GY, _GZ, _W, _F) = (MOTION_COLUMNS, MOTION_COLUMNS + 6, MOTION_COLUMNS + 12,
                                             MOTION_COLUMNS + 21, MOTION_COLUMNS + 22, MOTION_COLUMNS + 23,
                                             MOTION_COLUMNS + 24, MOTION_COLUMNS + 25)
MOMENTUM_BLOCK_COLUMNS = 33   # _S_B, _R_B: six columns each (b's sigma / rho^2, R_b); _K_B: nine (K_b^-1)


@njit(cache=True, fastmath=False, error_model="numpy", inline="always")
def _momentum_pair(block, j, sa, ra, ka, rho_a, terms, art_exponent, correct_gradient):
    """Pair j of a block in _momentum_pair_block; sa, ra, ka: particle a's sigma / rho^2, R_a and K_a^-1 as tuples
    (values kept in registers); `terms`: PairTerms."""
    sa0, sa1, sa2, sa3, sa4, sa5 = sa
    k00, k01, k02, k10, k11, k12, k20, k21, k22 = ka
    rx = block[_RX * STRIDE + j]
    ry = block[_RY * STRIDE + j]
    rz = block[_RZ * STRIDE + j]
    r2 = rx * rx + ry * ry + rz * rz
    wab, fab = cubic_spline_wf(math.sqrt(r2), terms.inv_h, terms.sigma)
    block[_W * STRIDE + j] = wab
    block[_F * STRIDE + j] = fab
    sb0 = block[(_S_B + XX) * STRIDE + j]
    sb1 = block[(_S_B + YY) * STRIDE + j]
    sb2 = block[(_S_B + ZZ) * STRIDE + j]
    sb3 = block[(_S_B + XY) * STRIDE + j]
    sb4 = block[(_S_B + XZ) * STRIDE + j]
    sb5 = block[(_S_B + YZ) * STRIDE + j]
    if correct_gradient:
        # K_a^-1 g and K_b^-1 g for the two particles' own stresses
        gx = fab * rx
        gy = fab * ry
        gz = fab * rz
        gax = k00 * gx + k01 * gy + k02 * gz
        gay = k10 * gx + k11 * gy + k12 * gz
        gaz = k20 * gx + k21 * gy + k22 * gz
        gbx = (block[_K_B * STRIDE + j] * gx + block[(_K_B + 1) * STRIDE + j] * gy
               + block[(_K_B + 2) * STRIDE + j] * gz)
        gby = (block[(_K_B + 3) * STRIDE + j] * gx + block[(_K_B + 4) * STRIDE + j] * gy
               + block[(_K_B + 5) * STRIDE + j] * gz)
        gbz = (block[(_K_B + 6) * STRIDE + j] * gx + block[(_K_B + 7) * STRIDE + j] * gy
               + block[(_K_B + 8) * STRIDE + j] * gz)
        mx = 0.5 * (gax + gbx)
        my = 0.5 * (gay + gby)
        mz = 0.5 * (gaz + gbz)
        fx = (sa0 * gax + sa3 * gay + sa4 * gaz) + (sb0 * gbx + sb3 * gby + sb4 * gbz)
        fy = (sa3 * gax + sa1 * gay + sa5 * gaz) + (sb3 * gbx + sb1 * gby + sb5 * gbz)
        fz = (sa4 * gax + sa5 * gay + sa2 * gaz) + (sb4 * gbx + sb5 * gby + sb2 * gbz)
        txx = tyy = tzz = txy = txz = tyz = 0.0
    else:
        mx = fab * rx
        my = fab * ry
        mz = fab * rz
        fx = fy = fz = 0.0
        txx = sa0 + sb0
        tyy = sa1 + sb1
        tzz = sa2 + sb2
        txy = sa3 + sb3
        txz = sa4 + sb4
        tyz = sa5 + sb5
    pxx, pyy, pzz, pxy, pxz, pyz = viscous_and_artificial_stress_terms(block, j, _R_B, ra, rho_a, rx, ry, rz, r2, wab,
                                                                       terms, art_exponent)
    txx += pxx
    tyy += pyy
    tzz += pzz
    txy += pxy
    txz += pxz
    tyz += pyz
    block[_GX * STRIDE + j] = fx + txx * mx + txy * my + txz * mz
    block[_GY * STRIDE + j] = fy + txy * mx + tyy * my + tyz * mz
    block[_GZ * STRIDE + j] = fz + txz * mx + tyz * my + tzz * mz


@njit(cache=True, fastmath=False, error_model="numpy", nogil=True)
def _momentum_pair_block(block, m, sa, ra, ka, rho_a, terms, art_exponent, correct_gradient):
    """Eq. (5)'s pair term for the m pairs of a block (momentum_rate): the bracket T_ab dotted with the gradient,
    into _GX.._GZ (particle a gets m_b times it, b minus m_a times it), and W_ab, F_ab into _W, _F.

    sa, ra: particle a's sigma / rho^2 and R_a; ka: its K^-1 (used with correct_gradient); `terms`: PairTerms. One
    loop per setting (no artificial stress, Gray's n = 4, another n; with or without the corrected gradient), each
    with its options as constants: a branch inside a SIMD loop runs both sides on every pair."""
    sa = (sa[XX], sa[YY], sa[ZZ], sa[XY], sa[XZ], sa[YZ])
    ra = (ra[XX], ra[YY], ra[ZZ], ra[XY], ra[XZ], ra[YZ])
    ka = (ka[0, 0], ka[0, 1], ka[0, 2], ka[1, 0], ka[1, 1], ka[1, 2], ka[2, 0], ka[2, 1], ka[2, 2])
    if correct_gradient:
        if art_exponent == 0:
            for j in range(m):
                _momentum_pair(block, j, sa, ra, ka, rho_a, terms, 0, True)
        elif art_exponent == 4:
            for j in range(m):
                _momentum_pair(block, j, sa, ra, ka, rho_a, terms, 4, True)
        else:
            for j in range(m):
                _momentum_pair(block, j, sa, ra, ka, rho_a, terms, art_exponent, True)
    else:
        if art_exponent == 0:
            for j in range(m):
                _momentum_pair(block, j, sa, ra, ka, rho_a, terms, 0, False)
        elif art_exponent == 4:
            for j in range(m):
                _momentum_pair(block, j, sa, ra, ka, rho_a, terms, 4, False)
        else:
            for j in range(m):
                _momentum_pair(block, j, sa, ra, ka, rho_a, terms, art_exponent, False)


@njit(cache=True, fastmath=False, error_model="numpy", inline="always")
def _gather_momentum_block(block, a, lo, m, state, neighbours, half_period, work, h, art_exponent, correct_gradient):
    """Pairs lo..lo+m-1 of a's row into the block's columns (pair_blocks.py): the pair's motion, b's sigma / rho^2,
    R_b (with the artificial stress) and K_b^-1 (with the corrected gradient); r_a - r_b through the minimum image
    on a row that may need it (NeighbourList.crossing)."""
    pos = state.pos
    vel = state.vel
    index = neighbours.index
    period = neighbours.period
    gather_motion(block, index, lo, m, a, pos, vel, state.rho, h)
    gather_tensors(block, _S_B, index, lo, m, work.sigma_over_rho2)
    if art_exponent > 0:
        gather_tensors(block, _R_B, index, lo, m, work.art_stress)
    if correct_gradient:
        kinv = work.kinv
        for j in range(m):
            b = index[unsigned(lo + j)]
            for k in range(9):
                block[(_K_B + k) * STRIDE + j] = kinv[b, k // 3, k % 3]
        pad_block(block, m, _K_B, 0.0, _K_B + 1, _K_B + 9, 0.0)
    if (period[0] > 0.0 or period[1] > 0.0 or period[2] > 0.0) and neighbours.crossing[a]:
        minimum_image_block(block, _RX, m, period, half_period)


@njit(cache=True, fastmath=False, error_model="numpy", inline="always")
def _scatter_momentum_block(block, a, lo, m, mass, movable, index, w, f, out, ax, ay, az):
    """The block's pair terms: W_ab, F_ab into the pair cache (w, f), m_b T.g added to a's sums (returned) and
    -m_a T.g to b's chunk buffer row. Pairs of two clamp particles only refresh the cache."""
    movable_a = movable[a]
    for j in range(m):
        s = unsigned(lo + j)
        w[s] = block[_W * STRIDE + j]
        f[s] = block[_F * STRIDE + j]
        b = index[s]
        if not (movable_a or movable[b]):
            continue
        gx = block[_GX * STRIDE + j]
        gy = block[_GY * STRIDE + j]
        gz = block[_GZ * STRIDE + j]
        ax += mass[b] * gx
        ay += mass[b] * gy
        az += mass[b] * gz
        out[b, 0] -= mass[a] * gx
        out[b, 1] -= mass[a] * gy
        out[b, 2] -= mass[a] * gz
    return ax, ay, az


@njit(cache=True, fastmath=False, error_model="numpy", parallel=True, nogil=True)
def momentum_rate(state, neighbours, prm, work, body_acc):
    """Eq. (5): dv_a/dt = sum_b m_b (sigma_a/rho_a^2 + sigma_b/rho_b^2 - Pi_ab I + R_ab f_ab^n) . grad_a W_ab + g,
    into state.acc (g = body_acc).

    f_ab = W_ab / W(dp); R_ab = R_a + R_b; n = prm.art_exponent, an integer (0: no artificial stress).
    Pi_ab: Monaghan's viscosity (>= 0, see module doc for the sign). The bracket T_ab is symmetric in a and b
    and grad_b W_ba = -grad_a W_ab, so over the half list each pair adds m_b T.g to a and -m_a T.g to b:
    momentum is conserved to round-off. The same pass evaluates the kernel at the current positions and leaves
    it in the pair cache (work.w, work.f) for the next step's velocity passes. The pair terms are computed in blocks
    (pair_blocks.py; work.blocks: per-chunk scratch of MOMENTUM_BLOCK_COLUMNS columns), summed per chunk in
    work.vector_buf; sigma / rho^2 and R from work (stress_terms).

    With prm.gradient_order 1 each particle's stress acts through its kernel-corrected gradient K^-1 grad W (Bonet &
    Lok 1999; work.kinv), the counterpart of the corrected velocity gradient, so that stress power and strain rate
    stay paired; the pair terms (viscosity, artificial stress) use the mean of the two. Still antisymmetric per pair.
    Pairs of two clamp particles (state.movable False) only refresh the cache: their forces act on no moving
    particle (and with the mirrored clamp they would move the ghosts' images). Arguments as in
    xsph_velocity_and_gradient.
    """
    mass = state.mass
    movable = state.movable
    rho = state.rho
    acc = state.acc
    sigma_over_rho2 = work.sigma_over_rho2
    art_stress = work.art_stress
    kinv = work.kinv
    w = work.w
    f = work.f
    buf = work.vector_buf
    blocks = work.blocks
    start = neighbours.start
    index = neighbours.index
    art_exponent = prm.art_exponent
    correct_gradient = prm.gradient_order == 1
    h = prm.h
    terms = pair_terms(prm)
    half_period = 0.5 * neighbours.period
    n = mass.shape[0]
    chunks = buf.shape[0]
    for c in prange(chunks):
        out = buf[c]
        block = blocks[c]
        out[:, 0:3] = 0.0
        for a in range(chunk_first_target(start, c, chunks), chunk_first_target(start, c + 1, chunks)):
            ax = ay = az = 0.0
            for lo in range(start[a], start[a + 1], BLOCK):
                m = min(BLOCK, start[a + 1] - lo)
                _gather_momentum_block(block, a, lo, m, state, neighbours, half_period, work, h, art_exponent,
                                       correct_gradient)
                _momentum_pair_block(block, padded(m), sigma_over_rho2[a], art_stress[a], kinv[a], rho[a], terms,
                                     art_exponent, correct_gradient)
                ax, ay, az = _scatter_momentum_block(block, a, lo, m, mass, movable, index, w, f, out, ax, ay, az)
            out[a, 0] += ax
            out[a, 1] += ay
            out[a, 2] += az
    for a in prange(n):
        for k in range(3):
            total = body_acc[k]
            for c in range(chunks):
                total += buf[c, a, k]
            acc[a, k] = total


@njit(cache=True, fastmath=False, error_model="numpy", nogil=True)
def strain_energy(mass, rho, stress, pressure, shear_modulus, bulk_modulus):
    """Elastic energy sum_a (m_a/rho_a) (S:S/(4G) + p^2/(2K)) of linear isotropic elasticity (the paper's Fig. 8)."""
    total = 0.0
    for a in range(stress.shape[0]):
        ss = (stress[a, XX] ** 2 + stress[a, YY] ** 2 + stress[a, ZZ] ** 2
              + 2.0 * (stress[a, XY] ** 2 + stress[a, XZ] ** 2 + stress[a, YZ] ** 2))
        total += mass[a] / rho[a] * (ss / (4.0 * shear_modulus) + pressure[a] ** 2 / (2.0 * bulk_modulus))
    return total
