"""Tests of the cell-linked-list neighbour search (sph_fsi_core.numerics.neighbours) against brute force."""
import numpy as np
import pytest

from sph_fsi_core.numerics.neighbours import (MAX_CELLS_PER_AXIS, MIN_CELL_BUDGET, NeighbourList, cell_grid, chunk_first_target,
                                     inverse_periods, max_displacement, minimum_image)

BOX = np.array([0.03, 0.02, 0.025])


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
    period = np.array([1.0, 0.036, 0.0])
    inv = inverse_periods(period)
    assert inv[0] == 1.0 and inv[1] == pytest.approx(1.0 / 0.036, rel=1e-15) and inv[2] == 0.0
    assert minimum_image(0.7, 1.0, inv[0]) == pytest.approx(-0.3, abs=1e-15)
    assert minimum_image(-0.7, 1.0, inv[0]) == pytest.approx(0.3, abs=1e-15)
    assert minimum_image(0.2, 1.0, inv[0]) == pytest.approx(0.2, abs=1e-15)
    assert minimum_image(2.2, 1.0, inv[0]) == pytest.approx(0.2, abs=1e-14)
    assert minimum_image(-0.035, 0.036, inv[1]) == pytest.approx(0.001, abs=1e-15)
    assert minimum_image(0.7, 0.0, inv[2]) == 0.7


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
