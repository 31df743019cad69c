"""The fluid's neighbour lists (fluid-fluid half list, fluid->wall, wall->fluid): one scan over the candidates.

neighbours.NeighbourList builds the same lists by scanning twice (count, then fill) with sources read through
the cell order; the fluid rebuilds its lists every step or two (a dam break moves 0.2 h per step against a skin
of 0.1 h), so here the build is tuned: sources read in cell order from a sorted copy, a division-free minimum
image, rows written once into per-thread buffers, cells out of reach skipped, and a source grid that can be
shared (the wall->fluid list scans the fluid grid the half list just built; fixed walls keep theirs).
"""
import math
from typing import NamedTuple

import numba
import numpy as np
from numba import njit, prange
from numba.cpython.unsafe.numbers import trailing_zeros

from .okaji import fluid_separation, xz_periodic_marker
from ..numerics.neighbours import (INDEX_DTYPE, NeighbourList, bin_sources, cell_coordinates, cell_grid, wrapped_cells,
                         unsigned)


@njit(cache=True, fastmath=False, error_model="numpy", inline="always")
def _first_above(order, first, end, a):
    """The first position in order[first:end] (one cell's sources, ascending: the counting sort is stable) whose
    source is above a (end if none): a half list's row skips the others without looking at them. Most cells lie
    wholly above or below a in index order (the scenes number their particles cell by cell of a lattice), which
    the two ends tell without a search (0.92x the half list's scan at 10^5 fluid particles)."""
    if first >= end or order[unsigned(end - 1)] <= a:
        return end
    if order[unsigned(first)] > a:
        return first
    while first < end:
        middle = (first + end) // 2
        if order[unsigned(middle)] > a:
            end = middle
        else:
            first = middle + 1
    return first


@njit(cache=True, fastmath=False, error_model="numpy", inline="always")
def _neighbour_cells(x, lo, size, c, n, periodic, cells, gaps2):
    """The cells around coordinate x along one axis (c - 1, c, c + 1 as wrapped_cells gives them, in its order)
    and each one's squared gap to x: how far x is from the cell's slab (0 for its own cell). A cell whose gaps on
    the three axes add up to more than the cutoff squared holds no neighbour, so the scan skips it without
    reading its sources (a corner cell of the 27 is out of reach about half the time, an edge cell a fifth).
    On a periodic axis of fewer than 3 cells the gaps are taken as 0 (a cell may be both neighbours)."""
    m = wrapped_cells(c, n, periodic, cells)
    if periodic:
        if n < 3:
            for k in range(m):
                gaps2[k] = 0.0
            return m
        inside = (x - lo) - math.floor((x - lo) / size) * size   # x's offset in its cell, as the tiling repeats
        gaps2[0] = inside * inside
        gaps2[1] = 0.0
        gaps2[2] = (size - inside) * (size - inside)
        return m
    for k in range(m):
        left = lo + cells[k] * size
        gap = max(left - x, x - (left + size), 0.0)
        gaps2[k] = gap * gap
    return m


SCAN_BLOCK = 64   # candidates per block of the scan (the bits of one mask); 32 and 16 measured slower


