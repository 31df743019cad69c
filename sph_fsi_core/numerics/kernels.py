"""The M4 cubic spline kernel in 3D (Monaghan & Lattanzio 1985), the kernel of Satake et al. eq. (1).

W(r, h) = sigma * w(q), q = r / h, support 2h, sigma = 1 / (pi h^3):

    w(q) = 1 - 1.5 q^2 + 0.75 q^3     for 0 <= q < 1
    w(q) = 0.25 (2 - q)^3             for 1 <= q < 2
    w(q) = 0                          for q >= 2

Gradients are stored as the scalar F = (dW/dr) / r, so that grad_a W_ab = F_ab * (r_a - r_b). F is finite at
r = 0 (its limit is -3 sigma / h^2), which lets a particle's own pair be handled without a special case.
"""
import math

import numpy as np
from numba import njit

SUPPORT_RADIUS_IN_H = 2.0


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


def lattice_kernel_sum(smoothing_ratio):
    """sum_b dp^3 W(|r_b|, h) over a full cubic lattice of spacing dp (dp = 1 here): 0.99726 at h/dp = 1.3.

    The radial M4 kernel is not a partition of unity on a lattice, so a lattice of mass rho0 dp^3 would sit
    0.27 % below rho0 (and first compress by that much before any pressure acts)."""
    reach = int(np.ceil(SUPPORT_RADIUS_IN_H * smoothing_ratio)) + 1
    r = np.arange(-reach, reach + 1, dtype=np.float64)
    g = np.stack(np.meshgrid(r, r, r, indexing="ij"), axis=-1).reshape(-1, 3)
    d = np.sqrt((g * g).sum(axis=1))
    return float(sum(cubic_spline_w(x, smoothing_ratio) for x in d))


def lattice_density_scale(smoothing_ratio):
    """Factor on rho0 dp^3 that makes the summation density (1) of a full lattice exactly rho0: fluid and wall
    particles carry mass rho0 dp^3 / lattice_kernel_sum."""
    return 1.0 / lattice_kernel_sum(smoothing_ratio)
