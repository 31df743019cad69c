"""The fluid's bundles (fluid.stepper: FluidArrays, FluidWalls, FluidNeighbours, CorrectionParams, FluidBuffers)
for a pass called on its own in a test, from the lists and arrays the test sets; the rest empty or zeros."""
import numpy as np

from sph_fsi_core.fluid.okaji import FLUID_BLOCK_COLUMNS
from sph_fsi_core.fluid.stepper import CorrectionParams, FluidArrays, FluidBuffers, FluidNeighbours, FluidWalls
from sph_fsi_core.numerics.kernels import CUBIC_SPLINE
from sph_fsi_core.numerics.neighbours import INDEX_DTYPE
from sph_fsi_core.numerics.pair_blocks import block_scratch


def arrays(pos, mass, rho=None, pressure=None):
    n = len(pos)
    return FluidArrays(pos, mass, np.zeros(n) if rho is None else rho, np.zeros(n) if pressure is None else pressure,
                       np.zeros((n, 3)))


def walls(pos=None, mass=None):
    pos = np.zeros((0, 3)) if pos is None else pos
    return FluidWalls(pos, np.zeros(0) if mass is None else mass, np.zeros(len(pos)))


def neighbours(fluid_list, wall_list=None, period=None, xz_periodic=None, crossing=None):
    """The half list `fluid_list` and the fluid->wall list `wall_list` (none: empty rows); crossing defaults to
    the union of the two lists' flags."""
    n = len(fluid_list.start) - 1
    period = np.zeros(3) if period is None else period
    if wall_list is None:
        wall_start, wall_index = np.zeros(n + 1, dtype=np.int64), np.zeros(0, dtype=INDEX_DTYPE)
        flags = fluid_list.crossing
    else:
        wall_start, wall_index = wall_list.start, wall_list.index
        flags = fluid_list.crossing | wall_list.crossing
    return FluidNeighbours(fluid_list.start, fluid_list.index, wall_start, wall_index, np.zeros(0, dtype=np.int64),
                           np.zeros(1, dtype=np.int64), np.zeros(0, dtype=INDEX_DTYPE),
                           flags if crossing is None else crossing, np.zeros(0, dtype=np.bool_),
                           fluid_list.targets_at_build, period, xz_periodic)


def params(h, rho0=1000.0, c2=1.0, dt2=0.0, kernel=CUBIC_SPLINE):
    return CorrectionParams(h, rho0, c2, dt2, 0.01, False, 1, 100, 0.0, kernel)


def buffers(n, pairs, wall_pairs=0, chunks=2, **changes):
    """FluidBuffers for n fluid particles and lists of `pairs` and `wall_pairs` pairs, `chunks` chunks; `changes`
    replace fields by name (e.g. f_fluid)."""
    return FluidBuffers(np.zeros(n), np.zeros(n), np.zeros(pairs), np.zeros(wall_pairs), np.zeros((n, 3)), np.zeros(n),
                        np.zeros((chunks, n, 3)), np.zeros((chunks, n)),
                        block_scratch(chunks, FLUID_BLOCK_COLUMNS))._replace(**changes)
