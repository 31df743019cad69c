"""Cell-linked-list neighbour search (Numba): the one list builder of the solid, the fluid, the coupling and the
scenes' checks, and the per-pair kernel cache.

A `NeighbourList` holds, for each target particle a, the source particles b within the cutoff (2h plus a skin) in
compressed rows: `start[a]:start[a+1]` index `index`. A full list has every pair in both rows (and a's own pair),
so a pass over it is a gather, race-free in parallel. A half list (targets and sources the same set) keeps each
pair once, b > a, no self pair: a pass over it evaluates each pair once and adds to both particles, through
per-chunk buffers (see solid/gray2001.py; chunk_first_target cuts the targets into chunks of equal work); that
halves the kernel and pair arithmetic. The skin lets a list serve many steps: it is rebuilt only once some
particle has moved more than half the skin since the build (Verlet's criterion).

The build is tuned, since the fluid rebuilds its lists every step or two (a dam break moves 0.2 h per step against
a skin of 0.1 h): one scan over the candidates with the sources' positions read in cell order from a sorted copy,
rows written once into per-thread buffers, cells out of reach skipped, and a source grid that can be shared (the
water's wall->fluid list scans the fluid grid its half list just built; fixed walls keep theirs). Within a cell the
sources come in ascending order (a stable counting sort), the cells in the order wrapped_cells gives: the rows'
order, and so every pass's summation order, is the scan's.

Periodicity: an axis with a positive entry in `period` wraps (periodic.minimum_image); the period must be at least
twice the cutoff, and the particles of a build within a quarter period less half a skin of the periodic box
(image_margin), so that one image shift is enough until the next build.
"""
import math
from typing import NamedTuple

import numba
import numpy as np
from numba import njit, prange
from numba.cpython.unsafe.numbers import trailing_zeros

from .kernels import cubic_spline_wf, kernel_normalisation
from .periodic import minimum_image, minimum_image_if, xz_periodic_marker

MAX_CELLS_PER_AXIS = 1024
MIN_CELL_BUDGET = 1 << 20   # the grid may hold max(MIN_CELL_BUDGET, 8 N) cells
# Neighbour lists hold unsigned indices: Numba wraps a negative signed index (a[-1] is the last element), a test
# and an add on every load through an index read from memory, which the compiler cannot prove away. Unsigned, the
# fluid's density and pressure passes ran 1.2x faster.
INDEX_DTYPE = np.uint32
SCAN_BLOCK = 64   # candidates per block of the scan (the bits of one mask); 32 and 16 measured slower


@njit(cache=True, fastmath=False, error_model="numpy", inline="always")
def unsigned(k):
    """A position k >= 0 in a neighbour list (from its `start` rows, signed) as an unsigned index: the same reason
    as INDEX_DTYPE, for the loads of the list itself and of arrays aligned with it (1.1-1.2x on the fluid's
    density and pressure passes). Only for indexing: unsigned plus signed is a float in Numba."""
    return np.uint64(k)


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


@njit(cache=True, fastmath=False, error_model="numpy", nogil=True)
def named_in(index, n):
    """A bool per particle 0..n-1: whether `index` (a list's rows) names it, i.e. it has a neighbour in that list."""
    named = np.zeros(n, dtype=np.bool_)
    for k in range(index.shape[0]):
        named[index[k]] = True
    return named


# ---- the cell grid ------------------------------------------------------------------------------------------

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


