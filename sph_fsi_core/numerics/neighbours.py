"""Cell-linked-list neighbour search (Numba) and the per-pair kernel cache.

A `NeighbourList` holds, for each target particle a, the source particles b within the cutoff
(2h plus a skin) in compressed rows: `start[a]:start[a+1]` index `index`. A full list has every pair in both
rows (and a's own pair), so a pass over it is a gather, race-free in parallel. A half list (targets and sources
the same set) keeps each pair once, b > a, no self pair: a pass over it evaluates each pair once and adds to both
particles, through per-chunk buffers (see solid/gray2001.py; chunk_first_target cuts the targets into chunks
of equal work); that halves the kernel and pair arithmetic. The skin lets a list serve many steps: it is rebuilt
only once some particle has moved more than half the skin since the build (Verlet's criterion).

Periodicity: an axis with a positive entry in `period` wraps (minimum image); the period must be at least
twice the cutoff so that one image is enough.
"""
import math

import numpy as np
from numba import njit, prange

from .kernels import cubic_spline_wf

MAX_CELLS_PER_AXIS = 1024
MIN_CELL_BUDGET = 1 << 20   # the grid may hold max(MIN_CELL_BUDGET, 8 N) cells
# Neighbour lists hold unsigned indices: Numba wraps a negative signed index (a[-1] is the last element), a test
# and an add on every load through an index read from memory, which the compiler cannot prove away. Unsigned, the
# fluid's density and pressure passes ran 1.2x faster (session 12).
INDEX_DTYPE = np.uint32


@njit(cache=True, fastmath=False, error_model="numpy", inline="always")
def unsigned(k):
    """A position k >= 0 in a neighbour list (from its `start` rows, signed) as an unsigned index: the same reason
    as INDEX_DTYPE, for the loads of the list itself and of arrays aligned with it (1.1-1.2x on the fluid's
    density and pressure passes, session 12). Only for indexing: unsigned plus signed is a float in Numba."""
    return np.uint64(k)


@njit(cache=True, fastmath=False, error_model="numpy", nogil=True)
def cell_coordinates(pos, lo, cell_size, ncell, period):
    """Integer cell coordinates of each point: wrapped on periodic axes, clamped into the grid on open ones.

    Clamping is safe: a point beyond the grid's edge lands in the edge cell, and every point within the cutoff
    of it is in that cell or the next one in, because cells are at least one cutoff wide.
    """
    n = pos.shape[0]
    cell = np.empty((n, 3), dtype=np.int64)
    for a in range(n):
        for k in range(3):
            c = int(math.floor((pos[a, k] - lo[k]) / cell_size[k]))
            if period[k] > 0.0:
                c = c % ncell[k]
            elif c < 0:
                c = 0
            elif c >= ncell[k]:
                c = ncell[k] - 1
            cell[a, k] = c
    return cell


@njit(cache=True, fastmath=False, error_model="numpy", nogil=True)
def bin_sources(cell, ncell):
    """Counting sort of source points by linear cell id: returns (cell_start, order)."""
    n = cell.shape[0]
    ncells = ncell[0] * ncell[1] * ncell[2]
    counts = np.zeros(ncells + 1, dtype=np.int64)
    linear = np.empty(n, dtype=np.int64)
    for b in range(n):
        lid = (cell[b, 0] * ncell[1] + cell[b, 1]) * ncell[2] + cell[b, 2]
        linear[b] = lid
        counts[lid + 1] += 1
    for c in range(ncells):
        counts[c + 1] += counts[c]
    fill = counts[:-1].copy()
    order = np.empty(n, dtype=INDEX_DTYPE)
    for b in range(n):
        order[fill[linear[b]]] = b
        fill[linear[b]] += 1
    return counts, order


@njit(cache=True, fastmath=False, error_model="numpy", inline="always")
def wrapped_cells(c, n, periodic, out):
    """Neighbouring cell coordinates along one axis (c-1, c, c+1), wrapped or cut at the edges; returns count."""
    m = 0
    for d in range(-1, 2):
        cc = c + d
        if periodic:
            cc = cc % n
        elif cc < 0 or cc >= n:
            continue
        duplicate = False
        for k in range(m):
            if out[k] == cc:
                duplicate = True
        if not duplicate:
            out[m] = cc
            m += 1
    return m


