"""The fluid step's compiled density-correction loop (Satake et al. sec. 2.2, Okaji 2002: eqs. (1), (7), (2)) and
the bundles of arrays it takes: the step around it (gravity, the predictor, eq. (8), (9)) is fluid/solver.py's
FluidSolver, the passes it calls fluid/okaji.py's."""
from typing import NamedTuple

import numpy as np
from numba import njit, prange

from .okaji import apply_displacement, compression_error, pressure_displacement, summation_density, wall_pressure

CONVERGED, CAPPED, NEEDS_REBUILD = 0, 1, 2


class FluidArrays(NamedTuple):
    """The fluid's particle arrays the correction loop moves and writes (state.FluidState's, N particles)."""
    pos: np.ndarray                      # (N, 3) m, r*, corrected in place
    mass: np.ndarray                     # (N,) kg
    rho: np.ndarray                      # (N,) kg/m^3, eq. (1)'s summation density at the current positions
    pressure: np.ndarray                 # (N,) Pa, the sum of the step's iteration pressures (7)
    correction_displacement: np.ndarray  # (N, 3) m, the step's correction so far, r - r* (eq. (10)'s coupling)

    @classmethod
    def of(cls, fluid):
        """The arrays of a state.FluidState (the same arrays, not copies)."""
        return cls(fluid.pos, fluid.mass, fluid.rho, fluid.pressure, fluid.correction_displacement)


class FluidWalls(NamedTuple):
    """The fluid's wall particles (fixed walls, or the coupling's moving boundary), M of them; empty without."""
    pos: np.ndarray           # (M, 3) m
    mass: np.ndarray          # (M,) kg
    p_over_rho2: np.ndarray   # (M,) Pa m^6/kg^2, p_w / rho0^2 of eq. (2), written by the wall pressure pass


class FluidNeighbours(NamedTuple):
    """The fluid's three lists (numerics/neighbours.py; row a of a list is index[start[a]:start[a + 1]]) and the box."""
    fluid_start: np.ndarray        # (N + 1,) int64, the fluid-fluid half list (each pair once)
    fluid_index: np.ndarray        # (P,)
    wall_start: np.ndarray         # (N + 1,) int64, fluid -> wall
    wall_index: np.ndarray         # (Pw,)
    active_walls: np.ndarray       # (A,) int64, the wall particles within reach of the water, one row each below
    wall_fluid_start: np.ndarray   # (A + 1,) int64, wall -> fluid, row i for wall particle active_walls[i]
    wall_fluid_index: np.ndarray   # (Pw',)
    crossing: np.ndarray           # (N,) bool, fluid rows (fluid and wall) that may need the minimum image
    wall_crossing: np.ndarray      # (A,) bool, wall -> fluid rows that may
    targets_at_build: np.ndarray   # (N, 3) m, the fluid positions the lists were built at (the skin test)
    period: np.ndarray             # (3,) m, the periodic box's lengths (0: not periodic)
    xz_periodic: object            # None or True: periodic.xz_periodic_marker(period)


class CorrectionParams(NamedTuple):
    """The numbers of one step's density correction (module docstring)."""
    h: float               # m, smoothing length
    rho0: float            # kg/m^3, reference density
    c2: float              # m^2/s^2, c^2 of eq. (7) (FluidSolver.correction_c)
    dt2: float             # s^2, the step's dt^2
    tolerance: float       # fluid.density_tolerance, on the relative compression (rho - rho0)_+ / rho0
    on_mean: bool          # the tolerance applies to the mean compression (else the maximum)
    min_iterations: int
    max_iterations: int    # the cap: reaching it ends the step as CAPPED
    half_skin: float       # m, a particle moved further than this since the build needs new lists
    kernel: int            # numerics/kernels.py's id of the water's kernel (fluid.kernel)