@njit(cache=True, fastmath=False, error_model="numpy", nogil=True)
def cell_coordinates(pos, lo, cell_size, ncell, period, margin):
    """Integer cell coordinates of each point: wrapped on periodic axes, clamped into the grid on open ones; and
    how many points lie more than margin[k] outside the periodic box [lo, lo + period) along a periodic axis k
    (NeighbourList.build refuses those: one image shift would not do for them).

    Clamping is safe: a point beyond the grid's edge lands in the edge cell, and every point within the cutoff
    of it is in that cell or the next one in, because cells are at least one cutoff wide.
    """
    n = pos.shape[0]
    cell = np.empty((n, 3), dtype=np.int64)
    beyond = 0
    for a in range(n):
        for k in range(3):
            x = pos[a, k] - lo[k]
            c = int(math.floor(x / cell_size[k]))
            if period[k] > 0.0:
                if x < -margin[k] or x >= period[k] + margin[k]:
                    beyond += 1
                c = c % ncell[k]
            elif c < 0:
                c = 0
            elif c >= ncell[k]:
                c = ncell[k] - 1
            cell[a, k] = c
    return cell, beyond


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


class SourceGrid(NamedTuple):
    """Sources binned into cells at least one cutoff wide (cell_grid): what a scan over them needs."""
    lo: np.ndarray
    cell_size: np.ndarray
    ncell: np.ndarray
    cells: np.ndarray            # (N, 3) cell coordinates of each source
    cell_start: np.ndarray       # counting sort by linear cell id ...
    order: np.ndarray            # ... and the sources in that order
    sorted_coordinates: np.ndarray   # (3, N): x, y, z of the sources in that order, one row per axis


def image_margin(period, skin):
    """How far outside the periodic box a list's particles may lie along each axis (inf where open): a quarter
    period less half a skin, so that any two stay within 1.5 periods less a skin of each other, and within 1.5
    periods until the next build, where periodic.minimum_image's one shift is exact."""
    return np.where(period > 0.0, 0.25 * period - 0.5 * skin, np.inf)


def refuse_points_beyond(beyond, period, margin):
    """The error for points too far outside the periodic box (cell_coordinates' count)."""
    if beyond:
        raise ValueError(
            f"{beyond} particle coordinate(s) lie more than {np.min(margin):.6g} m outside the periodic box of "
            f"period {period.tolist()} m; allowed: within a quarter period less half the skin of it (the minimum "
            f"image takes one shift: wrap them into the box)")


def source_grid(sources, cutoff, period, box_lo, box_hi, margin=None):
    """The SourceGrid of `sources` for lists with this cutoff and periodicity; ValueError for a source more than
    `margin` (image_margin; default: no skin) outside the periodic box."""
    margin = image_margin(period, 0.0) if margin is None else margin
    lo, cell_size, ncell = cell_grid(sources, cutoff, period, box_lo, box_hi)
    cells, beyond = cell_coordinates(sources, lo, cell_size, ncell, period, margin)
    refuse_points_beyond(beyond, period, margin)
    cell_start, order = bin_sources(cells, ncell)
    return SourceGrid(lo, cell_size, ncell, cells, cell_start, order, np.ascontiguousarray(sources[order].T))


# ---- the scan -----------------------------------------------------------------------------------------------

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


