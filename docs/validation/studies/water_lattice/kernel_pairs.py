"""The study's experiment scripts' pair sums (particle_shifting.py, background_split.py, corrected_velocity.py): pairs
within a radius from scipy's periodic k-d tree and the M4 cubic spline (numerics/kernels.py's) on arrays of them,
its own copy, so the scripts smooth and sum with the spline whatever the water's kernel (fluid.kernel; the rows
with Wendland's C2 were run so). Experiments, not solver passes: a step's pairs are found anew each call.
"""
import math

import numpy as np
from scipy.spatial import cKDTree

_FAR = 1.0e3   # m, the k-d tree's "period" along an axis that has none


def periodic_pairs(points, period, box_lo, radius):
    """(i, j, d): the index pairs i < j of `points` within `radius` and their minimum-image r_i - r_j."""
    box = np.where(period > 0, period, _FAR)
    origin = np.where(period > 0, box_lo, np.minimum(points.min(axis=0), 0.0) - 1.0)
    q = points - origin
    q = np.where(period > 0, np.mod(q, box), q)
    i, j = cKDTree(q, boxsize=box).query_pairs(radius, output_type="ndarray").T
    d = q[i] - q[j]
    return i, j, np.where(period > 0, d - box * np.round(d / box), d)


def kernel_and_gradient(d, r, h):
    """W(r) and grad W (rows d = r_a - r_b) of the cubic spline."""
    q = r / h
    sigma = 1.0 / (np.pi * h ** 3)
    w = np.where(q < 1, 1 - 1.5 * q ** 2 + 0.75 * q ** 3, np.where(q < 2, 0.25 * (2 - q) ** 3, 0.0)) * sigma
    dw = np.where(q < 1, -3 * q + 2.25 * q ** 2, np.where(q < 2, -0.75 * (2 - q) ** 2, 0.0)) * sigma / h
    with np.errstate(invalid="ignore", divide="ignore"):
        grad = np.where(r[:, None] > 0, dw[:, None] * d / r[:, None], 0.0)
    return w, grad


def kernel_w(r, h):
    """W(r, h) of the same spline at one distance, written as numerics/kernels.py's cubic_spline_w (the same bits)."""
    q = r / h
    t2 = max(2.0 - q, 0.0)
    t1 = max(1.0 - q, 0.0)
    return (0.25 * t2 * t2 * t2 - t1 * t1 * t1) / (math.pi * h * h * h)


def pair_sum(i, j, n, values_i, values_j):
    """sum over pairs of values_i into i and values_j into j (rows of any width), as (n, width)."""
    out = np.empty((n, values_i.shape[1]))
    for c in range(values_i.shape[1]):
        out[:, c] = np.bincount(i, values_i[:, c], n) + np.bincount(j, values_j[:, c], n)
    return out


def kernel_fullness(i, j, w, volume, h):
    """sum_b V_b W_ab over the pairs (i, j, W) and each particle's own term: 1 where its kernel is full."""
    return volume * kernel_w(0.0, h) + pair_sum(i, j, len(volume), (volume[j] * w)[:, None],
                                                 (volume[i] * w)[:, None])[:, 0]
