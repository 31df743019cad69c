"""Tests of the cell-linked-list neighbour search (sph_fsi_core.numerics.neighbours: the one list builder of the
solid, the fluid, the coupling and the scenes' checks) against brute force."""
import numpy as np
import pytest

from sph_fsi_core.numerics.neighbours import (MAX_CELLS_PER_AXIS, MIN_CELL_BUDGET, NeighbourList, cell_grid,
                                              chunk_first_target, inside_box, max_displacement, named_in,
                                              source_grid)
from sph_fsi_core.numerics.periodic import minimum_image

BOX = np.array([0.03, 0.02, 0.025])


def lattice(nx, ny, nz, spacing, offset=(0.0, 0.0, 0.0)):
    """Sites (i + 1/2) dp + offset for i < nx, j < ny, k < nz, x slowest."""
    axes = [(np.arange(n) + 0.5) * spacing + o for n, o in zip((nx, ny, nz), offset)]
    return np.stack(np.meshgrid(*axes, indexing="ij"), axis=-1).reshape(-1, 3)


def _random(n, seed, lo=None, hi=None):
    rng = np.random.default_rng(seed)
    lo = np.zeros(3) if lo is None else lo
    hi = BOX if hi is None else hi
    return np.ascontiguousarray(lo + rng.random((n, 3)) * (hi - lo))


def _pairs(nl):
    """The list as a set of (target, source) pairs."""
    counts = np.diff(nl.start)
    a = np.repeat(np.arange(len(counts)), counts)
    return set(zip(a.tolist(), nl.index.tolist()))


def _brute(targets, sources, cutoff, period=np.zeros(3)):
    d = targets[:, None, :] - sources[None, :, :]
    for k in range(3):
        if period[k] > 0:
            d[..., k] -= period[k] * np.floor(d[..., k] / period[k] + 0.5)
    r2 = np.einsum("abk,abk->ab", d, d)
    a, b = np.nonzero(r2 < cutoff * cutoff)
    return set(zip(a.tolist(), b.tolist()))


def _check_rows(nl, n_targets):
    assert nl.start.shape == (n_targets + 1,)
    assert nl.start[0] == 0
    assert np.all(np.diff(nl.start) >= 0)
    assert nl.pairs == len(nl.index)
    # no duplicates within a row
    for a in range(n_targets):
        row = nl.index[nl.start[a]:nl.start[a + 1]]
        assert len(np.unique(row)) == len(row)


@pytest.mark.parametrize("radius, skin", [(2.6e-3, 0.13e-3), (1.0e-3, 0.0), (4.0e-3, 1.0e-3), (0.5e-3, 0.05e-3)])
def test_same_set_matches_brute_force(radius, skin):
    pos = _random(2000, 1)
    nl = NeighbourList(radius, skin)
    nl.build(pos, pos)
    _check_rows(nl, len(pos))
    expected = _brute(pos, pos, radius + skin)
    got = _pairs(nl)
    assert len(got) == nl.pairs            # no duplicate pairs
    assert got == expected
    # self pairs are included, and the list is symmetric
    assert all((a, a) in got for a in range(len(pos)))
    assert all((b, a) in got for a, b in got)
    assert nl.pairs > len(pos) + 100       # the case is not trivially self pairs only


@pytest.mark.parametrize("radius, skin", [(2.6e-3, 0.13e-3), (5.0e-3, 0.5e-3)])
def test_half_list_is_upper_triangle(radius, skin):
    pos = _random(2000, 2)
    nl = NeighbourList(radius, skin, half=True)
    nl.build(pos, pos)
    _check_rows(nl, len(pos))
    expected = {(a, b) for a, b in _brute(pos, pos, radius + skin) if b > a}
    assert _pairs(nl) == expected
    with pytest.raises(ValueError, match="half"):
        nl.build(pos, pos.copy())


@pytest.mark.parametrize("radius, skin", [(2.6e-3, 0.13e-3), (1.5e-3, 0.3e-3)])
def test_different_targets_and_sources(radius, skin):
    targets = _random(500, 3)
    sources = _random(1500, 4)
    nl = NeighbourList(radius, skin)
    nl.build(targets, sources)
    _check_rows(nl, len(targets))
    expected = _brute(targets, sources, radius + skin)
    assert len(expected) > 500
    assert _pairs(nl) == expected


