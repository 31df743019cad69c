"""Elastic solid of Gray, Monaghan & Swift (2001) in 3D, as used by Satake et al. (sec. 2.1, eqs. (3)-(5)).

Each function is one pass: an equation's right-hand side over the half pair list (each pair once, b > a; see
neighbours.py), or one per-particle update. State per solid particle: position, velocity, density rho, deviatoric stress S (N, 6 in the
XX, YY, ZZ, XY, XZ, YZ order of tensors.py). The full stress is sigma = -p I + S with p = c0^2 (rho - rho0).

Sign of the artificial viscosity (METHOD 'Open (sign)'): Pi_ab here is Monaghan's, (-alpha cbar mu + beta mu^2)
/ rhobar with mu = h v_ab.r_ab / (r_ab^2 + 0.01 h^2) for approaching pairs (v_ab.r_ab < 0), so Pi_ab >= 0. It
must act like a pressure, so it enters eq. (5)'s bracket as -Pi_ab delta^ij next to sigma/rho^2 = -p/rho^2 I.
(The paper's "+Pi delta" is Gray's convention, whose Pi carries the opposite sign.) test_solid_physics checks
that it removes energy.
"""
import math

import numpy as np
from numba import njit, prange

from .kernels import cubic_spline_wf
from .neighbours import chunk_first_target, inverse_periods, minimum_image
from .tensors import XX, XY, XZ, YY, YZ, ZZ, symmetric_eigen


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


