"""The fluid's neighbour lists (sph_fsi_core/fluid/neighbours.py) against the general NeighbourList and brute force."""
import numpy as np
import pytest

from sph_fsi_core.fluid.neighbours import FluidNeighbourList, inside_box, named_in, source_grid
from sph_fsi_core.numerics.neighbours import NeighbourList


def lattice(nx, ny, nz, spacing, offset=(0.0, 0.0, 0.0)):
    """Sites (i + 1/2) dp + offset for i < nx, j < ny, k < nz, x slowest."""
    axes = [(np.arange(n) + 0.5) * spacing + o for n, o in zip((nx, ny, nz), offset)]
    return np.stack(np.meshgrid(*axes, indexing="ij"), axis=-1).reshape(-1, 3)


DP = 1.0e-3
H = 1.3 * DP


def _brute_force_rows(targets, sources, cutoff, period, half):
    """Each target's sources within the cutoff (minimum image), ascending: the sets the lists must hold."""
    d = targets[:, None, :] - sources[None, :, :]
    for k in range(3):
        if period[k] > 0.0:
            d[..., k] -= period[k] * np.round(d[..., k] / period[k])
    near = (d ** 2).sum(axis=2) < cutoff * cutoff
    if half:
        near &= np.arange(len(sources))[None, :] > np.arange(len(targets))[:, None]
    return [np.flatnonzero(row) for row in near]


def _rows(lst):
    return [np.sort(lst.index[lst.start[a]:lst.start[a + 1]]) for a in range(len(lst.start) - 1)]


@pytest.mark.parametrize("half", [True, False])
def test_fluid_neighbour_list_equals_the_general_one(half):
    """The fluid's list builder (sources in cell order, division-free minimum image) gives exactly the general
    NeighbourList's rows, on a jittered periodic block with particles a little outside the box."""
    pos = lattice(9, 9, 9, DP) + np.random.default_rng(3).normal(0.0, 0.3 * DP, (729, 3))
    period = np.array([0.0, 9 * DP, 0.0])
    pos[:5, 1] -= 0.2 * DP        # a little below the periodic box's start
    cutoff_args = (2.0 * H, 0.1 * H)
    general = NeighbourList(*cutoff_args, period=period, box_lo=np.zeros(3), box_hi=period, half=half)
    fast = FluidNeighbourList(*cutoff_args, period=period, box_lo=np.zeros(3), box_hi=period, half=half)
    general.build(pos, pos)
    fast.build(pos, pos)
    assert general.pairs > 10 * len(pos) and np.array_equal(general.start, fast.start)
    assert np.array_equal(general.index, fast.index)
    walls = lattice(9, 9, 2, DP, offset=(0.0, 0.0, -2 * DP))
    general.half = fast.half = False
    general.build(pos, walls)
    fast.build(pos, walls)
    assert general.pairs > 0 and np.array_equal(general.start, fast.start)
    assert np.array_equal(general.index, fast.index)
    # a first build whose per-thread buffers are far too small scans again and gives the same rows
    small = FluidNeighbourList(*cutoff_args, period=period, box_lo=np.zeros(3), box_hi=period, half=half)
    small.PAIRS_PER_TARGET_GUESS = 1
    small.build(pos, pos)
    general.half = half
    general.build(pos, pos)
    assert small.overflows == 1
    assert np.array_equal(general.start, small.start) and np.array_equal(general.index, small.index)
    small.build(pos, pos)           # sized from the first build: one scan
    assert small.overflows == 1 and np.array_equal(general.index, small.index)


def test_walls_within_reach_are_the_points_inside_the_box_brute_force():
    """The rebuild's active walls: every point inside [lo, hi] on all three axes, boundaries included, none other,
    in ascending order; an infinite bound (a periodic axis) takes every coordinate."""
    rng = np.random.default_rng(7)
    points = np.round(rng.uniform(-1.0, 1.0, (5000, 3)), 2)   # rounded: many points exactly on the bounds
    for lo, hi in (([-0.5, -0.2, 0.0], [0.5, 0.3, 0.1]), ([-np.inf, -0.5, -0.5], [np.inf, 0.5, 0.5]),
                   ([2.0, 2.0, 2.0], [3.0, 3.0, 3.0])):
        lo, hi = np.array(lo), np.array(hi)
        expected = np.flatnonzero(((points >= lo) & (points <= hi)).all(axis=1))
        got = inside_box(points, lo, hi)
        assert np.array_equal(got, expected)
        assert len(expected) > 0 or lo[0] == 2.0
    assert np.sum((points == -0.5).any(axis=1)) > 0