@njit(cache=True, fastmath=False, error_model="numpy", inline="always")
def minimum_image(d, period, inv_period):
    """Shortest periodic separation along one axis (period <= 0: not periodic); inv_period = 1 / period
    (inverse_periods), so the pair loops multiply instead of divide (about 4.5 % of the periodic gate's Gray passes)."""
    if period > 0.0:
        return d - period * math.floor(d * inv_period + 0.5)
    return d


@njit(cache=True, fastmath=False, error_model="numpy", inline="always")
def inverse_periods(period):
    """1 / period per axis for minimum_image (0 where the axis is not periodic)."""
    inv = np.zeros(3)
    for k in range(3):
        if period[k] > 0.0:
            inv[k] = 1.0 / period[k]
    return inv


@njit(cache=True, fastmath=False, error_model="numpy", inline="always")
def chunk_first_target(start, chunk, chunks):
    """First target of `chunk` when a pair list's targets are cut into `chunks` runs of about equal work.

    A particle's work is taken as its pair count plus one, so the cut is a binary search on start[a] + a. Equal
    particle counts are not equal work on a half list: in a thin plate stored layer by layer the first layers own
    the pairs to the next ones and the last layer owns almost none (the paper's gate, 4 layers thick, put two
    thirds of the pairs in the first of two chunks).
    """
    n = start.shape[0] - 1
    if chunk <= 0:
        return 0
    if chunk >= chunks:
        return n
    target = (start[n] + n) * chunk // chunks
    lo = 0
    hi = n
    while lo < hi:   # first a with start[a] + a >= target
        mid = (lo + hi) // 2
        if start[mid] + mid < target:
            lo = mid + 1
        else:
            hi = mid
    return lo


@njit(cache=True, fastmath=False, error_model="numpy", parallel=True, nogil=True)
def _scan_pairs(targets, sources, tcell, cell_start, order, ncell, period, cutoff, half, start, index, fill):
    """One pass over candidate pairs: counts per target (fill=False) or writes them into `index` (fill=True).

    half: targets and sources are the same set and only pairs with b > a are kept.
    """
    inv_period = inverse_periods(period)
    cutoff2 = cutoff * cutoff
    for a in prange(targets.shape[0]):
        cx = np.empty(3, dtype=np.int64)
        cy = np.empty(3, dtype=np.int64)
        cz = np.empty(3, dtype=np.int64)
        nx = wrapped_cells(tcell[a, 0], ncell[0], period[0] > 0.0, cx)
        ny = wrapped_cells(tcell[a, 1], ncell[1], period[1] > 0.0, cy)
        nz = wrapped_cells(tcell[a, 2], ncell[2], period[2] > 0.0, cz)
        count = 0
        slot = start[a] if fill else 0
        for ix in range(nx):
            for iy in range(ny):
                for iz in range(nz):
                    lid = (cx[ix] * ncell[1] + cy[iy]) * ncell[2] + cz[iz]
                    for s in range(cell_start[lid], cell_start[lid + 1]):
                        b = order[s]
                        if half and b <= a:
                            continue
                        dx = minimum_image(targets[a, 0] - sources[b, 0], period[0], inv_period[0])
                        dy = minimum_image(targets[a, 1] - sources[b, 1], period[1], inv_period[1])
                        dz = minimum_image(targets[a, 2] - sources[b, 2], period[2], inv_period[2])
                        if dx * dx + dy * dy + dz * dz < cutoff2:
                            if fill:
                                index[slot] = b
                                slot += 1
                            count += 1
        if not fill:
            start[a + 1] = count


@njit(cache=True, fastmath=False, error_model="numpy", parallel=True, nogil=True)
def pair_kernel_values(targets, sources, start, index, h, period, w, f):
    """Pair cache for one configuration: W_ab and F_ab = (dW/dr)/r (eq. (1)'s kernel), r_ab by minimum image."""
    inv_period = inverse_periods(period)
    inv_h = 1.0 / h
    sigma = 1.0 / (math.pi * h * h * h)
    for a in prange(targets.shape[0]):
        for s in range(start[a], start[a + 1]):
            b = index[s]
            dx = minimum_image(targets[a, 0] - sources[b, 0], period[0], inv_period[0])
            dy = minimum_image(targets[a, 1] - sources[b, 1], period[1], inv_period[1])
            dz = minimum_image(targets[a, 2] - sources[b, 2], period[2], inv_period[2])
            w[s], f[s] = cubic_spline_wf(math.sqrt(dx * dx + dy * dy + dz * dz), inv_h, sigma)