@njit(cache=True, fastmath=False, error_model="numpy", parallel=True, nogil=True)
def xsph_velocity_and_gradient(pos, period, mass, rho, vel, start, index, w, f, xsph_eps, vhat, grad_v, buf,
                               correct_gradient, kinv):
    """XSPH-averaged velocity, eq. (4), and the velocity gradient L^ij_a = sum_b (m_b/rho_b)(v_b^i - v_a^i) dW_ab/dx_a^j.

    One pass over the half list (each pair once): with g = grad_a W_ab and dv = v_b - v_a, the pair adds
    V_b dv (x) g to L_a and V_a dv (x) g to L_b (grad_b W_ba = -g and v_a - v_b = -dv), and m/rhobar W dv with
    opposite signs to the two XSPH sums. Each chunk of rows accumulates into its own slice of `buf`
    (chunks, N, 21), so there are no write races; a second loop sums the chunks.

    correct_gradient: also sum K_a = sum_b V_b (r_b - r_a) (x) grad_a W_ab and return L K^-1, the velocity
    gradient that is exact for linear fields also where the kernel is truncated (free surfaces); K^-1 is left
    in `kinv` (N, 3, 3) for the momentum pass. Not in the paper (Gray 2001 uses the plain sum); a scene option.
    """
    inv_period = inverse_periods(period)
    n = vel.shape[0]
    chunks = buf.shape[0]
    for c in prange(chunks):
        out = buf[c]
        out[:, 0:18 if correct_gradient else 12] = 0.0
        for a in range(chunk_first_target(start, c, chunks), chunk_first_target(start, c + 1, chunks)):
            va = mass[a] / rho[a]
            # a's sums stay in registers; only b's go through the buffer
            x0 = x1 = x2 = 0.0
            l00 = l01 = l02 = l10 = l11 = l12 = l20 = l21 = l22 = 0.0
            k00 = k01 = k02 = k11 = k12 = k22 = 0.0
            for s in range(start[a], start[a + 1]):
                b = index[s]
                vb = mass[b] / rho[b]
                fs = f[s]
                rx = minimum_image(pos[a, 0] - pos[b, 0], period[0], inv_period[0])
                ry = minimum_image(pos[a, 1] - pos[b, 1], period[1], inv_period[1])
                rz = minimum_image(pos[a, 2] - pos[b, 2], period[2], inv_period[2])
                gx = fs * rx
                gy = fs * ry
                gz = fs * rz
                dvx = vel[b, 0] - vel[a, 0]
                dvy = vel[b, 1] - vel[a, 1]
                dvz = vel[b, 2] - vel[a, 2]
                k = w[s] / (0.5 * (rho[a] + rho[b]))
                x0 += mass[b] * k * dvx
                x1 += mass[b] * k * dvy
                x2 += mass[b] * k * dvz
                out[b, 0] -= mass[a] * k * dvx
                out[b, 1] -= mass[a] * k * dvy
                out[b, 2] -= mass[a] * k * dvz
                o00 = dvx * gx
                o01 = dvx * gy
                o02 = dvx * gz
                o10 = dvy * gx
                o11 = dvy * gy
                o12 = dvy * gz
                o20 = dvz * gx
                o21 = dvz * gy
                o22 = dvz * gz
                l00 += vb * o00
                l01 += vb * o01
                l02 += vb * o02
                l10 += vb * o10
                l11 += vb * o11
                l12 += vb * o12
                l20 += vb * o20
                l21 += vb * o21
                l22 += vb * o22
                out[b, 3] += va * o00
                out[b, 4] += va * o01
                out[b, 5] += va * o02
                out[b, 6] += va * o10
                out[b, 7] += va * o11
                out[b, 8] += va * o12
                out[b, 9] += va * o20
                out[b, 10] += va * o21
                out[b, 11] += va * o22
                if correct_gradient:
                    # -(r_ab (x) g) is the pair's K term seen from both sides (r_ab (x) g is symmetric)
                    q00 = -rx * gx
                    q01 = -rx * gy
                    q02 = -rx * gz
                    q11 = -ry * gy
                    q12 = -ry * gz
                    q22 = -rz * gz
                    k00 += vb * q00
                    k01 += vb * q01
                    k02 += vb * q02
                    k11 += vb * q11
                    k12 += vb * q12
                    k22 += vb * q22
                    out[b, 12] += va * q00
                    out[b, 13] += va * q01
                    out[b, 14] += va * q02
                    out[b, 15] += va * q11
                    out[b, 16] += va * q12
                    out[b, 17] += va * q22
            out[a, 0] += x0
            out[a, 1] += x1
            out[a, 2] += x2
            out[a, 3] += l00
            out[a, 4] += l01
            out[a, 5] += l02
            out[a, 6] += l10
            out[a, 7] += l11
            out[a, 8] += l12
            out[a, 9] += l20
            out[a, 10] += l21
            out[a, 11] += l22
            if correct_gradient:
                out[a, 12] += k00
                out[a, 13] += k01
                out[a, 14] += k02
                out[a, 15] += k11
                out[a, 16] += k12
                out[a, 17] += k22
    for a in prange(n):
        sum_velocity_chunks(buf, a, vel, xsph_eps, vhat, grad_v)
        if correct_gradient:
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
            if abs(det) > 1e-3:   # a particle with too few neighbours keeps the plain gradient
                # K^-1 (symmetric) into kinv[a], then each row of L times K^-1, in place
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
def continuity_rate(pos, period, mass, rho, vhat, start, index, f, drho, buf):
    """Eq. (3): d rho_a/dt = rho_a sum_b (m_b/rho_b) (vhat_a - vhat_b) . grad_a W_ab.

    Half list: the pair's (vhat_a - vhat_b) . grad_a W_ab is the same seen from b, so it adds V_b times it to a's
    sum and V_a times it to b's (chunked buffers as in xsph_velocity_and_gradient).
    """
    inv_period = inverse_periods(period)
    n = vhat.shape[0]
    chunks = buf.shape[0]
    for c in prange(chunks):
        out = buf[c]
        out[:, 0] = 0.0
        for a in range(chunk_first_target(start, c, chunks), chunk_first_target(start, c + 1, chunks)):
            va = mass[a] / rho[a]
            da = 0.0
            for s in range(start[a], start[a + 1]):
                b = index[s]
                rx = minimum_image(pos[a, 0] - pos[b, 0], period[0], inv_period[0])
                ry = minimum_image(pos[a, 1] - pos[b, 1], period[1], inv_period[1])
                rz = minimum_image(pos[a, 2] - pos[b, 2], period[2], inv_period[2])
                d = f[s] * ((vhat[a, 0] - vhat[b, 0]) * rx + (vhat[a, 1] - vhat[b, 1]) * ry
                            + (vhat[a, 2] - vhat[b, 2]) * rz)
                da += mass[b] / rho[b] * d
                out[b, 0] += va * d
            out[a, 0] += da
    for a in prange(n):
        acc = 0.0
        for c in range(chunks):
            acc += buf[c, a, 0]
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
def viscous_and_artificial_stress_terms(vel, rho, art_stress, a, b, rx, ry, rz, r2, wab, h, eta2, sound_speed,
                                        alpha, beta, art_exponent, inv_w_dp):
    """The pair's -Pi_ab I + R_ab f_ab^n in eq. (5)'s bracket, as (XX, YY, ZZ, XY, XZ, YZ); r = r_a - r_b."""
    txy = txz = tyz = 0.0
    vr = (vel[a, 0] - vel[b, 0]) * rx + (vel[a, 1] - vel[b, 1]) * ry + (vel[a, 2] - vel[b, 2]) * rz
    # branch-free (receding pairs give mu = 0): approaching and receding pairs alternate unpredictably
    mu = h * min(vr, 0.0) / (r2 + eta2)
    pi_ab = (-alpha * sound_speed * mu + beta * mu * mu) / (0.5 * (rho[a] + rho[b]))
    txx = tyy = tzz = -pi_ab
    if art_exponent > 0:
        ratio = wab * inv_w_dp
        if art_exponent == 4:   # Gray's n, the default: two multiplications
            fn = ratio * ratio
            fn *= fn
        else:
            fn = 1.0
            for _ in range(art_exponent):
                fn *= ratio
        txx += (art_stress[a, XX] + art_stress[b, XX]) * fn
        tyy += (art_stress[a, YY] + art_stress[b, YY]) * fn
        tzz += (art_stress[a, ZZ] + art_stress[b, ZZ]) * fn
        txy += (art_stress[a, XY] + art_stress[b, XY]) * fn
        txz += (art_stress[a, XZ] + art_stress[b, XZ]) * fn
        tyz += (art_stress[a, YZ] + art_stress[b, YZ]) * fn
    return txx, tyy, tzz, txy, txz, tyz


