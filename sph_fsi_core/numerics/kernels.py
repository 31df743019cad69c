"""The smoothing kernels in 3D: the M4 cubic spline (Monaghan & Lattanzio 1985), the kernel of Satake et al.
eq. (1), and Wendland's C2 kernel (Wendland 1995), which the water may take instead (fluid.kernel).

Both have support 2h, q = r / h, W(r, h) = sigma * w(q). The M4 cubic spline, sigma = 1 / (pi h^3):

    w(q) = 1 - 1.5 q^2 + 0.75 q^3     for 0 <= q < 1
    w(q) = 0.25 (2 - q)^3             for 1 <= q < 2
    w(q) = 0                          for q >= 2

Wendland's C2, sigma = 21 / (16 pi h^3) (the form DualSPHysics uses; Dehnen & Aly 2012 show it free of the
pairing instability that the cubic spline has past h / dp of about 1.5, docs/validation/OPEN.md 7):

    w(q) = (1 - q/2)^4 (2q + 1)       for 0 <= q < 2,  0 beyond.

Both have w(0) = 1, so a particle's own term is sigma. Gradients are stored as the scalar F = (dW/dr) / r, so that
grad_a W_ab = F_ab * (r_a - r_b). F is finite at r = 0 (-3 sigma / h^2 for the spline, -5 sigma / h^2 for
Wendland's), which lets a particle's own pair be handled without a special case.

The solid keeps the cubic spline (Gray et al. 2001's kernel, which its artificial stress was set for); the water's
passes take the kernel as an integer (CUBIC_SPLINE, WENDLAND_C2: KERNELS maps fluid.kernel's names to them).
"""
import math

import numpy as np
from numba import njit

SUPPORT_RADIUS_IN_H = 2.0
CUBIC_SPLINE = 0
WENDLAND_C2 = 1
KERNELS = {"cubic_spline": CUBIC_SPLINE, "wendland_c2": WENDLAND_C2}   # fluid.kernel's names


def water_kernel(values):
    """The id of a scene's fluid.kernel ({key: value}); the cubic spline in a scene without water."""
    return KERNELS[values.get("fluid.kernel", "cubic_spline")]


@njit(cache=True, fastmath=False, error_model="numpy", inline="always")
def kernel_normalisation(h):
    """sigma = 1 / (pi h^3), the factor of the M4 kernel in 3D (W = sigma w(q)): what cubic_spline_wf takes."""
    return 1.0 / (math.pi * h * h * h)


@njit(cache=True, fastmath=False, error_model="numpy", inline="always")
def support_squared(h):
    """(2h)^2, the squared radius beyond which W and F vanish: pairs in a list's skin past it are skipped."""
    return SUPPORT_RADIUS_IN_H * SUPPORT_RADIUS_IN_H * h * h


@njit(cache=True, fastmath=False, error_model="numpy", inline="always")
def positive_part(x):
    """max(x, 0) as a select: the builtin max is a call into another compiled library, which keeps a loop that
    uses it from running in SIMD lanes in its own library (pair_blocks.py)."""
    return x if x > 0.0 else 0.0


@njit(cache=True, fastmath=False, error_model="numpy", inline="always")
def cubic_spline_w(r, h):
    """W(r, h) of the M4 cubic spline in 3D, eq. (1)'s kernel.

    Written branch-free as sigma (0.25 (2-q)_+^3 - (1-q)_+^3), which equals the piecewise form above: particle
    pairs arrive in no particular order of q, so branches would be mispredicted often.
    """
    q = r / h
    t2 = positive_part(2.0 - q)
    t1 = positive_part(1.0 - q)
    return (0.25 * t2 * t2 * t2 - t1 * t1 * t1) / (math.pi * h * h * h)


@njit(cache=True, fastmath=False, error_model="numpy", inline="always")
def cubic_spline_f(r, h):
    """F(r, h) = (dW/dr) / r of the M4 cubic spline, so that grad_a W_ab = F * (r_a - r_b).

    dW/dq = sigma (-0.75 (2-q)_+^2 + 3 (1-q)_+^2), branch-free; (dW/dq)/q -> -3 sigma as q -> 0, and the
    expression below is exact there too because dW/dq vanishes linearly in q.
    """
    q = r / h
    t2 = positive_part(2.0 - q)
    t1 = positive_part(1.0 - q)
    sigma_h2 = 1.0 / (math.pi * h * h * h * h * h)
    if q < 1e-12:
        return -3.0 * sigma_h2
    return (-0.75 * t2 * t2 + 3.0 * t1 * t1) / q * sigma_h2


