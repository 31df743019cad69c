"""The fluid step of Satake et al. sec. 2.2 (Okaji 2002): gravity, predictor (6), density correction, (8), (9).

One step of size dt:

    v += g dt;  r* = r + v dt                                        (body force, eq. (6))
    repeat:  rho from eq. (1) at r*;  stop if converged (below);
             p = c^2 (rho - rho0)_+  (7);  r* += dt^2 dv/dt of eq. (2)    (one correction iteration)
    r(t+dt) = r*;  v* = (r(t+dt) - r(t)) / dt                          (eq. (8))
    v = v* + dt (viscous term of eq. (9), Morris form)

Convergence: the compression (rho - rho0)_+ / rho0 is measured as its maximum and its mean over the fluid; the
one named by fluid.tolerance_on must be at most fluid.density_tolerance (the paper: 1 %), after at least
fluid.min_iterations corrections. A step that reaches fluid.max_iterations stops there and is counted and
reported (`capped`), never silently accepted.

The correction coefficient c: one iteration moves a particle by dt^2 c^2 (grad rho)/rho^2 ~ (c dt / h)^2 h
times its relative compression, so what sets the iteration's stability and speed is kappa = c dt / h, not c.
fluid.correction_coefficient = 0 (the default) takes c = kappa h / dt with kappa = fluid.correction_kappa, so the
iteration behaves the same at any dt; a positive value fixes c in m/s (then a large dt can make it unstable).

Neighbour lists: fluid-fluid (half: each pair once), fluid-wall, and wall-fluid (for the wall pressure; only wall particles within
reach of the water's bounding box), cutoff 2h + skin, built at r* when some particle has moved more than half the
skin since the last build and reused by every iteration of the step (and by later steps while valid); every
position correction measures how far particles have moved since the build, and the loop returns for a rebuild
mid-step if one may have crossed half the skin.

Pressure output: FluidState.pressure is the sum of the step's iteration pressures (fluid_okaji.py's docstring).
"""
import math
from typing import NamedTuple

import numba
import numpy as np
from numba import njit, prange

from .fluid_okaji import (DENSITY_BLOCK_COLUMNS, _image, apply_displacement, compression_error, gravity_and_predictor,
                          pressure_displacement, summation_density, velocity_from_displacement, viscous_velocity,
                          wall_pressure, wrap_periodic)
from .kernels import SUPPORT_RADIUS_IN_H
from .neighbours import (INDEX_DTYPE, NeighbourList, _bin_sources, _bounds, _cell_coordinates, _grid,
                         _wrapped_cells, unsigned)
from .pair_blocks import block_scratch

CONVERGED, CAPPED, NEEDS_REBUILD = 0, 1, 2


class StepReport(NamedTuple):
    """What one fluid step did: correction iterations, final compression (max, mean), whether it hit the cap."""
    dt: float
    iterations: int
    error_max: float
    error_mean: float
    capped: bool
    rebuilds: int


@njit(cache=True, fastmath=False, error_model="numpy", nogil=True)
def correction_loop(it_start, pos, mass, rho, p, p_over_rho2, accumulated, fstart, findex, f_fluid, wall_pos,
                    wall_mass, wall_p_over_rho2, wstart, windex, f_wall, active, wfstart, wfindex, period, h, rho0,
                    c2, dt2, tolerance, on_mean, min_iterations, max_iterations, pos_at_build, half_skin, disp, total,
                    moved2, buf, density_buf, blocks):
    """The density-correction iterations of one step, from iteration `it_start` (lists valid on entry).

    Returns (iterations done, max error, mean error, status): CONVERGED, CAPPED, or NEEDS_REBUILD when a particle
    has moved more than half the skin since the lists were built (the caller rebuilds and calls again).
    Four parallel passes per iteration: density with (7), wall pressure, position correction, apply.
    """
    it = it_start
    while True:
        summation_density(pos, mass, fstart, findex, wall_pos, wall_mass, wstart, windex, period, h, rho0, c2, rho,
                          p, p_over_rho2, f_fluid, f_wall, density_buf, blocks)
        emax, emean = compression_error(rho, rho0)
        err = emean if on_mean else emax
        if it >= min_iterations and err <= tolerance:
            return it, emax, emean, CONVERGED
        if it >= max_iterations:
            return it, emax, emean, CAPPED
        if wall_pos.shape[0] > 0:
            wall_pressure(wall_pos, active, pos, p, wfstart, wfindex, period, h, rho0, wall_p_over_rho2)
        pressure_displacement(pos, mass, p, p_over_rho2, fstart, findex, f_fluid, wall_pos, wall_mass,
                              wall_p_over_rho2, wstart, windex, f_wall, period, dt2, disp, accumulated, buf)
        apply_displacement(pos, disp, total, pos_at_build, moved2)
        it += 1
        if _largest(moved2) > half_skin * half_skin:
            return it, -1.0, -1.0, NEEDS_REBUILD