@pytest.mark.parametrize("period_in_dp", [(0, 0, 0), (0, 5.4, 0), (0, 9, 0), (9, 9, 0)])
def test_cells_out_of_reach_hide_no_neighbour(period_in_dp):
    """The scan skips cells whose gap to the target exceeds the cutoff; on a lattice whose points sit on the cell
    faces (cell size = cutoff = 2 dp here) and on jittered points, with targets far outside the grid along open
    axes (clamped into its edge cells), with all axes open, a periodic axis of 2 cells (no skipping) and of 4
    cells, and two periodic axes, every row holds exactly the brute-force set, for the half list and for a full
    list between two sets."""
    period = np.array(period_in_dp, dtype=float) * DP
    cutoff = 2.0 * DP
    sites = lattice(9, 9, 6, DP)
    jittered = sites + np.random.default_rng(5).uniform(-0.45 * DP, 0.45 * DP, sites.shape)
    for k in range(3):
        if period[k] > 0.0:
            jittered[:, k] %= period[k]
            sites = sites[sites[:, k] < period[k] - 1e-12]
    far = np.array([[30 * DP, 4 * DP, 2 * DP], [-20 * DP, -20 * DP, -20 * DP], [4 * DP, 4 * DP, 6.9 * DP]])
    for k in range(3):   # the lists' contract: on a periodic axis, positions within the box (a shift of one period)
        if period[k] > 0.0:
            far[:, k] %= period[k]
    for points in (sites, jittered):
        half = FluidNeighbourList(cutoff, 0.0, period=period, box_lo=np.zeros(3), box_hi=period, half=True)
        half.build(points, points)
        expected = _brute_force_rows(points, points, cutoff, period, True)
        assert half.pairs == sum(len(r) for r in expected) > 5 * len(points)
        assert all(np.array_equal(got, want) for got, want in zip(_rows(half), expected))
        targets = np.concatenate([points[::3] + 0.37 * DP, far])
        targets[:, period > 0.0] %= period[period > 0.0]
        full = FluidNeighbourList(cutoff, 0.0, period=period, box_lo=np.zeros(3), box_hi=period)
        full.build(targets, points)
        expected = _brute_force_rows(targets, points, cutoff, period, False)
        assert full.pairs == sum(len(r) for r in expected)
        assert all(np.array_equal(got, want) for got, want in zip(_rows(full), expected))
        assert len(expected[-1]) > 0 and len(expected[-2]) == 0


def test_a_shared_or_kept_grid_gives_the_same_lists():
    """The wall->fluid list scanning the half list's fluid grid, and a fixed-walls list keeping its grid while the
    walls stay, give the rows a fresh grid gives; a wall that moves (a solid in the boundary) makes a new grid."""
    fluid = lattice(8, 6, 8, DP) + np.random.default_rng(2).normal(0.0, 0.2 * DP, (384, 3))
    walls = lattice(12, 6, 3, DP, offset=(-2 * DP, 0.0, -3 * DP))
    period = np.array([0.0, 6 * DP, 0.0])
    args = (2.0 * H, 0.1 * H)
    kw = dict(period=period, box_lo=np.zeros(3), box_hi=period)
    half = FluidNeighbourList(*args, half=True, **kw)
    half.build(fluid, fluid)
    shared = FluidNeighbourList(*args, **kw)
    shared.build(walls, fluid, grid=half.grid)
    fresh = FluidNeighbourList(*args, **kw)
    fresh.build(walls, fluid)
    assert shared.pairs > 100 and np.array_equal(shared.start, fresh.start)
    assert np.array_equal(shared.index, fresh.index) and shared.grid_builds == 0
    kept = FluidNeighbourList(*args, keep_grid_while_sources_stay=True, **kw)
    boundary = walls.copy()
    for moved in (0.0, 0.0, 0.3 * DP):
        boundary[-1, 2] += moved
        kept.build(fluid, boundary)
        fresh.build(fluid, boundary)
        assert np.array_equal(kept.start, fresh.start) and np.array_equal(kept.index, fresh.index)
    assert kept.grid_builds == 2
    assert np.array_equal(kept.grid.order, source_grid(boundary, kept.cutoff, period, np.zeros(3), period).order)