@njit(cache=True, fastmath=False, error_model="numpy", inline="always")
def _scan_target(a, targets, sorted_sources, tcell, cell_start, order, lo, cell_size, ncell, period, half_period,
                 cutoff2, half, near_y, cx, cy, cz, gx, gy, gz, r2, far_y, out, slot, capacity, on_x, on_y, on_z):
    """Target a's row: the sources within the cutoff in the 27 cells around it, in cell order (b > a only for a half
    list), written to out[slot:] while slot stays below `capacity`; returns (the row's length, all of it, and
    whether any of its pairs is `near_y` or farther apart along y as stored, before the minimum image: see
    FluidNeighbourList.crossing). Cells out of reach are skipped (_neighbour_cells; the margin keeps a source on a
    cell's face from being lost to round-off). on_x, on_y, on_z: the axes to take the minimum image on (constants:
    okaji.xz_periodic_marker).

    A cell's candidates are taken in blocks of SCAN_BLOCK: their squared distances (r2) and whether they are
    near_y apart (far_y) in one loop over the sources' coordinates in cell order (sorted_sources (3, N): no
    indirection, no branch, so it runs in SIMD lanes), then a bit mask of those within the cutoff, whose set bits
    are the pairs kept, in order. About one candidate in seven is kept; once the water has moved off its lattice
    the kept ones fall at random, and a test per candidate cost a mispredicted branch per pair (the half list's
    build at 10^5 fluid particles in the dam break took 1.6x as long 40 steps in as 3 steps in, with the same
    candidates). The same rows as the one loop before (which tested each candidate as it computed it), 1.14-1.17x
    faster (docs/method.md, "Performance design")."""
    xa, ya, za = targets[a, 0], targets[a, 1], targets[a, 2]
    nx = _neighbour_cells(xa, lo[0], cell_size[0], tcell[a, 0], ncell[0], period[0] > 0.0, cx, gx)
    ny = _neighbour_cells(ya, lo[1], cell_size[1], tcell[a, 1], ncell[1], period[1] > 0.0, cy, gy)
    nz = _neighbour_cells(za, lo[2], cell_size[2], tcell[a, 2], ncell[2], period[2] > 0.0, cz, gz)
    reach2 = cutoff2 * (1.0 + 1e-9)
    xs, ys, zs = sorted_sources[0], sorted_sources[1], sorted_sources[2]
    count = 0
    crosses = False
    for ix in range(nx):
        for iy in range(ny):
            gxy = gx[ix] + gy[iy]
            for iz in range(nz):
                if gxy + gz[iz] > reach2:
                    continue
                lid = (cx[ix] * ncell[1] + cy[iy]) * ncell[2] + cz[iz]
                first, end = cell_start[lid], cell_start[lid + 1]
                if half:
                    first = _first_above(order, first, end, a)
                for s0 in range(first, end, SCAN_BLOCK):
                    m = min(SCAN_BLOCK, end - s0)
                    for j in range(m):
                        s = unsigned(s0 + j)
                        dx = fluid_separation(xa - xs[s], period[0], half_period[0], on_x)
                        stored_dy = ya - ys[s]
                        dy = fluid_separation(stored_dy, period[1], half_period[1], on_y)
                        dz = fluid_separation(za - zs[s], period[2], half_period[2], on_z)
                        r2[j] = dx * dx + dy * dy + dz * dz
                        far_y[j] = abs(stored_dy) >= near_y
                    kept = np.uint64(0)
                    for j in range(m):
                        kept |= np.uint64(r2[j] < cutoff2) << np.uint64(j)
                    while kept != 0:
                        j = np.int64(trailing_zeros(kept))
                        if slot + count < capacity:
                            out[slot + count] = order[unsigned(s0 + j)]
                        count += 1
                        crosses |= far_y[j]
                        kept &= kept - np.uint64(1)
    return count, crosses


@njit(cache=True, fastmath=False, error_model="numpy", inline="always")
def _stencil_scratch():
    """A thread's scratch for _scan_target: the cells around a target along x, y, z and their squared gaps, and a
    block of candidates' squared distances and near_y flags."""
    return (np.empty(3, dtype=np.int64), np.empty(3, dtype=np.int64), np.empty(3, dtype=np.int64), np.empty(3),
            np.empty(3), np.empty(3), np.empty(SCAN_BLOCK), np.empty(SCAN_BLOCK, dtype=np.bool_))