@njit(cache=True, fastmath=False, error_model="numpy", nogil=True)
def _largest(x):
    m = 0.0
    for i in range(x.shape[0]):
        if x[i] > m:
            m = x[i]
    return m


@njit(cache=True, fastmath=False, error_model="numpy", inline="always")
def _first_above(order, first, end, a):
    """The first position in order[first:end] (one cell's sources, ascending: the counting sort is stable) whose
    source is above a (end if none): a half list's row skips the others without looking at them."""
    while first < end:
        middle = (first + end) // 2
        if order[unsigned(middle)] > a:
            end = middle
        else:
            first = middle + 1
    return first


@njit(cache=True, fastmath=False, error_model="numpy", inline="always")
def _scan_target(a, targets, sorted_sources, tcell, cell_start, order, ncell, period, half_period, cutoff2, half, cx, cy,
                 cz, out, slot, capacity):
    """Target a's row: the sources within the cutoff in the 27 cells around it, in cell order (b > a only for a half
    list), written to out[slot:] while slot stays below `capacity`; returns the row's length (all of it)."""
    nx = _wrapped_cells(tcell[a, 0], ncell[0], period[0] > 0.0, cx)
    ny = _wrapped_cells(tcell[a, 1], ncell[1], period[1] > 0.0, cy)
    nz = _wrapped_cells(tcell[a, 2], ncell[2], period[2] > 0.0, cz)
    xa, ya, za = targets[a, 0], targets[a, 1], targets[a, 2]
    count = 0
    for ix in range(nx):
        for iy in range(ny):
            for iz in range(nz):
                lid = (cx[ix] * ncell[1] + cy[iy]) * ncell[2] + cz[iz]
                first, end = cell_start[lid], cell_start[lid + 1]
                if half:
                    first = _first_above(order, first, end, a)
                for s in range(unsigned(first), unsigned(end)):
                    b = order[s]
                    dx = _image(xa - sorted_sources[s, 0], period[0], half_period[0])
                    dy = _image(ya - sorted_sources[s, 1], period[1], half_period[1])
                    dz = _image(za - sorted_sources[s, 2], period[2], half_period[2])
                    if dx * dx + dy * dy + dz * dz < cutoff2:
                        if slot + count < capacity:
                            out[slot + count] = b
                        count += 1
    return count