@njit(cache=True, fastmath=False, error_model="numpy", inline="always")
def pair_separation(pos, a, b, period, inv_period, wrap):
    """r_a - r_b, through minimum_image on each axis when `wrap` (the row's NeighbourList.crossing flag), else the
    plain differences (the same bits wherever the flag is off)."""
    rx = pos[a, 0] - pos[b, 0]
    ry = pos[a, 1] - pos[b, 1]
    rz = pos[a, 2] - pos[b, 2]
    if wrap:
        rx = minimum_image(rx, period[0], inv_period[0])
        ry = minimum_image(ry, period[1], inv_period[1])
        rz = minimum_image(rz, period[2], inv_period[2])
    return rx, ry, rz


@njit(cache=True, fastmath=False, error_model="numpy", parallel=True, nogil=True)
def rows_near_a_periodic_face(targets, sources, start, index, near):
    """Per target: whether its row holds a pair at least near[k] apart along some axis k as stored, before the
    minimum image (near[k] = inf on an open axis). NeighbourList.crossing."""
    n = targets.shape[0]
    crossing = np.zeros(n, dtype=np.bool_)
    for a in prange(n):
        for s in range(unsigned(start[a]), unsigned(start[a + 1])):
            b = index[s]
            for k in range(3):
                if abs(targets[a, k] - sources[b, k]) >= near[k]:
                    crossing[a] = True
    return crossing


@njit(cache=True, fastmath=False, error_model="numpy", parallel=True, nogil=True)
def max_displacement(pos, pos_at_build):
    """Largest distance any point has moved since the list was built (Verlet skin test)."""
    n = pos.shape[0]
    d2 = np.zeros(n)
    for a in prange(n):
        dx = pos[a, 0] - pos_at_build[a, 0]
        dy = pos[a, 1] - pos_at_build[a, 1]
        dz = pos[a, 2] - pos_at_build[a, 2]
        d2[a] = dx * dx + dy * dy + dz * dz
    return math.sqrt(d2.max()) if n > 0 else 0.0


@njit(cache=True, fastmath=False, error_model="numpy", nogil=True)
def position_bounds(points):
    """(lowest, highest) coordinate per axis of (N, 3) points, zeros for none: one pass (NumPy's min(axis=0) on a
    C-ordered (N, 3) array took 0.27 ms at 10^4 points, most of a fluid list's grid set-up)."""
    lo = np.zeros(3)
    hi = np.zeros(3)
    if points.shape[0] > 0:
        for k in range(3):
            lo[k] = points[0, k]
            hi[k] = points[0, k]
        for a in range(1, points.shape[0]):
            for k in range(3):
                x = points[a, k]
                if x < lo[k]:
                    lo[k] = x
                if x > hi[k]:
                    hi[k] = x
    return lo, hi