@njit(cache=True, fastmath=False, error_model="numpy", parallel=True, nogil=True)
def momentum_rate(pos, period, mass, movable, rho, vel, sigma_over_rho2, art_stress, start, index, h, sound_speed,
                  alpha, beta, art_exponent, inv_w_dp, body_acc, acc, w, f, buf, correct_gradient, kinv):
    """Eq. (5): dv_a/dt = sum_b m_b (sigma_a/rho_a^2 + sigma_b/rho_b^2 - Pi_ab I + R_ab f_ab^n) . grad_a W_ab + g.

    f_ab = W_ab / W(dp); R_ab = R_a + R_b; n = art_exponent, an integer (0: no artificial stress).
    Pi_ab: Monaghan's viscosity (>= 0, see module doc for the sign). The bracket T_ab is symmetric in a and b
    and grad_b W_ba = -grad_a W_ab, so over the half list each pair adds m_b T.g to a and -m_a T.g to b:
    momentum is conserved to round-off. The same pass evaluates the kernel at the current positions and leaves
    it in the pair cache (w, f) for the next step's velocity passes.

    correct_gradient: each particle's stress acts through its kernel-corrected gradient K^-1 grad W (Bonet & Lok
    1999), the counterpart of the corrected velocity gradient, so that stress power and strain rate stay paired;
    the pair terms (viscosity, artificial stress) use the mean of the two. Still antisymmetric per pair.
    Pairs of two clamp particles (`movable` False) only refresh the cache: their forces act on no moving particle
    (and with the mirrored clamp they would move the ghosts' images).
    """
    inv_period = inverse_periods(period)
    eta2 = 0.01 * h * h
    inv_h = 1.0 / h
    sigma = 1.0 / (math.pi * h * h * h)
    n = vel.shape[0]
    chunks = buf.shape[0]
    for c in prange(chunks):
        out = buf[c]
        out[:, 0:3] = 0.0
        for a in range(chunk_first_target(start, c, chunks), chunk_first_target(start, c + 1, chunks)):
            ax = ay = az = 0.0
            for s in range(start[a], start[a + 1]):
                b = index[s]
                rx = minimum_image(pos[a, 0] - pos[b, 0], period[0], inv_period[0])
                ry = minimum_image(pos[a, 1] - pos[b, 1], period[1], inv_period[1])
                rz = minimum_image(pos[a, 2] - pos[b, 2], period[2], inv_period[2])
                r2 = rx * rx + ry * ry + rz * rz
                r = math.sqrt(r2)
                wab, fab = cubic_spline_wf(r, inv_h, sigma)
                w[s] = wab
                f[s] = fab
                if not (movable[a] or movable[b]):
                    continue
                if correct_gradient:
                    # K_a^-1 g and K_b^-1 g for the two particles' own stresses
                    gx = fab * rx
                    gy = fab * ry
                    gz = fab * rz
                    gax = kinv[a, 0, 0] * gx + kinv[a, 0, 1] * gy + kinv[a, 0, 2] * gz
                    gay = kinv[a, 1, 0] * gx + kinv[a, 1, 1] * gy + kinv[a, 1, 2] * gz
                    gaz = kinv[a, 2, 0] * gx + kinv[a, 2, 1] * gy + kinv[a, 2, 2] * gz
                    gbx = kinv[b, 0, 0] * gx + kinv[b, 0, 1] * gy + kinv[b, 0, 2] * gz
                    gby = kinv[b, 1, 0] * gx + kinv[b, 1, 1] * gy + kinv[b, 1, 2] * gz
                    gbz = kinv[b, 2, 0] * gx + kinv[b, 2, 1] * gy + kinv[b, 2, 2] * gz
                    mx = 0.5 * (gax + gbx)
                    my = 0.5 * (gay + gby)
                    mz = 0.5 * (gaz + gbz)
                    sa = sigma_over_rho2[a]
                    sb = sigma_over_rho2[b]
                    fx = (sa[XX] * gax + sa[XY] * gay + sa[XZ] * gaz) + (sb[XX] * gbx + sb[XY] * gby + sb[XZ] * gbz)
                    fy = (sa[XY] * gax + sa[YY] * gay + sa[YZ] * gaz) + (sb[XY] * gbx + sb[YY] * gby + sb[YZ] * gbz)
                    fz = (sa[XZ] * gax + sa[YZ] * gay + sa[ZZ] * gaz) + (sb[XZ] * gbx + sb[YZ] * gby + sb[ZZ] * gbz)
                    txx = tyy = tzz = txy = txz = tyz = 0.0
                else:
                    mx = fab * rx
                    my = fab * ry
                    mz = fab * rz
                    fx = fy = fz = 0.0
                    txx = sigma_over_rho2[a, XX] + sigma_over_rho2[b, XX]
                    tyy = sigma_over_rho2[a, YY] + sigma_over_rho2[b, YY]
                    tzz = sigma_over_rho2[a, ZZ] + sigma_over_rho2[b, ZZ]
                    txy = sigma_over_rho2[a, XY] + sigma_over_rho2[b, XY]
                    txz = sigma_over_rho2[a, XZ] + sigma_over_rho2[b, XZ]
                    tyz = sigma_over_rho2[a, YZ] + sigma_over_rho2[b, YZ]
                pxx, pyy, pzz, pxy, pxz, pyz = viscous_and_artificial_stress_terms(
                    vel, rho, art_stress, a, b, rx, ry, rz, r2, wab, h, eta2, sound_speed, alpha, beta, art_exponent,
                    inv_w_dp)
                txx += pxx
                tyy += pyy
                tzz += pzz
                txy += pxy
                txz += pxz
                tyz += pyz
                gx = fx + txx * mx + txy * my + txz * mz
                gy = fy + txy * mx + tyy * my + tyz * mz
                gz = fz + txz * mx + tyz * my + tzz * mz
                ax += mass[b] * gx
                ay += mass[b] * gy
                az += mass[b] * gz
                out[b, 0] -= mass[a] * gx
                out[b, 1] -= mass[a] * gy
                out[b, 2] -= mass[a] * gz
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