@njit(cache=True, fastmath=False, error_model="numpy", inline="always")
def cubic_spline_wf(r, inv_h, sigma):
    """(W, F) together for one pair, sharing q and the two truncated powers; inv_h = 1/h,
    sigma = kernel_normalisation(h).

    The same values as cubic_spline_w and cubic_spline_f up to rounding, with one division instead of four:
    this is the form the per-step pair passes use.
    """
    q = r * inv_h
    t2 = positive_part(2.0 - q)
    t1 = positive_part(1.0 - q)
    w = sigma * (0.25 * t2 * t2 * t2 - t1 * t1 * t1)
    if q < 1e-12:
        return w, -3.0 * sigma * inv_h * inv_h
    return w, sigma * inv_h * (-0.75 * t2 * t2 + 3.0 * t1 * t1) / r


@njit(cache=True, fastmath=False, error_model="numpy", inline="always")
def wendland_c2_normalisation(h):
    """sigma = 21 / (16 pi h^3), the factor of Wendland's C2 kernel in 3D with support 2h."""
    return 21.0 / (16.0 * math.pi * h * h * h)


@njit(cache=True, fastmath=False, error_model="numpy", inline="always")
def wendland_c2_wf(r, inv_h, sigma):
    """(W, F) of Wendland's C2 kernel for one pair, F = (dW/dr)/r; inv_h = 1/h, sigma = wendland_c2_normalisation.

    dW/dq = sigma (-2 (1 - q/2)^3 (2q + 1) + 2 (1 - q/2)^4) = -5 sigma q (1 - q/2)^3, so F = -5 sigma (1 - q/2)^3 / h^2,
    finite at r = 0 without a special case; branch-free through positive_part."""
    q = r * inv_h
    t = positive_part(1.0 - 0.5 * q)
    t3 = t * t * t
    return sigma * t3 * t * (2.0 * q + 1.0), -5.0 * sigma * inv_h * inv_h * t3


@njit(cache=True, fastmath=False, error_model="numpy", inline="always")
def kernel_sigma(h, kernel):
    """sigma of `kernel` (CUBIC_SPLINE or WENDLAND_C2) at h: W(0), the factor the water's pair passes take."""
    if kernel == WENDLAND_C2:
        return wendland_c2_normalisation(h)
    return kernel_normalisation(h)


@njit(cache=True, fastmath=False, error_model="numpy", inline="always")
def kernel_wf(r, inv_h, sigma, kernel):
    """(W, F) of `kernel` for one pair (sigma = kernel_sigma(h, kernel)); the cubic spline's are cubic_spline_wf's
    to the bit."""
    if kernel == WENDLAND_C2:
        return wendland_c2_wf(r, inv_h, sigma)
    return cubic_spline_wf(r, inv_h, sigma)


@njit(cache=True, fastmath=False, error_model="numpy", inline="always")
def kernel_w(r, h, kernel):
    """W(r, h) of `kernel`; the cubic spline's is cubic_spline_w's to the bit."""
    if kernel == WENDLAND_C2:
        return wendland_c2_wf(r, 1.0 / h, wendland_c2_normalisation(h))[0]
    return cubic_spline_w(r, h)


@njit(cache=True, fastmath=False, error_model="numpy", inline="always")
def kernel_f(r, h, kernel):
    """F(r, h) = (dW/dr)/r of `kernel`; the cubic spline's is cubic_spline_f's to the bit."""
    if kernel == WENDLAND_C2:
        return wendland_c2_wf(r, 1.0 / h, wendland_c2_normalisation(h))[1]
    return cubic_spline_f(r, h)


def lattice_kernel_sum(smoothing_ratio, kernel=CUBIC_SPLINE):
    """sum_b dp^3 W(|r_b|, h) over a full cubic lattice of spacing dp (dp = 1 here) for `kernel`: 0.99726 at
    h/dp = 1.3 for the cubic spline.

    A radial kernel is not a partition of unity on a lattice, so with the spline at 1.3 a lattice of mass rho0 dp^3
    would sit 0.27 % below rho0 (and first compress by that much before any pressure acts)."""
    reach = int(np.ceil(SUPPORT_RADIUS_IN_H * smoothing_ratio)) + 1
    r = np.arange(-reach, reach + 1, dtype=np.float64)
    g = np.stack(np.meshgrid(r, r, r, indexing="ij"), axis=-1).reshape(-1, 3)
    d = np.sqrt((g * g).sum(axis=1))
    return float(sum(kernel_w(x, smoothing_ratio, kernel) for x in d))


def lattice_density_scale(smoothing_ratio, kernel=CUBIC_SPLINE):
    """Factor on rho0 dp^3 that makes the summation density (1) of a full lattice exactly rho0: fluid and wall
    particles carry mass rho0 dp^3 / lattice_kernel_sum."""
    return 1.0 / lattice_kernel_sum(smoothing_ratio, kernel)