def cell_grid(points, cutoff, period, box_lo, box_hi):
    """Cell grid over the points (periodic axes: over the box), cells at least `cutoff` wide.

    The number of cells is bounded by max(MIN_CELL_BUDGET, 8 N): a particle flung far away (a diverging run)
    coarsens the grid on the open axes instead of allocating a huge one.
    """
    lo, hi = position_bounds(points)
    cell_size = np.empty(3)
    ncell = np.empty(3, dtype=np.int64)
    for k in range(3):
        if period[k] > 0.0:
            lo[k], hi[k] = box_lo[k], box_hi[k]
            ncell[k] = max(int(math.floor(period[k] / cutoff)), 1)
        else:
            extent = max(hi[k] - lo[k], cutoff)
            ncell[k] = min(max(int(math.floor(extent / cutoff)), 1), MAX_CELLS_PER_AXIS)
    budget = max(MIN_CELL_BUDGET, 8 * len(points))
    while int(np.prod(ncell)) > budget:
        open_axes = [k for k in range(3) if period[k] <= 0.0 and ncell[k] > 1]
        if not open_axes:
            break
        k = max(open_axes, key=lambda axis: ncell[axis])
        ncell[k] = max(ncell[k] // 2, 1)
    for k in range(3):
        if period[k] > 0.0:
            cell_size[k] = period[k] / ncell[k]
        else:
            cell_size[k] = max(max(hi[k] - lo[k], cutoff) / ncell[k], cutoff)
    return lo, cell_size, ncell


class NeighbourList:
    """Neighbours of `targets` among `sources` within `radius` + `skin`, reusable until particles move skin/2.

    `period` (3,) gives the periodic length per axis (0: open); `box_lo`/`box_hi` locate periodic axes.

    `crossing[a]`: row a holds a pair at least half a period less 1.1 skins apart along a periodic axis as stored
    (rows_near_a_periodic_face; all False without one). Until the next build every target and source stays
    within half the skin of where it was (the staleness test), so the pairs of the other rows stay less than half
    a period apart as stored, where minimum_image returns the plain difference to the bit: the solid's passes
    skip the image there. (FluidNeighbourList flags along y only; its passes take the x and z image on every row
    when those axes are periodic.)
    """

    def __init__(self, radius, skin, period=None, box_lo=None, box_hi=None, half=False):
        self.half = bool(half)
        self.radius = float(radius)
        self.skin = float(skin)
        self.cutoff = self.radius + self.skin
        self.period = np.zeros(3) if period is None else np.asarray(period, dtype=np.float64)
        self.box_lo = np.zeros(3) if box_lo is None else np.asarray(box_lo, dtype=np.float64)
        self.box_hi = np.zeros(3) if box_hi is None else np.asarray(box_hi, dtype=np.float64)
        for k in range(3):
            if self.period[k] > 0.0 and self.period[k] < 2.0 * self.cutoff:
                raise ValueError(
                    f"periodic length {self.period[k]:.6g} m along axis {'xyz'[k]} is below twice the "
                    f"neighbour cutoff ({2 * self.cutoff:.6g} m); widen the periodic slab")
        self.start = np.zeros(1, dtype=np.int64)
        self.index = np.zeros(0, dtype=INDEX_DTYPE)
        self.builds = 0
        self.targets_at_build = np.zeros((0, 3))   # typed as after a build (the drivers' arguments), stale
        self._sources_at_build = None
        self.crossing = np.zeros(0, dtype=np.bool_)
        # 10 % more than the skin, so that round-off in the staleness test cannot matter
        self._near_face = np.where(self.period > 0.0, 0.5 * self.period - 1.1 * self.skin, np.inf)

    def build(self, targets, sources):
        """Rebuild the lists for the current positions."""
        lo, cell_size, ncell = cell_grid(sources, self.cutoff, self.period, self.box_lo, self.box_hi)
        scell = cell_coordinates(sources, lo, cell_size, ncell, self.period)
        tcell = cell_coordinates(targets, lo, cell_size, ncell, self.period)
        cell_start, order = bin_sources(scell, ncell)
        start = np.zeros(len(targets) + 1, dtype=np.int64)
        dummy = np.zeros(0, dtype=INDEX_DTYPE)
        if self.half and sources is not targets:
            raise ValueError("a half neighbour list needs targets and sources to be the same array")
        _scan_pairs(targets, sources, tcell, cell_start, order, ncell, self.period, self.cutoff, self.half, start,
                    dummy, False)
        np.cumsum(start, out=start)
        index = np.empty(start[-1], dtype=INDEX_DTYPE)
        _scan_pairs(targets, sources, tcell, cell_start, order, ncell, self.period, self.cutoff, self.half, start,
                    index, True)
        self.start, self.index = start, index
        if self.period.any():
            self.crossing = rows_near_a_periodic_face(targets, sources, start, index, self._near_face)
        else:
            self.crossing = np.zeros(len(targets), dtype=np.bool_)
        self.targets_at_build = targets.copy()
        self._sources_at_build = None if sources is targets else sources.copy()
        self.builds += 1

    def is_stale(self, targets, sources):
        """True once some target or source has moved more than half the skin since the last build."""
        if self.builds == 0 or len(targets) != len(self.targets_at_build):
            return True
        moved = max_displacement(targets, self.targets_at_build)
        if self._sources_at_build is not None:
            moved = max(moved, max_displacement(sources, self._sources_at_build))
        return moved > 0.5 * self.skin

    def update(self, targets, sources):
        """Rebuild if stale; returns True when it rebuilt."""
        if self.is_stale(targets, sources):
            self.build(targets, sources)
            return True
        return False

    @property
    def pairs(self):
        return int(self.start[-1])