def test_targets_outside_the_source_box():
    """Targets beyond the sources' bounding box are clamped into the edge cells and still find their pairs."""
    sources = _random(1500, 5)
    rng = np.random.default_rng(6)
    targets = np.ascontiguousarray(np.concatenate([
        _random(200, 7, lo=-0.004 * np.ones(3), hi=BOX + 0.004),
        np.array([[-1e3, 0.01, 0.01], [1e3, 1e3, 1e3]]),
        rng.random((10, 3)) * BOX + np.array([BOX[0] + 0.001, 0.0, 0.0])]))
    nl = NeighbourList(2.6e-3, 0.13e-3)
    nl.build(targets, sources)
    assert _pairs(nl) == _brute(targets, sources, 2.73e-3)
    assert nl.start[201] - nl.start[200] == 0     # the far targets have no neighbours


def test_far_particle_clamps_grid():
    """Particles far outside the others' box (1e3 m along x, -1 m along z) stretch the source box; the cell
    counts are capped (per axis and in total) and the pairs stay exact."""
    pos = _random(2000, 8)
    pos = np.ascontiguousarray(np.concatenate([pos, [[1e3, 0.01, 0.01], [1e3 + 1e-3, 0.01, 0.01],
                                                     [0.01, 0.01, -1.0]]]))
    radius, skin = 2.6e-3, 0.13e-3
    nl = NeighbourList(radius, skin)
    nl.build(pos, pos)
    expected = _brute(pos, pos, radius + skin)
    got = _pairs(nl)
    assert got == expected
    assert (2000, 2001) in got and (2001, 2000) in got   # the two far particles see each other
    assert nl.start[2003] - nl.start[2002] == 1           # the third only itself
    _, cell_size, ncell = cell_grid(pos, radius + skin, np.zeros(3), np.zeros(3), np.zeros(3))
    assert ncell.max() <= MAX_CELLS_PER_AXIS
    assert int(np.prod(ncell)) <= max(MIN_CELL_BUDGET, 8 * len(pos))
    assert cell_size[0] == pytest.approx((1e3 + 1e-3 - pos[:, 0].min()) / ncell[0], rel=1e-12)


def test_grid_size_bounded_when_a_particle_flies_off():
    """A diverging particle far away in all three axes must not blow up the cell grid.

    The cap is per axis (MAX_CELLS_PER_AXIS = 1024), so one particle at (1e3, 1e3, 1e3) m among 2000 gives
    1024^3 = 1.07e9 cells: `bin_sources` then allocates and scans an 8.6 GB int64 array (building that list took
    46 s and 8.6 GB here). Only the grid is computed below (cheap); the bound asked for is generous: at most
    32 cells per particle or 2^20 cells, whichever is larger.
    """
    pos = _random(2000, 15)
    pos = np.ascontiguousarray(np.concatenate([pos, [[1e3, 1e3, 1e3]]]))
    _, cell_size, ncell = cell_grid(pos, 2.73e-3, np.zeros(3), np.zeros(3), np.zeros(3))
    total = int(np.prod(ncell))
    assert total <= max(32 * len(pos), 2 ** 20), f"{total:.3g} cells ({ncell.tolist()}) for {len(pos)} particles"


@pytest.mark.parametrize("radius, skin, ly", [(2.6e-3, 0.13e-3, 0.02), (2.6e-3, 0.13e-3, 2 * 2.73e-3),
                                              (2.6e-3, 0.13e-3, 2.5 * 2.73e-3), (1.0e-3, 0.2e-3, 0.011)])
def test_periodic_y_matches_minimum_image(radius, skin, ly):
    lo = np.array([0.0, -0.3 * ly, 0.0])
    hi = np.array([BOX[0], 0.7 * ly, BOX[2]])
    pos = _random(2000, 9, lo=lo, hi=hi)
    period = np.array([0.0, ly, 0.0])
    nl = NeighbourList(radius, skin, period=period, box_lo=lo, box_hi=hi)
    nl.build(pos, pos)
    _check_rows(nl, len(pos))
    expected = _brute(pos, pos, radius + skin, period)
    got = _pairs(nl)
    assert got == expected
    # the periodic images really contribute pairs that the open search would not find
    assert len(expected - _brute(pos, pos, radius + skin)) > 0


