"""Pair passes in blocks of neighbours: gather, compute in SIMD lanes, scatter.

A pass over particle a's neighbour row handles it in blocks of up to BLOCK pairs, each in three loops:

1. gather (scalar): what the pair needs of each neighbour b, read through the list's index, into the columns of a
   per-thread scratch block (column c of pair j at block[c * STRIDE + j]);
2. compute: one loop over the block's columns with no indirection, no branch and no running sum, so LLVM turns it
   into vector code (8 pairs per AVX-512 instruction, square roots and divisions included: on the 2-core CI
   machine a scalar pair loop spends about half its time waiting on the divider);
3. scatter (scalar): the pair terms summed into a and, through the index, into b, in the row's order.

Each pair's arithmetic is the same expression, in the same order, as in a scalar loop, and fastmath is off (no
fused multiply-adds, no reordering), so the results are the same to the bit; only where the time goes changes
(docs/method.md, "Performance design"). A block is padded to a multiple of LANES with pairs beyond the kernel's
support (FAR_IN_H: W = F = 0), so the compute loop has no scalar remainder.
"""
import math

import numpy as np
from numba import njit

from .kernels import WENDLAND_C2, cubic_spline_wf, wendland_c2_wf
from .neighbours import unsigned
from .periodic import minimum_image

LANES = 8                  # float64 lanes of an AVX-512 register
BLOCK = 64                 # pairs per block; longer rows are done in several blocks
STRIDE = BLOCK + LANES     # column stride: columns 4 KiB apart would alias in the load/store queue
FAR_IN_H = 4.0             # a padding pair sits 4 h apart, where the kernel and its gradient vanish


def block_scratch(chunks, columns):
    """Zeroed scratch for `chunks` threads of `columns` block columns each, as the passes take it."""
    return np.zeros((max(int(chunks), 1), columns * STRIDE))


@njit(cache=True, fastmath=False, error_model="numpy", inline="always")
def padded(m):
    """The block length the compute loop runs over: m rounded up to a multiple of LANES."""
    return (m + LANES - 1) // LANES * LANES


@njit(cache=True, fastmath=False, error_model="numpy", inline="always")
def pad_block(block, m, col_far, far, other_columns_lo, other_columns_hi, fill):
    """Padding pairs m..padded(m)-1: `far` in column col_far (a separation or squared separation of a pair beyond
    the support: FAR_IN_H h or its square), `fill` in the columns [other_columns_lo, other_columns_hi) (1 where a
    column is divided by, 0 elsewhere: see the callers). Their results are computed and never read."""
    for j in range(m, padded(m)):
        block[col_far * STRIDE + j] = far
        for col in range(other_columns_lo, other_columns_hi):
            block[col * STRIDE + j] = fill


# The first columns of a solid pass's block: the pair's motion, which every solid pair term needs.
SEPARATION = 0             # 3 columns: r_a - r_b, a plain difference (minimum_image_block makes it periodic)
VELOCITY_DIFFERENCE = 3    # 3 columns: v_a - v_b
NEIGHBOUR_DENSITY = 6      # rho_b
MOTION_COLUMNS = 7


@njit(cache=True, fastmath=False, error_model="numpy", inline="always")
def gather_motion(block, index, lo, m, a, pos, vel, rho, h):
    """The motion columns of pairs lo..lo+m-1 of a's row, and their padding (a pair FAR_IN_H h apart, at rest, of
    density 1) up to padded(m)."""
    xa, ya, za = pos[a, 0], pos[a, 1], pos[a, 2]
    vxa, vya, vza = vel[a, 0], vel[a, 1], vel[a, 2]
    pad_block(block, m, SEPARATION, FAR_IN_H * h, SEPARATION + 1, NEIGHBOUR_DENSITY, 0.0)
    pad_block(block, m, NEIGHBOUR_DENSITY, 1.0, 0, 0, 0.0)
    for j in range(m):
        b = index[unsigned(lo + j)]
        block[SEPARATION * STRIDE + j] = xa - pos[b, 0]
        block[(SEPARATION + 1) * STRIDE + j] = ya - pos[b, 1]
        block[(SEPARATION + 2) * STRIDE + j] = za - pos[b, 2]
        block[VELOCITY_DIFFERENCE * STRIDE + j] = vxa - vel[b, 0]
        block[(VELOCITY_DIFFERENCE + 1) * STRIDE + j] = vya - vel[b, 1]
        block[(VELOCITY_DIFFERENCE + 2) * STRIDE + j] = vza - vel[b, 2]
        block[NEIGHBOUR_DENSITY * STRIDE + j] = rho[b]


@njit(cache=True, fastmath=False, error_model="numpy", inline="always")
def gather_tensors(block, col, index, lo, m, tensors):
    """b's symmetric tensor (six components, tensors[b]) of pairs lo..lo+m-1 into the columns col..col+5, zeros
    for the padding; written out (a loop over the components measured 7-14 % slower in the momentum passes)."""
    for j in range(m):
        b = index[unsigned(lo + j)]
        block[col * STRIDE + j] = tensors[b, 0]
        block[(col + 1) * STRIDE + j] = tensors[b, 1]
        block[(col + 2) * STRIDE + j] = tensors[b, 2]
        block[(col + 3) * STRIDE + j] = tensors[b, 3]
        block[(col + 4) * STRIDE + j] = tensors[b, 4]
        block[(col + 5) * STRIDE + j] = tensors[b, 5]
    pad_block(block, m, col, 0.0, col + 1, col + 6, 0.0)


@njit(cache=True, fastmath=False, error_model="numpy", nogil=True)
def minimum_image_block(block, col_x, m, period, half_period):
    """periodic.minimum_image on the separations of a block's m pairs, in columns col_x, col_x + 1, col_x + 2;
    called only for periodic scenes (the gather stores plain differences)."""
    for k in range(3):
        p = period[k]
        hp = half_period[k]
        if p > 0.0:
            c0 = (col_x + k) * STRIDE
            for j in range(m):
                block[c0 + j] = minimum_image(block[c0 + j], p, hp)


@njit(cache=True, fastmath=False, error_model="numpy", nogil=True)
def kernel_block(block, col_r2, col_w, col_f, m, inv_h, sigma, kernel):
    """Eq. (1)'s kernel for the m pairs of a block: W (col_w) and F = (dW/dr)/r (col_f) from r^2 (col_r2), by
    kernels.cubic_spline_wf (whose one branch LLVM turns into a select) or, kernel = WENDLAND_C2, wendland_c2_wf;
    sigma = kernels.kernel_sigma(h, kernel). One loop per kernel, so each runs in SIMD lanes."""
    w0 = col_w * STRIDE
    f0 = col_f * STRIDE
    r0 = col_r2 * STRIDE
    if kernel == WENDLAND_C2:
        for j in range(m):
            block[w0 + j], block[f0 + j] = wendland_c2_wf(math.sqrt(block[r0 + j]), inv_h, sigma)
    else:
        for j in range(m):
            block[w0 + j], block[f0 + j] = cubic_spline_wf(math.sqrt(block[r0 + j]), inv_h, sigma)