def test_a_neighbour_on_the_corner_of_a_cell_just_in_reach_is_kept():
    """The skip test's margin: a source on the corner of its cell (a lattice point on the grid's corners; cells of
    exactly the cutoff here) and a target diagonally across, 0.9999 cutoff away, whose gaps to that cell add up to
    0.9998 cutoff^2: the pair is listed."""
    cutoff = 2.0 * DP
    sources = lattice(9, 9, 9, DP, offset=(-0.5 * DP,) * 3)   # 0 .. 8 dp: 4 cells of 2 dp per axis
    delta = 0.9999 * cutoff / np.sqrt(3.0)
    targets = np.full((1, 3), 2.0 * DP - delta)    # in cell (0, 0, 0), across the corner (2, 2, 2) dp
    lst = FluidNeighbourList(cutoff, 0.0)
    lst.build(targets, sources)
    assert np.array_equal(lst.grid.cell_size, np.full(3, cutoff))
    corner = np.flatnonzero(np.all(np.isclose(sources, 2.0 * DP, rtol=0, atol=1e-12), axis=1))
    assert corner[0] in lst.index
    assert np.array_equal(np.sort(lst.index), _brute_force_rows(targets, sources, cutoff, np.zeros(3), False)[0])


def test_the_fluid_to_wall_list_scanning_only_the_fluid_the_wall_to_fluid_list_names_is_the_full_one():
    """The solver's rebuild scans for fluid->wall rows only the fluid particles that the wall->fluid list names
    (named_in): on a jittered periodic block above a floor, the rows and crossing flags are those of a scan over
    all the fluid, and most of the fluid is not scanned."""
    fluid = lattice(8, 6, 12, DP) + np.random.default_rng(4).normal(0.0, 0.2 * DP, (576, 3))
    period = np.array([0.0, 6 * DP, 0.0])
    fluid[:, 1] %= period[1]
    walls = lattice(12, 6, 3, DP, offset=(-2 * DP, 0.0, -3 * DP))
    args = (2.0 * H, 0.1 * H)
    kw = dict(period=period, box_lo=np.zeros(3), box_hi=period)
    wall_fluid = FluidNeighbourList(*args, **kw)
    wall_fluid.build(walls, fluid)
    named = named_in(wall_fluid.index, len(fluid))
    assert np.array_equal(named, np.isin(np.arange(len(fluid)), wall_fluid.index))
    assert 0.05 * len(fluid) < named.sum() < 0.5 * len(fluid)
    scanned, everything = FluidNeighbourList(*args, **kw), FluidNeighbourList(*args, **kw)
    scanned.build(fluid, walls, scanned=named)
    everything.build(fluid, walls)
    assert everything.pairs == wall_fluid.pairs > 100
    assert np.array_equal(scanned.start, everything.start) and np.array_equal(scanned.index, everything.index)
    assert np.array_equal(scanned.crossing, everything.crossing) and everything.crossing.any()
    tiny = FluidNeighbourList(*args, **kw)       # the overflow path's second scan skips the same targets
    tiny.PAIRS_PER_TARGET_GUESS = 0
    tiny._buffers = np.zeros((0, 0), dtype=tiny._buffers.dtype)
    tiny.build(fluid, walls, scanned=named)
    assert tiny.overflows == 1 and np.array_equal(tiny.index, everything.index)


def test_a_half_list_over_shuffled_particles_is_the_brute_force_one():
    """The half list's row skips the sources below its target by their cells' ends or a search (_first_above); with
    the particles numbered at random (no cell wholly above or below a target) the rows are still brute force's."""
    points = lattice(9, 9, 9, DP) + np.random.default_rng(6).normal(0.0, 0.25 * DP, (729, 3))
    points = points[np.random.default_rng(8).permutation(len(points))]
    half = FluidNeighbourList(2.0 * DP, 0.1 * DP, half=True)
    half.build(points, points)
    expected = _brute_force_rows(points, points, 2.1 * DP, np.zeros(3), True)
    assert half.pairs == sum(len(r) for r in expected) > 10 * len(points)
    assert all(np.array_equal(got, want) for got, want in zip(_rows(half), expected))