@pytest.mark.parametrize("ly", [0.012, 4.004 * 2.73e-3])
def test_periodic_y_with_particles_slightly_outside_box(ly):
    """Nothing in the stepper wraps positions into the periodic box, so particles may sit a little outside it
    (by up to the skin between two rebuilds, or more): the list must still be the minimum-image list.

    ly = 4.004 cutoffs gives cells only 0.1 % wider than the cutoff, so a particle half a skin outside the box,
    clamped into the edge cell, has minimum-image neighbours two cells away."""
    lo = np.array([0.0, 0.0, 0.0])
    hi = np.array([BOX[0], ly, BOX[2]])
    radius, skin = 2.6e-3, 0.13e-3
    pos = _random(2000, 10, lo=lo - np.array([0, 0.5 * skin, 0]), hi=hi + np.array([0, 0.5 * skin, 0]))
    period = np.array([0.0, ly, 0.0])
    nl = NeighbourList(radius, skin, period=period, box_lo=lo, box_hi=hi)
    nl.build(pos, pos)
    assert _pairs(nl) == _brute(pos, pos, radius + skin, period)


@pytest.mark.parametrize("outside", [+1, -1])
def test_periodic_pair_across_the_seam_from_outside_the_box(outside):
    """A deterministic case of the one above: particle A a little outside the periodic box in y (above box_hi,
    or below box_lo), particle B 2.70 mm from A's image (cutoff 2.73 mm), two cells from A's clamped cell."""
    cutoff = 2.73e-3
    ly = 4.004 * cutoff                       # 4 cells of 1.001 cutoff
    lo = np.zeros(3)
    hi = np.array([0.02, ly, 0.02])
    delta = 0.05e-3                           # A outside the box by less than half the skin (0.065 mm)
    if outside > 0:
        a = [0.01, ly + delta, 0.01]          # image at y = delta
        b = [0.01, delta + 2.70e-3, 0.01]     # in cell 1; A is clamped into cell 3
    else:
        a = [0.01, -delta, 0.01]              # image at y = ly - delta
        b = [0.01, ly - delta - 2.70e-3, 0.01]  # in cell 2; A is clamped into cell 0
    pos = np.array([a, b])
    nl = NeighbourList(2.6e-3, 0.13e-3, period=np.array([0.0, ly, 0.0]), box_lo=lo, box_hi=hi)
    nl.build(pos, pos)
    expected = _brute(pos, pos, cutoff, np.array([0.0, ly, 0.0]))
    assert (0, 1) in expected
    assert _pairs(nl) == expected


def test_periodic_x_and_z_together():
    lo = np.array([0.0, 0.0, 0.0])
    hi = np.array([0.012, 0.02, 0.009])
    pos = _random(1500, 11, lo=lo, hi=hi)
    period = np.array([0.012, 0.0, 0.009])
    nl = NeighbourList(2.0e-3, 0.2e-3, period=period, box_lo=lo, box_hi=hi)
    nl.build(pos, pos)
    assert _pairs(nl) == _brute(pos, pos, 2.2e-3, period)


@pytest.mark.parametrize("axis", [0, 1, 2])
def test_period_below_twice_cutoff_is_refused(axis):
    period = np.zeros(3)
    period[axis] = 2 * 2.73e-3 * 0.99
    with pytest.raises(ValueError, match="xyz"[axis]):
        NeighbourList(2.6e-3, 0.13e-3, period=period, box_lo=np.zeros(3), box_hi=period)
    period[axis] = 2 * 2.73e-3 * 1.0001
    NeighbourList(2.6e-3, 0.13e-3, period=period, box_lo=np.zeros(3), box_hi=period)   # allowed


def test_minimum_image():
    """One shift by the period, exact on separations up to 1.5 periods as stored (what the lists' builds allow),
    antisymmetric to the bit, the plain separation up to half a period and on an open axis."""
    assert minimum_image(0.7, 1.0, 0.5) == pytest.approx(-0.3, abs=1e-15)
    assert minimum_image(-0.7, 1.0, 0.5) == pytest.approx(0.3, abs=1e-15)
    assert minimum_image(0.2, 1.0, 0.5) == 0.2
    assert minimum_image(1.45, 1.0, 0.5) == pytest.approx(0.45, abs=1e-15)
    assert minimum_image(-0.035, 0.036, 0.018) == pytest.approx(0.001, abs=1e-15)
    assert minimum_image(0.7, 0.0, 0.0) == 0.7
    d = np.random.default_rng(16).uniform(-1.5, 1.5, 1000) * 0.036
    images = np.array([minimum_image(x, 0.036, 0.018) for x in d])
    assert np.array_equal(images, -np.array([minimum_image(-x, 0.036, 0.018) for x in d]))
    assert np.allclose(images, d - 0.036 * np.round(d / 0.036), rtol=0, atol=1e-17)
    within = np.abs(d) <= 0.018
    assert np.array_equal(images[within], d[within])