@njit(cache=True, fastmath=False, error_model="numpy", parallel=True, nogil=True)
def _scan_into_chunks(targets, sorted_sources, tcell, cell_start, order, ncell, period, cutoff, half, counts, buffers,
                      used):
    """One scan over the candidate pairs (neighbours._scan_pairs with the sources' positions in cell order and a
    division-free minimum image, fluid_okaji._image: the fluid's positions are wrapped into the periodic box after
    every step and move less than the skin within one, so one shift by the period is always enough).

    Chunk c (targets n c / C .. n (c + 1) / C) appends its targets' rows, in order, to buffers[c] and their
    lengths to counts[a + 1]; used[c] = the length of all its rows, more than the buffer holds if it overflowed
    (the counts are right either way)."""
    n = targets.shape[0]
    chunks = buffers.shape[0]
    capacity = buffers.shape[1]
    cutoff2 = cutoff * cutoff
    half_period = 0.5 * period
    for c in prange(chunks):
        cx = np.empty(3, dtype=np.int64)
        cy = np.empty(3, dtype=np.int64)
        cz = np.empty(3, dtype=np.int64)
        out = buffers[c]
        slot = 0
        for a in range((n * c) // chunks, (n * (c + 1)) // chunks):
            k = _scan_target(a, targets, sorted_sources, tcell, cell_start, order, ncell, period, half_period, cutoff2,
                             half, cx, cy, cz, out, slot, capacity)
            counts[a + 1] = k
            slot += k
        used[c] = slot


@njit(cache=True, fastmath=False, error_model="numpy", parallel=True, nogil=True)
def _fill_rows(targets, sorted_sources, tcell, cell_start, order, ncell, period, cutoff, half, start, index):
    """The same scan writing each row into index[start[a]:start[a + 1]] (after a chunk buffer overflowed)."""
    n = targets.shape[0]
    cutoff2 = cutoff * cutoff
    half_period = 0.5 * period
    for a in prange(n):
        cx = np.empty(3, dtype=np.int64)
        cy = np.empty(3, dtype=np.int64)
        cz = np.empty(3, dtype=np.int64)
        _scan_target(a, targets, sorted_sources, tcell, cell_start, order, ncell, period, half_period, cutoff2, half,
                     cx, cy, cz, index, start[a], start[a + 1])


@njit(cache=True, fastmath=False, error_model="numpy", nogil=True)
def _inside_box(points, lo, hi):
    """Indices (ascending) of the points with lo <= x <= hi on every axis: one pass (NumPy's comparisons and
    all(axis=1) on (N, 3) arrays, with the bounds' min(axis=0), took 8 ms of a 72 ms rebuild at 10^5 fluid
    particles)."""
    keep = np.empty(points.shape[0], dtype=np.int64)
    count = 0
    for a in range(points.shape[0]):
        inside = True
        for k in range(3):
            if not (lo[k] <= points[a, k] <= hi[k]):
                inside = False
        if inside:
            keep[count] = a
            count += 1
    return keep[:count].copy()


class FluidNeighbourList(NeighbourList):
    """NeighbourList whose build scans the candidates once (_scan_into_chunks: sources read in cell order, no floor
    in the minimum image); the same lists in the same order, the same staleness test.

    Each thread's rows go to a buffer sized from the previous build (a quarter more than its largest chunk, at
    least PAIRS_PER_TARGET_GUESS per target on the first build) and are copied into place; a chunk that overflows
    its buffer costs one more scan (_fill_rows), with the exact row lengths the first one counted. (Until session
    11 every build scanned twice: once to count, once to fill.)"""

    PAIRS_PER_TARGET_GUESS = 48

    def __init__(self, *args, **kwargs):
        super().__init__(*args, **kwargs)
        self._buffers = np.zeros((0, 0), dtype=INDEX_DTYPE)
        self.overflows = 0

    def build(self, targets, sources):
        if self.half and sources is not targets:
            raise ValueError("a half neighbour list needs targets and sources to be the same array")
        lo, cell_size, ncell = _grid(sources, self.cutoff, self.period, self.box_lo, self.box_hi)
        scell = _cell_coordinates(sources, lo, cell_size, ncell, self.period)
        tcell = scell if sources is targets else _cell_coordinates(targets, lo, cell_size, ncell, self.period)
        cell_start, order = _bin_sources(scell, ncell)
        sorted_sources = np.ascontiguousarray(sources[order])
        n = len(targets)
        chunks = max(numba.get_num_threads(), 1)
        if self._buffers.shape[0] != chunks:
            per_chunk = (n + chunks - 1) // chunks
            self._buffers = np.empty((chunks, per_chunk * self.PAIRS_PER_TARGET_GUESS + 64), dtype=INDEX_DTYPE)
        start = np.zeros(n + 1, dtype=np.int64)
        used = np.zeros(chunks, dtype=np.int64)
        _scan_into_chunks(targets, sorted_sources, tcell, cell_start, order, ncell, self.period, self.cutoff, self.half,
                          start, self._buffers, used)
        np.cumsum(start, out=start)
        index = np.empty(start[-1], dtype=INDEX_DTYPE)
        if used.max() <= self._buffers.shape[1]:
            for c in range(chunks):
                first = start[(n * c) // chunks]
                index[first:first + used[c]] = self._buffers[c, :used[c]]
        else:
            self.overflows += 1
            _fill_rows(targets, sorted_sources, tcell, cell_start, order, ncell, self.period, self.cutoff, self.half,
                       start, index)
        wanted = int(1.25 * used.max()) + 64
        if wanted > self._buffers.shape[1] or 2 * wanted < self._buffers.shape[1]:
            self._buffers = np.empty((chunks, wanted), dtype=INDEX_DTYPE)
        self.start, self.index = start, index
        self._targets_at_build = targets.copy()
        self._sources_at_build = None if sources is targets else sources.copy()
        self.builds += 1


class FluidSolver:
    """The fluid's work arrays, neighbour lists and settings; `step(dt)` advances the fluid by one step."""

    def __init__(self, fluid, walls, h, period, box_lo, box_hi, skin):
        self.fluid = fluid
        self.walls = walls
        self.h = float(h)
        self.period = np.asarray(period, dtype=np.float64)
        self.box_lo = np.asarray(box_lo if box_lo is not None else np.zeros(3), dtype=np.float64)
        n = fluid.count
        radius = SUPPORT_RADIUS_IN_H * self.h
        self.skin = float(skin)
        # half list: each fluid pair once (fluid_okaji.py), which halves the pair work of every pass and the build
        self.fluid_neighbours = FluidNeighbourList(radius, skin, period=period, box_lo=box_lo, box_hi=box_hi,
                                                   half=True)
        self.wall_neighbours = FluidNeighbourList(radius, skin, period=period, box_lo=box_lo, box_hi=box_hi)
        self.wall_fluid_neighbours = FluidNeighbourList(radius, skin, period=period, box_lo=box_lo, box_hi=box_hi)
        self.wall_pos = walls.pos if walls is not None else np.zeros((0, 3))
        self.wall_mass = walls.mass if walls is not None else np.zeros(0)
        self.wall_p_over_rho2 = np.zeros(len(self.wall_mass))
        self.active_walls = np.zeros(0, dtype=np.int64)
        self._no_walls_start = np.zeros(n + 1, dtype=np.int64)
        self._no_walls_index = np.zeros(0, dtype=INDEX_DTYPE)
        self.pos_old = np.zeros((n, 3))
        self.disp = np.zeros((n, 3))
        self.p = np.zeros(n)
        self.p_over_rho2 = np.zeros(n)
        self.vel_work = np.zeros((n, 3))
        self.moved2 = np.zeros(n)
        self.buf = np.zeros((max(numba.get_num_threads(), 1), n, 3))   # per-chunk pair accumulators
        self.density_buf = np.zeros(self.buf.shape[:2])   # per-chunk density sums
        self.blocks = block_scratch(self.buf.shape[0], DENSITY_BLOCK_COLUMNS)   # per-chunk pair blocks
        self.f_fluid = np.zeros(0)
        self.f_wall = np.zeros(0)
        self.builds = 0
        # settings (configure())
        self.rho0 = 1000.0
        self.nu = 1.0e-6
        self.gravity = (0.0, 0.0, 0.0)
        self.tolerance = 0.01
        self.on_mean = False
        self.coefficient = 0.0
        self.kappa = 1.0
        self.min_iterations = 1
        self.max_iterations = 100
        self.rebuild()
        self.density()

    def configure(self, rho0, nu, gravity, tolerance, tolerance_on, coefficient, kappa, min_iterations,
                  max_iterations):
        self.rho0, self.nu = float(rho0), float(nu)
        self.gravity = tuple(float(g) for g in gravity)
        self.tolerance = float(tolerance)
        self.on_mean = tolerance_on == "mean"
        self.coefficient, self.kappa = float(coefficient), float(kappa)
        self.min_iterations, self.max_iterations = int(min_iterations), int(max_iterations)

    # ---- neighbour lists -------------------------------------------------------------------------------
    def rebuild(self):
        pos = self.fluid.pos
        self.fluid_neighbours.build(pos, pos)
        if len(self.f_fluid) < self.fluid_neighbours.pairs:
            self.f_fluid = np.zeros(int(1.25 * self.fluid_neighbours.pairs) + 16)
        if self.walls is not None:
            self.wall_neighbours.build(pos, self.wall_pos)
            # Only wall particles within the cutoff of the water's bounding box can have fluid neighbours; the
            # others would be clamped into the grid's edge cells and scan them for nothing.
            reach = self.wall_fluid_neighbours.cutoff
            lo, hi = _bounds(pos)
            lo -= reach
            hi += reach
            for k in range(3):
                if self.period[k] > 0.0:
                    lo[k], hi[k] = -np.inf, np.inf
            self.active_walls = _inside_box(self.wall_pos, lo, hi)
            self.wall_fluid_neighbours.build(np.ascontiguousarray(self.wall_pos[self.active_walls]), pos)
            self.wall_p_over_rho2[:] = 0.0
            if len(self.f_wall) < self.wall_neighbours.pairs:
                self.f_wall = np.zeros(int(1.25 * self.wall_neighbours.pairs) + 16)
        self.builds += 1

    def _wall_rows(self):
        """(fluid->wall start, index, wall->fluid start, index); empty rows when the scene has no walls."""
        if self.walls is None:
            return self._no_walls_start, self._no_walls_index, np.zeros(1, dtype=np.int64), self._no_walls_index
        return (self.wall_neighbours.start, self.wall_neighbours.index, self.wall_fluid_neighbours.start,
                self.wall_fluid_neighbours.index)

    def density(self):
        """Eq. (1) at the current positions (lists must be valid); returns (max, mean) compression."""
        fl, nb = self.fluid, self.fluid_neighbours
        wstart, windex, _, _ = self._wall_rows()
        summation_density(fl.pos, fl.mass, nb.start, nb.index, self.wall_pos, self.wall_mass, wstart, windex,
                          self.period, self.h, self.rho0, 0.0, fl.rho, self.p, self.p_over_rho2, self.f_fluid,
                          self.f_wall, self.density_buf, self.blocks)
        return compression_error(fl.rho, self.rho0)

    # ---- time step ---------------------------------------------------------------------------------------
    def max_speed(self):
        v = self.fluid.vel
        return float(np.sqrt((v * v).sum(axis=1).max())) if len(v) else 0.0

    def stable_dt(self, cfl):
        """min of: cfl h / |v|max (advection), cfl sqrt(h / |g|) (body force), 0.125 h^2 / nu (viscous diffusion,
        Morris et al. 1997). At rest only the last two bound it."""
        limits = [0.125 * self.h * self.h / self.nu]
        g = math.sqrt(sum(x * x for x in self.gravity))
        if g > 0.0:
            limits.append(cfl * math.sqrt(self.h / g))
        vmax = self.max_speed()
        if vmax > 0.0:
            limits.append(cfl * self.h / vmax)
        return min(limits)

    def correction_c(self, dt):
        """c of eq. (7): fluid.correction_coefficient, or kappa h / dt when that is 0 (module docstring)."""
        return self.coefficient if self.coefficient > 0.0 else self.kappa * self.h / dt

    # ---- one step ----------------------------------------------------------------------------------------
    def step(self, dt):
        fl = self.fluid
        gravity_and_predictor(fl.pos, fl.vel, dt, self.gravity[0], self.gravity[1], self.gravity[2], self.pos_old)
        fl.correction_displacement[:] = 0.0
        fl.pressure[:] = 0.0
        c = self.correction_c(dt)
        it, rebuilds = 0, 0
        while True:
            if self.fluid_neighbours.is_stale(fl.pos, fl.pos):
                self.rebuild()
                rebuilds += 1
            nb = self.fluid_neighbours
            wstart, windex, wfstart, wfindex = self._wall_rows()
            it, emax, emean, status = correction_loop(
                it, fl.pos, fl.mass, fl.rho, self.p, self.p_over_rho2, fl.pressure, nb.start, nb.index, self.f_fluid,
                self.wall_pos, self.wall_mass, self.wall_p_over_rho2, wstart, windex, self.f_wall, self.active_walls,
                wfstart, wfindex, self.period, self.h, self.rho0, c * c, dt * dt, self.tolerance, self.on_mean,
                self.min_iterations, self.max_iterations, nb._targets_at_build, 0.5 * self.skin, self.disp,
                fl.correction_displacement, self.moved2, self.buf, self.density_buf, self.blocks)
            if status != NEEDS_REBUILD:
                break
            if rebuilds > self.max_iterations + 2:   # cannot happen unless particles fly: let the watchdog see it
                break
            self.rebuild()
            rebuilds += 1
        velocity_from_displacement(fl.pos, self.pos_old, dt, fl.vel)
        if self.nu > 0.0:
            viscous_velocity(fl.pos, fl.vel, fl.mass, fl.rho, nb.start, nb.index, self.f_fluid, self.period, self.h,
                             self.nu, dt, self.vel_work, self.buf)
            fl.vel[:] = self.vel_work
        if self.period.any():
            wrap_periodic(fl.pos, self.period, self.box_lo)
        return StepReport(dt, it, emax, emean, status == CAPPED, rebuilds)