@njit(cache=True, fastmath=False, error_model="numpy", parallel=True, nogil=True)
def _scan_into_chunks(targets, sorted_sources, tcell, cell_start, order, lo, cell_size, ncell, period, xz_periodic,
                      cutoff, half, near_y, scanned, counts, crossing, buffers, used):
    """One scan over the candidate pairs (neighbours._scan_pairs with the sources' positions in cell order and a
    division-free minimum image, okaji._image: the fluid's positions are wrapped into the periodic box after
    every step and move less than the skin within one, so one shift by the period is always enough), along y only
    unless `xz_periodic` (okaji.xz_periodic_marker).

    Chunk c (targets n c / C .. n (c + 1) / C) appends its targets' rows, in order, to buffers[c], their
    lengths to counts[a + 1] and their near_y flags (_scan_target) to crossing[a]; used[c] = the length of all its
    rows, more than the buffer holds if it overflowed (the counts and flags are right either way). `scanned`: the
    targets to scan (bool per target; empty: all); the others get empty rows without a look at the grid."""
    n = targets.shape[0]
    chunks = buffers.shape[0]
    capacity = buffers.shape[1]
    cutoff2 = cutoff * cutoff
    half_period = 0.5 * period
    for c in prange(chunks):
        cx, cy, cz, gx, gy, gz, r2, far_y = _stencil_scratch()
        out = buffers[c]
        slot = 0
        for a in range((n * c) // chunks, (n * (c + 1)) // chunks):
            if scanned.shape[0] > 0 and not scanned[a]:
                counts[a + 1] = 0
                crossing[a] = False
                continue
            if xz_periodic is None:
                k, crosses = _scan_target(a, targets, sorted_sources, tcell, cell_start, order, lo, cell_size, ncell,
                                          period, half_period, cutoff2, half, near_y, cx, cy, cz, gx, gy, gz, r2,
                                          far_y, out, slot, capacity, False, True, False)
            else:
                k, crosses = _scan_target(a, targets, sorted_sources, tcell, cell_start, order, lo, cell_size, ncell,
                                          period, half_period, cutoff2, half, near_y, cx, cy, cz, gx, gy, gz, r2,
                                          far_y, out, slot, capacity, True, True, True)
            counts[a + 1] = k
            crossing[a] = crosses
            slot += k
        used[c] = slot


@njit(cache=True, fastmath=False, error_model="numpy", parallel=True, nogil=True)
def _fill_rows(targets, sorted_sources, tcell, cell_start, order, lo, cell_size, ncell, period, xz_periodic, cutoff,
               half, near_y, scanned, start, index):
    """The same scan writing each row into index[start[a]:start[a + 1]] (after a chunk buffer overflowed)."""
    n = targets.shape[0]
    cutoff2 = cutoff * cutoff
    half_period = 0.5 * period
    for a in prange(n):
        if scanned.shape[0] > 0 and not scanned[a]:
            continue
        cx, cy, cz, gx, gy, gz, r2, far_y = _stencil_scratch()
        if xz_periodic is None:
            _scan_target(a, targets, sorted_sources, tcell, cell_start, order, lo, cell_size, ncell, period,
                         half_period, cutoff2, half, near_y, cx, cy, cz, gx, gy, gz, r2, far_y, index, start[a],
                         start[a + 1], False, True, False)
        else:
            _scan_target(a, targets, sorted_sources, tcell, cell_start, order, lo, cell_size, ncell, period,
                         half_period, cutoff2, half, near_y, cx, cy, cz, gx, gy, gz, r2, far_y, index, start[a],
                         start[a + 1], True, True, True)


@njit(cache=True, fastmath=False, error_model="numpy", nogil=True)
def inside_box(points, lo, hi):
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


_ALL_TARGETS = np.zeros(0, dtype=np.bool_)   # `scanned` meaning every target


@njit(cache=True, fastmath=False, error_model="numpy", nogil=True)
def named_in(index, n):
    """A bool per particle 0..n-1: whether `index` (a list's rows) names it, i.e. it has a neighbour in that list."""
    named = np.zeros(n, dtype=np.bool_)
    for k in range(index.shape[0]):
        named[index[k]] = True
    return named


class SourceGrid(NamedTuple):
    """Sources binned into cells at least one cutoff wide (neighbours.cell_grid): what a scan over them needs."""
    lo: np.ndarray
    cell_size: np.ndarray
    ncell: np.ndarray
    cells: np.ndarray            # (N, 3) cell coordinates of each source
    cell_start: np.ndarray       # counting sort by linear cell id ...
    order: np.ndarray            # ... and the sources in that order
    sorted_coordinates: np.ndarray   # (3, N): x, y, z of the sources in that order, one row per axis


def source_grid(sources, cutoff, period, box_lo, box_hi):
    """The SourceGrid of `sources` for lists with this cutoff and periodicity."""
    lo, cell_size, ncell = cell_grid(sources, cutoff, period, box_lo, box_hi)
    cells = cell_coordinates(sources, lo, cell_size, ncell, period)
    cell_start, order = bin_sources(cells, ncell)
    return SourceGrid(lo, cell_size, ncell, cells, cell_start, order, np.ascontiguousarray(sources[order].T))


class FluidNeighbourList(NeighbourList):
    """NeighbourList whose build scans the candidates once (_scan_into_chunks: sources read in cell order, no floor
    in the minimum image, cells out of reach skipped); the same lists in the same order, the same staleness test.

    Each thread's rows go to a buffer sized from the previous build (a quarter more than its largest chunk, at
    least PAIRS_PER_TARGET_GUESS per target on the first build) and are copied into place; a chunk that overflows
    its buffer costs one more scan (_fill_rows), with the exact row lengths the first one counted. (Until session
    11 every build scanned twice: once to count, once to fill.)

    The source grid of the last build is kept (`grid`): another list over the same sources at the same moment
    can scan it (`build(..., grid=...)`). With `keep_grid_while_sources_stay`, a build whose sources are where
    they were at the last build (compared to the bit) reuses its grid: the fixed walls of a fluid-only scene.

    `crossing[a]`: row a holds a pair at least half the y period less 1.1 skins apart along y as stored. Until the
    next build every target and source stays within half the skin of where it was (the staleness test; the
    periodic wrap moves a particle by a period and so forces a build), so the pairs of the other rows stay at most
    half the period apart as stored, and the minimum image leaves them alone: the fluid's passes skip it there."""

    PAIRS_PER_TARGET_GUESS = 48

    def __init__(self, *args, keep_grid_while_sources_stay=False, **kwargs):
        super().__init__(*args, **kwargs)
        self._buffers = np.zeros((0, 0), dtype=INDEX_DTYPE)
        self.overflows = 0
        self.grid = None
        self.grid_builds = 0
        self._keep_grid = bool(keep_grid_while_sources_stay)
        # pairs this far apart along y as stored may need the minimum image before the next build (`crossing`;
        # 10 % more than the skin, so that round-off in the staleness test cannot matter)
        self.near_y = 0.5 * self.period[1] - 1.1 * self.skin if self.period[1] > 0.0 else np.inf
        self.xz_periodic = xz_periodic_marker(self.period)

    def _grid_for(self, sources):
        # the staleness test's copy of the last build's sources tells whether they have moved since
        if self._keep_grid and self._sources_at_build is not None and np.array_equal(self._sources_at_build,
                                                                                        sources):
            return self.grid
        self.grid_builds += 1
        return source_grid(sources, self.cutoff, self.period, self.box_lo, self.box_hi)

    def build(self, targets, sources, grid=None, scanned=None):
        """Rebuild for the current positions; `grid`: a SourceGrid of these sources as they are now (else made
        here, or kept from the last build: class docstring). `scanned` (bool per target): only these targets can
        have neighbours (the caller knows it, e.g. from the transposed list); the others get empty rows unscanned."""
        if self.half and sources is not targets:
            raise ValueError("a half neighbour list needs targets and sources to be the same array")
        g = self._grid_for(sources) if grid is None else grid
        tcell = g.cells if sources is targets else cell_coordinates(targets, g.lo, g.cell_size, g.ncell,
                                                                     self.period)
        n = len(targets)
        chunks = max(numba.get_num_threads(), 1)
        if self._buffers.shape[0] != chunks:
            per_chunk = (n + chunks - 1) // chunks
            self._buffers = np.empty((chunks, per_chunk * self.PAIRS_PER_TARGET_GUESS + 64), dtype=INDEX_DTYPE)
        start = np.zeros(n + 1, dtype=np.int64)
        used = np.zeros(chunks, dtype=np.int64)
        crossing = np.zeros(n, dtype=np.bool_)
        scanned = _ALL_TARGETS if scanned is None else scanned
        _scan_into_chunks(targets, g.sorted_coordinates, tcell, g.cell_start, g.order, g.lo, g.cell_size, g.ncell,
                          self.period, self.xz_periodic, self.cutoff, self.half, self.near_y, scanned, start,
                          crossing, self._buffers, used)
        np.cumsum(start, out=start)
        index = np.empty(start[-1], dtype=INDEX_DTYPE)
        if used.max() <= self._buffers.shape[1]:
            for c in range(chunks):
                first = start[(n * c) // chunks]
                index[first:first + used[c]] = self._buffers[c, :used[c]]
        else:
            self.overflows += 1
            _fill_rows(targets, g.sorted_coordinates, tcell, g.cell_start, g.order, g.lo, g.cell_size, g.ncell,
                       self.period, self.xz_periodic, self.cutoff, self.half, self.near_y, scanned, start, index)
        wanted = int(1.25 * used.max()) + 64
        if wanted > self._buffers.shape[1] or 2 * wanted < self._buffers.shape[1]:
            self._buffers = np.empty((chunks, wanted), dtype=INDEX_DTYPE)
        self.start, self.index, self.crossing = start, index, crossing
        self.grid = g
        self.targets_at_build = targets.copy()
        self._sources_at_build = None if sources is targets else sources.copy()
        self.builds += 1