@njit(cache=True, fastmath=False, error_model="numpy", inline="always")
def _scan_target(a, targets, grid, tcell, period, half_period, cutoff2, half, near, scratch, out, slot, capacity,
                 on_x, on_y, on_z):
    """Target a's row: the sources within the cutoff in the 27 cells around it, in cell order (b > a only for a half
    list), written to out[slot:] while slot stays below `capacity`; returns (the row's length, all of it, and
    whether any of its pairs is near[k] or farther apart along a periodic axis k as stored, before the minimum
    image: NeighbourList.crossing). Cells out of reach are skipped (_neighbour_cells; the margin keeps a source on a
    cell's face from being lost to round-off). on_x, on_y, on_z: the axes to take the minimum image on (constants:
    periodic.xz_periodic_marker); on an open axis near is infinite.

    A cell's candidates are taken in blocks of SCAN_BLOCK: their squared distances (r2) and whether they are near
    apart (far) in one loop over the sources' coordinates in cell order (grid.sorted_coordinates: no indirection,
    no branch, so it runs in SIMD lanes), then a bit mask of those within the cutoff, whose set bits are the pairs
    kept, in order. About one candidate in seven is kept; once the water has moved off its lattice the kept ones
    fall at random, and a test per candidate cost a mispredicted branch per pair (the half list's build at 10^5
    fluid particles in the dam break took 1.6x as long 40 steps in as 3 steps in, with the same candidates). The
    same rows as one loop testing each candidate as it computed it, 1.14-1.17x faster (docs/method.md,
    "Performance design")."""
    cx, cy, cz, gx, gy, gz, r2, far = scratch
    lo, cell_size, ncell, cell_start, order = grid.lo, grid.cell_size, grid.ncell, grid.cell_start, grid.order
    xa, ya, za = targets[a, 0], targets[a, 1], targets[a, 2]
    nx = _neighbour_cells(xa, lo[0], cell_size[0], tcell[a, 0], ncell[0], period[0] > 0.0, cx, gx)
    ny = _neighbour_cells(ya, lo[1], cell_size[1], tcell[a, 1], ncell[1], period[1] > 0.0, cy, gy)
    nz = _neighbour_cells(za, lo[2], cell_size[2], tcell[a, 2], ncell[2], period[2] > 0.0, cz, gz)
    reach2 = cutoff2 * (1.0 + 1e-9)
    xs, ys, zs = grid.sorted_coordinates[0], grid.sorted_coordinates[1], grid.sorted_coordinates[2]
    near_x, near_y, near_z = near[0], near[1], near[2]
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
                        stored_dx = xa - xs[s]
                        stored_dy = ya - ys[s]
                        stored_dz = za - zs[s]
                        dx = minimum_image_if(stored_dx, period[0], half_period[0], on_x)
                        dy = minimum_image_if(stored_dy, period[1], half_period[1], on_y)
                        dz = minimum_image_if(stored_dz, period[2], half_period[2], on_z)
                        r2[j] = dx * dx + dy * dy + dz * dz
                        apart = abs(stored_dy) >= near_y
                        if on_x:
                            apart = apart | (abs(stored_dx) >= near_x)
                        if on_z:
                            apart = apart | (abs(stored_dz) >= near_z)
                        far[j] = apart
                    kept = np.uint64(0)
                    for j in range(m):
                        kept |= np.uint64(r2[j] < cutoff2) << np.uint64(j)
                    while kept != 0:
                        j = np.int64(trailing_zeros(kept))
                        if slot + count < capacity:
                            out[slot + count] = order[unsigned(s0 + j)]
                        count += 1
                        crosses |= far[j]
                        kept &= kept - np.uint64(1)
    return count, crosses


@njit(cache=True, fastmath=False, error_model="numpy", inline="always")
def _stencil_scratch():
    """A thread's scratch for _scan_target: the cells around a target along x, y, z and their squared gaps, and a
    block of candidates' squared distances and `near` flags."""
    return (np.empty(3, dtype=np.int64), np.empty(3, dtype=np.int64), np.empty(3, dtype=np.int64), np.empty(3),
            np.empty(3), np.empty(3), np.empty(SCAN_BLOCK), np.empty(SCAN_BLOCK, dtype=np.bool_))


@njit(cache=True, fastmath=False, error_model="numpy", inline="always")
def _scan_row(a, targets, grid, tcell, period, xz_periodic, half_period, cutoff2, half, near, scratch, out, slot,
              capacity):
    """_scan_target with the axes of the image picked by the type of `xz_periodic` (None: y only)."""
    if xz_periodic is None:
        return _scan_target(a, targets, grid, tcell, period, half_period, cutoff2, half, near, scratch, out, slot,
                            capacity, False, True, False)
    return _scan_target(a, targets, grid, tcell, period, half_period, cutoff2, half, near, scratch, out, slot,
                        capacity, True, True, True)