@pytest.mark.parametrize("half", [True, False])
def test_particles_far_outside_the_periodic_box_are_refused(half):
    """The one-shift image needs every pair within 1.5 periods as stored until the next build: a build is refused
    when a particle (target or source) lies more than a quarter period less half a skin outside the periodic box,
    and within that the list is brute force's."""
    ly, skin = 0.012, 0.13e-3
    period = np.array([0.0, ly, 0.0])
    pos = _random(500, 17, hi=np.array([BOX[0], ly, BOX[2]]))
    nl = NeighbourList(2.6e-3, skin, period=period, box_lo=np.zeros(3), box_hi=np.array([1.0, ly, 1.0]), half=half)
    margin = 0.25 * ly - 0.5 * skin
    for y in (ly + 0.99 * margin, -0.99 * margin):
        pos[0, 1] = y
        nl.build(pos, pos)
        expected = _brute(pos, pos, nl.cutoff, period)
        assert _pairs(nl) == ({(a, b) for a, b in expected if b > a} if half else expected)
        assert any(0 in pair for pair in _pairs(nl))
    for y in (ly + 1.01 * margin, -1.01 * margin):
        pos[0, 1] = y
        with pytest.raises(ValueError, match="outside the periodic box"):
            nl.build(pos, pos)
    if not half:
        far = pos[:1].copy()
        pos[0, 1] = 0.5 * ly
        with pytest.raises(ValueError, match="outside the periodic box"):
            nl.build(far, pos)
        nl.build(pos, pos)


def test_is_stale_and_update():
    pos = _random(800, 12)
    radius, skin = 2.6e-3, 0.2e-3
    nl = NeighbourList(radius, skin)
    assert nl.is_stale(pos, pos)               # never built
    nl.build(pos, pos)
    assert nl.builds == 1
    assert not nl.is_stale(pos, pos)
    assert nl.update(pos, pos) is False
    assert nl.builds == 1

    moved = pos.copy()
    moved[17, 1] += 0.49 * skin
    assert not nl.is_stale(moved, moved)
    assert max_displacement(moved, pos) == pytest.approx(0.49 * skin, rel=1e-12)
    moved[17, 1] += 0.02 * skin               # now 0.51 skin from where it was built
    assert nl.is_stale(moved, moved)
    assert nl.update(moved, moved) is True
    assert nl.builds == 2
    assert not nl.is_stale(moved, moved)
    assert _pairs(nl) == _brute(moved, moved, radius + skin)

    # a list of different targets and sources watches the sources too
    targets = _random(300, 13)
    nl2 = NeighbourList(radius, skin)
    nl2.build(targets, pos)
    src = pos.copy()
    src[5] += np.array([0.3, 0.3, 0.3]) * skin   # |d| = 0.52 skin
    assert nl2.is_stale(targets, src)
    assert not nl2.is_stale(targets, pos)
    # a change of the particle count is stale
    assert nl.is_stale(moved[:-1], moved[:-1])


def test_build_does_not_keep_a_view_of_the_positions():
    pos = _random(500, 14)
    nl = NeighbourList(2.6e-3, 0.2e-3)
    nl.build(pos, pos)
    pos[0, 0] += 1.0                          # moved in place, as the stepper does
    assert nl.is_stale(pos, pos)


def _plate(layers, ny, nz, dp):
    """A lattice stored layer by layer along x (x outermost), as the scene builders store the paper's gate."""
    x, y, z = np.meshgrid(np.arange(layers), np.arange(ny), np.arange(nz), indexing="ij")
    return np.ascontiguousarray(np.stack([x.ravel(), y.ravel(), z.ravel()], axis=1) * dp + 0.5 * dp)