class FluidBuffers(NamedTuple):
    """FluidSolver's work arrays as the correction loop takes them; C chunks (threads) of the half-list passes.

    The pair caches are replaced when the lists outgrow them (FluidSolver.rebuild): take them after that."""
    p: np.ndarray             # (N,) Pa, this iteration's pressure of eq. (7)
    p_over_rho2: np.ndarray   # (N,) Pa m^6/kg^2, p / rho^2 of eq. (2)
    f_fluid: np.ndarray       # (>= P,) 1/m^5, pair cache F_ab = (dW/dr)/r of the fluid list
    f_wall: np.ndarray        # (>= Pw,) 1/m^5, the same for the fluid -> wall list
    disp: np.ndarray          # (N, 3) m, one iteration's position correction dt^2 dv/dt
    moved2: np.ndarray        # (N,) m^2, squared distance from targets_at_build
    buf: np.ndarray           # (C, N, 3) per-chunk sums of the pressure pass
    density_buf: np.ndarray   # (C, N) per-chunk sums of the density pass
    blocks: np.ndarray        # (C, columns) pair-block scratch (numerics/pair_blocks.py)


@njit(cache=True, fastmath=False, error_model="numpy", nogil=True)
def correction_loop(it_start, fluid, walls, neighbours, prm, work, partial, last_p, before):
    """The density-correction iterations of one step (Okaji 2002 as in Satake et al. sec. 2.2: eq. (1), (7), (2)),
    from iteration `it_start` (lists valid on entry).

    `fluid`: FluidArrays, `walls`: FluidWalls, `neighbours`: FluidNeighbours, `prm`: CorrectionParams, `work`:
    FluidBuffers. Returns (iterations done, max error, mean error, status): CONVERGED, CAPPED, or NEEDS_REBUILD
    when a particle has moved more than half the skin since the lists were built (the caller rebuilds and calls
    again). Four parallel passes per iteration: density with (7), wall pressure, position correction, apply.

    `partial` (fluid.partial_iteration): the iteration that takes the error below the tolerance is taken only in
    part, the fraction f = (e_before - tol) / (e_before - e_after) of it (the error taken as linear in the
    fraction), so the step ends with its error at the tolerance rather than anywhere below it, and the errors
    returned are the ones interpolated so. `last_p` (N,) keeps the last iteration's pressures for it, `before` (2,)
    the (max, mean) errors before the last iteration (the caller sets -1 at the step's start; kept across a
    rebuild). Without it the work a step does jumps by whole iterations, and at rest the pressure the water reads
    comes in pulses (docs/method.md, "Fluid", the partial iteration).
    """
    pos = fluid.pos
    rho = fluid.rho
    moved2 = work.moved2
    it = it_start
    while True:
        summation_density(fluid, walls, neighbours, prm, work)
        emax, emean = compression_error(rho, prm.rho0)
        err = emean if prm.on_mean else emax
        if it >= prm.min_iterations and err <= prm.tolerance:
            err_before = before[1] if prm.on_mean else before[0]
            if partial and err_before > prm.tolerance:      # then err_before > tol >= err
                kept = (err_before - prm.tolerance) / (err_before - err)
                undo_part(pos, work.disp, fluid.correction_displacement, fluid.pressure, last_p, 1.0 - kept)
                emax = before[0] + kept * (emax - before[0])
                emean = before[1] + kept * (emean - before[1])
            return it, emax, emean, CONVERGED
        if it >= prm.max_iterations:
            return it, emax, emean, CAPPED
        if walls.pos.shape[0] > 0:
            wall_pressure(walls, pos, work.p, neighbours, prm.h, prm.rho0, prm.kernel)
        pressure_displacement(fluid, walls, neighbours, prm, work)
        if partial:
            last_p[:] = work.p
        apply_displacement(pos, work.disp, fluid.correction_displacement, neighbours.targets_at_build, moved2)
        before[0] = emax
        before[1] = emean
        it += 1
        if _largest(moved2) > prm.half_skin * prm.half_skin:
            return it, -1.0, -1.0, NEEDS_REBUILD


@njit(cache=True, fastmath=False, error_model="numpy", parallel=True, nogil=True)
def undo_part(pos, disp, total, pressure, last_p, share):
    """Take back `share` of the last iteration: its displacement `disp` from the positions and from the step's
    correction `total`, its pressures `last_p` from the step's pressure sum."""
    for a in prange(pos.shape[0]):
        for k in range(3):
            d = share * disp[a, k]
            pos[a, k] -= d
            total[a, k] -= d
        pressure[a] -= share * last_p[a]


@njit(cache=True, fastmath=False, error_model="numpy", nogil=True)
def _largest(x):
    m = 0.0
    for i in range(x.shape[0]):
        if x[i] > m:
            m = x[i]
    return m