@njit(cache=True, fastmath=False, error_model="numpy", parallel=True, nogil=True)
def _scan_into_chunks(targets, grid, tcell, period, xz_periodic, cutoff, half, near, scanned, counts, crossing,
                      buffers, used):
    """One scan over the candidate pairs (_scan_target), along y only unless `xz_periodic`
    (periodic.xz_periodic_marker).

    Chunk c (targets n c / C .. n (c + 1) / C) appends its targets' rows, in order, to buffers[c], their
    lengths to counts[a + 1] and their `near` flags (_scan_target) to crossing[a]; used[c] = the length of all its
    rows, more than the buffer holds if it overflowed (the counts and flags are right either way). `scanned`: the
    targets to scan (bool per target; empty: all); the others get empty rows without a look at the grid."""
    n = targets.shape[0]
    chunks = buffers.shape[0]
    capacity = buffers.shape[1]
    cutoff2 = cutoff * cutoff
    half_period = 0.5 * period
    for c in prange(chunks):
        scratch = _stencil_scratch()
        out = buffers[c]
        slot = 0
        for a in range((n * c) // chunks, (n * (c + 1)) // chunks):
            if scanned.shape[0] > 0 and not scanned[a]:
                counts[a + 1] = 0
                crossing[a] = False
                continue
            k, crosses = _scan_row(a, targets, grid, tcell, period, xz_periodic, half_period, cutoff2, half, near,
                                   scratch, out, slot, capacity)
            counts[a + 1] = k
            crossing[a] = crosses
            slot += k
        used[c] = slot


_ALL_TARGETS = np.zeros(0, dtype=np.bool_)   # `scanned` meaning every target


# ---- the pair kernel cache -------------------------------------------------------------------------------------

@njit(cache=True, fastmath=False, error_model="numpy", parallel=True, nogil=True)
def pair_kernel_values(targets, sources, start, index, h, period, w, f):
    """Pair cache for one configuration: W_ab and F_ab = (dW/dr)/r (eq. (1)'s kernel), r_ab by minimum image."""
    half_period = 0.5 * period
    inv_h = 1.0 / h
    sigma = kernel_normalisation(h)
    for a in prange(targets.shape[0]):
        for s in range(start[a], start[a + 1]):
            b = index[s]
            dx = minimum_image(targets[a, 0] - sources[b, 0], period[0], half_period[0])
            dy = minimum_image(targets[a, 1] - sources[b, 1], period[1], half_period[1])
            dz = minimum_image(targets[a, 2] - sources[b, 2], period[2], half_period[2])
            w[s], f[s] = cubic_spline_wf(math.sqrt(dx * dx + dy * dy + dz * dz), inv_h, sigma)


# ---- the list ---------------------------------------------------------------------------------------------------

class NeighbourList:
    """Neighbours of `targets` among `sources` within `radius` + `skin`, reusable until particles move skin/2.

    `period` (3,) gives the periodic length per axis (0: open); `box_lo`/`box_hi` locate periodic axes.

    The build scans the candidates once (_scan_into_chunks). Each thread's rows go to a buffer sized from the
    previous build (a quarter more than its largest chunk, at least PAIRS_PER_TARGET_GUESS per target on the first
    build) and are copied into place; a chunk that overflows its buffer costs one more scan into buffers sized from
    the row lengths the first one counted.

    The source grid of the last build is kept (`grid`): another list over the same sources at the same moment
    can scan it (`build(..., grid=...)`). With `keep_grid_while_sources_stay`, a build whose sources are where
    they were at the last build (compared to the bit) reuses its grid: the fixed walls of a fluid-only scene.

    `crossing[a]`: row a holds a pair at least half a period less 1.1 skins apart along some periodic axis as
    stored (all False without one). Until the next build every target and source stays within half the skin of
    where it was (the staleness test; the fluid's periodic wrap moves a particle by a period and so forces a
    build), so the pairs of the other rows stay less than half a period apart as stored, where minimum_image
    returns the plain difference to the bit: every pair pass skips the image there. `xz_periodic`: the passes'
    argument saying on which axes the image is taken (periodic.xz_periodic_marker).
    """

    PAIRS_PER_TARGET_GUESS = 48

    def __init__(self, radius, skin, period=None, box_lo=None, box_hi=None, half=False,
                 keep_grid_while_sources_stay=False):
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
        # pairs this far apart as stored may need the minimum image before the next build (`crossing`; 10 % more
        # than the skin, so that round-off in the staleness test cannot matter)
        self.near = np.where(self.period > 0.0, 0.5 * self.period - 1.1 * self.skin, np.inf)
        self.xz_periodic = xz_periodic_marker(self.period)
        self.margin = image_margin(self.period, self.skin)
        self._buffers = np.zeros((0, 0), dtype=INDEX_DTYPE)
        self.overflows = 0
        self.grid = None
        self.grid_builds = 0
        self._keep_grid = bool(keep_grid_while_sources_stay)

    def _grid_for(self, sources):
        # the staleness test's copy of the last build's sources tells whether they have moved since
        if self._keep_grid and self._sources_at_build is not None and np.array_equal(self._sources_at_build,
                                                                                        sources):
            return self.grid
        self.grid_builds += 1
        return source_grid(sources, self.cutoff, self.period, self.box_lo, self.box_hi, self.margin)

    def build(self, targets, sources, grid=None, scanned=None):
        """Rebuild for the current positions; `grid`: a SourceGrid of these sources as they are now (else made
        here, or kept from the last build: class docstring). `scanned` (bool per target): only these targets can
        have neighbours (the caller knows it, e.g. from the transposed list); the others get empty rows unscanned."""
        if self.half and sources is not targets:
            raise ValueError("a half neighbour list needs targets and sources to be the same array")
        g = self._grid_for(sources) if grid is None else grid
        if sources is targets:
            tcell = g.cells
        else:
            tcell, beyond = cell_coordinates(targets, g.lo, g.cell_size, g.ncell, self.period, self.margin)
            refuse_points_beyond(beyond, self.period, self.margin)
        n = len(targets)
        chunks = max(numba.get_num_threads(), 1)
        if self._buffers.shape[0] != chunks:
            per_chunk = (n + chunks - 1) // chunks
            self._buffers = np.empty((chunks, per_chunk * self.PAIRS_PER_TARGET_GUESS + 64), dtype=INDEX_DTYPE)
        start = np.zeros(n + 1, dtype=np.int64)
        used = np.zeros(chunks, dtype=np.int64)
        crossing = np.zeros(n, dtype=np.bool_)
        scanned = _ALL_TARGETS if scanned is None else scanned
        _scan_into_chunks(targets, g, tcell, self.period, self.xz_periodic, self.cutoff, self.half, self.near,
                          scanned, start, crossing, self._buffers, used)
        if used.max() > self._buffers.shape[1]:
            # the same scan again into buffers that hold the rows the first one counted: no other compiled scan
            self.overflows += 1
            self._buffers = np.empty((chunks, int(1.25 * used.max()) + 64), dtype=INDEX_DTYPE)
            _scan_into_chunks(targets, g, tcell, self.period, self.xz_periodic, self.cutoff, self.half, self.near,
                              scanned, start, crossing, self._buffers, used)
        np.cumsum(start, out=start)
        index = np.empty(start[-1], dtype=INDEX_DTYPE)
        for c in range(chunks):
            first = start[(n * c) // chunks]
            index[first:first + used[c]] = self._buffers[c, :used[c]]
        wanted = int(1.25 * used.max()) + 64
        if wanted > self._buffers.shape[1] or 2 * wanted < self._buffers.shape[1]:
            self._buffers = np.empty((chunks, wanted), dtype=INDEX_DTYPE)
        self.start, self.index, self.crossing = start, index, crossing
        self.grid = g
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