@pytest.mark.parametrize("chunks", [2, 3, 4, 8])
def test_chunks_of_a_thin_plate_carry_equal_work(chunks):
    dp = 1e-3
    pos = _plate(4, 12, 20, dp)
    nl = NeighbourList(1.3 * dp * 2, 0.05 * dp, half=True)
    nl.build(pos, pos)
    n = len(pos)
    bounds = [chunk_first_target(nl.start, c, chunks) for c in range(chunks + 1)]
    assert bounds[0] == 0 and bounds[-1] == n
    assert all(lo <= hi for lo, hi in zip(bounds, bounds[1:]))
    work = nl.start + np.arange(n + 1)          # pairs + one per particle, as the cut counts it
    per_chunk = np.diff(work[bounds])
    heaviest_row = int(np.diff(work).max())
    ideal = work[-1] / chunks                     # each cut lands within one row of its target
    assert np.all(np.abs(per_chunk - ideal) <= heaviest_row)
    # an equal count of particles would not do: the first layers own the pairs to the next ones
    by_count = np.diff(work[[c * n // chunks for c in range(chunks + 1)]])
    assert by_count.max() > 1.3 * per_chunk.max()


@pytest.mark.parametrize("n, chunks", [(0, 2), (5, 8), (100, 3)])
def test_chunks_without_pairs_split_the_particles(n, chunks):
    start = np.zeros(n + 1, dtype=np.int64)
    bounds = [chunk_first_target(start, c, chunks) for c in range(chunks + 1)]
    assert bounds[0] == 0 and bounds[-1] == n
    sizes = np.diff(bounds)
    assert sizes.min() >= 0 and sizes.max() - sizes.min() <= 1


# ---- the build's own paths: per-thread buffers, shared and kept grids, scanned targets, skipped cells ----------

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


def _same_rows(lst, expected):
    return lst.pairs == sum(len(r) for r in expected) and all(
        np.array_equal(got, want) for got, want in zip(_rows(lst), expected))


@pytest.mark.parametrize("half", [True, False])
def test_overflowing_buffers_give_the_same_rows_in_the_same_order(half):
    """On a jittered periodic block with particles a little outside the box, the rows are brute force's; a first
    build whose per-thread buffers are far too small scans again and gives the same rows in the same order, and
    the next build, sized from it, scans once."""
    pos = lattice(9, 9, 9, DP) + np.random.default_rng(3).normal(0.0, 0.3 * DP, (729, 3))
    period = np.array([0.0, 9 * DP, 0.0])
    pos[:5, 1] -= 0.2 * DP        # a little below the periodic box's start
    cutoff_args = (2.0 * H, 0.1 * H)
    kw = dict(period=period, box_lo=np.zeros(3), box_hi=period, half=half)
    roomy = NeighbourList(*cutoff_args, **kw)
    roomy.build(pos, pos)
    first = roomy.overflows
    roomy.build(pos, pos)           # sized from the build before: one scan into the buffers
    assert roomy.overflows == first and roomy.pairs > 10 * len(pos)
    assert _same_rows(roomy, _brute_force_rows(pos, pos, roomy.cutoff, period, half))
    small = NeighbourList(*cutoff_args, **kw)
    small.PAIRS_PER_TARGET_GUESS = 1
    small.build(pos, pos)
    assert small.overflows == 1
    assert np.array_equal(roomy.start, small.start) and np.array_equal(roomy.index, small.index)
    assert np.array_equal(roomy.crossing, small.crossing)
    small.build(pos, pos)           # sized from the first build: one scan
    assert small.overflows == 1 and np.array_equal(roomy.index, small.index)
    walls = lattice(9, 9, 2, DP, offset=(0.0, 0.0, -2 * DP))
    full = NeighbourList(*cutoff_args, period=period, box_lo=np.zeros(3), box_hi=period)
    full.build(pos, walls)
    assert full.pairs > 0 and _same_rows(full, _brute_force_rows(pos, walls, full.cutoff, period, False))


def test_walls_within_reach_are_the_points_inside_the_box_brute_force():
    """The fluid rebuild's active walls: every point inside [lo, hi] on all three axes, boundaries included, none
    other, in ascending order; an infinite bound (a periodic axis) takes every coordinate."""
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
    for k in range(3):   # the lists' contract: on a periodic axis, positions within 1.5 periods of each other
        if period[k] > 0.0:
            far[:, k] %= period[k]
    for points in (sites, jittered):
        half = NeighbourList(cutoff, 0.0, period=period, box_lo=np.zeros(3), box_hi=period, half=True)
        half.build(points, points)
        expected = _brute_force_rows(points, points, cutoff, period, True)
        assert half.pairs > 5 * len(points) and _same_rows(half, expected)
        targets = np.concatenate([points[::3] + 0.37 * DP, far])
        targets[:, period > 0.0] %= period[period > 0.0]
        full = NeighbourList(cutoff, 0.0, period=period, box_lo=np.zeros(3), box_hi=period)
        full.build(targets, points)
        expected = _brute_force_rows(targets, points, cutoff, period, False)
        assert _same_rows(full, expected)
        assert len(expected[-1]) > 0 and len(expected[-2]) == 0


def test_a_shared_or_kept_grid_gives_the_same_lists():
    """The wall->fluid list scanning the half list's fluid grid, and a fixed-walls list keeping its grid while the
    walls stay, give the rows a fresh grid gives; a wall that moves (a solid in the boundary) makes a new grid."""
    fluid = lattice(8, 6, 8, DP) + np.random.default_rng(2).normal(0.0, 0.2 * DP, (384, 3))
    walls = lattice(12, 6, 3, DP, offset=(-2 * DP, 0.0, -3 * DP))
    period = np.array([0.0, 6 * DP, 0.0])
    args = (2.0 * H, 0.1 * H)
    kw = dict(period=period, box_lo=np.zeros(3), box_hi=period)
    half = NeighbourList(*args, half=True, **kw)
    half.build(fluid, fluid)
    shared = NeighbourList(*args, **kw)
    shared.build(walls, fluid, grid=half.grid)
    fresh = NeighbourList(*args, **kw)
    fresh.build(walls, fluid)
    assert shared.pairs > 100 and np.array_equal(shared.start, fresh.start)
    assert np.array_equal(shared.index, fresh.index) and shared.grid_builds == 0
    kept = NeighbourList(*args, keep_grid_while_sources_stay=True, **kw)
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
    lst = NeighbourList(cutoff, 0.0)
    lst.build(targets, sources)
    assert np.array_equal(lst.grid.cell_size, np.full(3, cutoff))
    corner = np.flatnonzero(np.all(np.isclose(sources, 2.0 * DP, rtol=0, atol=1e-12), axis=1))
    assert corner[0] in lst.index
    assert np.array_equal(np.sort(lst.index), _brute_force_rows(targets, sources, cutoff, np.zeros(3), False)[0])


def test_the_fluid_to_wall_list_scanning_only_the_fluid_the_wall_to_fluid_list_names_is_the_full_one():
    """The fluid's rebuild scans for fluid->wall rows only the fluid particles that the wall->fluid list names
    (named_in): on a jittered periodic block above a floor, the rows and crossing flags are those of a scan over
    all the fluid, and most of the fluid is not scanned."""
    fluid = lattice(8, 6, 12, DP) + np.random.default_rng(4).normal(0.0, 0.2 * DP, (576, 3))
    period = np.array([0.0, 6 * DP, 0.0])
    fluid[:, 1] %= period[1]
    walls = lattice(12, 6, 3, DP, offset=(-2 * DP, 0.0, -3 * DP))
    args = (2.0 * H, 0.1 * H)
    kw = dict(period=period, box_lo=np.zeros(3), box_hi=period)
    wall_fluid = NeighbourList(*args, **kw)
    wall_fluid.build(walls, fluid)
    named = named_in(wall_fluid.index, len(fluid))
    assert np.array_equal(named, np.isin(np.arange(len(fluid)), wall_fluid.index))
    assert 0.05 * len(fluid) < named.sum() < 0.5 * len(fluid)
    scanned, everything = NeighbourList(*args, **kw), NeighbourList(*args, **kw)
    scanned.build(fluid, walls, scanned=named)
    everything.build(fluid, walls)
    assert everything.pairs == wall_fluid.pairs > 100
    assert np.array_equal(scanned.start, everything.start) and np.array_equal(scanned.index, everything.index)
    assert np.array_equal(scanned.crossing, everything.crossing) and everything.crossing.any()
    tiny = NeighbourList(*args, **kw)       # the overflow path's second scan skips the same targets
    tiny.PAIRS_PER_TARGET_GUESS = 0
    tiny._buffers = np.zeros((0, 0), dtype=tiny._buffers.dtype)
    tiny.build(fluid, walls, scanned=named)
    assert tiny.overflows == 1 and np.array_equal(tiny.index, everything.index)


def test_a_half_list_over_shuffled_particles_is_the_brute_force_one():
    """The half list's row skips the sources below its target by their cells' ends or a search (_first_above); with
    the particles numbered at random (no cell wholly above or below a target) the rows are still brute force's."""
    points = lattice(9, 9, 9, DP) + np.random.default_rng(6).normal(0.0, 0.25 * DP, (729, 3))
    points = points[np.random.default_rng(8).permutation(len(points))]
    half = NeighbourList(2.0 * DP, 0.1 * DP, half=True)
    half.build(points, points)
    expected = _brute_force_rows(points, points, 2.1 * DP, np.zeros(3), True)
    assert half.pairs > 10 * len(points) and _same_rows(half, expected)
