"""The solid's bundles (solid.stepper: SolidArrays, SolidNeighbours, SolidParams, SolidBuffers) for a pass called on
its own in a test, from the few arrays and numbers the test sets; the rest are zeros of the right shapes."""
import numpy as np

from sph_fsi_core.numerics.kernels import cubic_spline_w
from sph_fsi_core.numerics.pair_blocks import block_scratch
from sph_fsi_core.solid.fitted_gradient import MOMENTUM_BLOCK_COLUMNS as MLS_COLUMNS
from sph_fsi_core.solid.gray2001 import MOMENTUM_BLOCK_COLUMNS as GRAY_COLUMNS
from sph_fsi_core.solid.stepper import SolidArrays, SolidNeighbours, SolidWork, make_params


def state(pos, vel, rho, mass, movable=None, stress=None, acc=None, pressure=None, stress_gradient=None):
    n = len(pos)
    return SolidArrays(pos, vel, rho, np.zeros((n, 6)) if stress is None else stress, mass,
                       np.ones(n, dtype=np.bool_) if movable is None else movable,
                       np.zeros(n) if pressure is None else pressure, np.zeros((n, 3)) if acc is None else acc,
                       np.zeros((0, 3, 6)) if stress_gradient is None else stress_gradient)


def neighbours(nl, period=None, crossing=None):
    period = np.zeros(3) if period is None else period
    return SolidNeighbours(nl.start, nl.index, nl.crossing if crossing is None else crossing, nl.targets_at_build,
                           period)


def params(h, spacing, sound_speed=30.0, alpha=1.0, beta=1.0, art_exponent=0, xsph_eps=0.5, velocity_gradient="sph",
           nodal_integration="plain", inv_w_dp=None, **changes):
    """SolidParams with these numbers (art_exponent > 0: the artificial stress on, its eps 1); inv_w_dp defaults to
    1 / W(spacing, h)."""
    prm = make_params(h, spacing, 1000.0, sound_speed, 1e6, xsph_eps, alpha, beta, 1.0 if art_exponent else 0.0,
                      art_exponent, (0.0, 0.0, 0.0), 0.1 * h, velocity_gradient=velocity_gradient,
                      nodal_integration=nodal_integration)
    if inv_w_dp is not None:
        changes["inv_w_dp"] = inv_w_dp
    return prm._replace(**changes)


def buffers(n, pairs, chunks=2, hessian_rows=False, implicit_pressure=False, **arrays):
    """SolidBuffers for n particles and a list of `pairs` pairs, its per-chunk arrays for `chunks` chunks; `arrays`
    replace fields by name (e.g. w, f, volume, sigma_over_rho2, mls_rows, mls_weights)."""
    work = SolidWork(n, hessian_rows=hessian_rows, implicit_pressure=implicit_pressure)
    work.resize_pairs(pairs)
    work.mls_weights = np.zeros((pairs, 6))
    work.buf = np.zeros((chunks, n, 18))
    work.vector_buf = np.zeros((chunks, n, 3))
    work.scalar_buf = np.zeros((chunks, n))
    work.blocks = block_scratch(chunks, max(GRAY_COLUMNS, MLS_COLUMNS))
    work.hessian_moments = np.zeros((chunks,) + work.hessian_moments.shape[1:])
    return work.buffers()._replace(**arrays)


def inverse_kernel_at_spacing(spacing, h):
    return 1.0 / cubic_spline_w(spacing, h)
