"""Particle shifting (fluid/shifting.py, fluid.shifting): the concentration and its gradient against brute-force
sums, the free surface's band left in place, a lattice left as it is, a jittered one evened, and the energy the
shift moves booked in the step's budget."""
from types import SimpleNamespace

import numpy as np
import pytest

from sph_fsi_core.fluid.shifting import ANTI_CLUMP_N, ANTI_CLUMP_R, BAND_CONCENTRATION, BAND_GRADIENT, \
    SURFACE_CONCENTRATION
from sph_fsi_core.fluid.solver import FluidSolver
from sph_fsi_core.numerics.kernels import cubic_spline_f, cubic_spline_w, lattice_density_scale
from sph_fsi_core.state import FluidState

DP = 1.0e-3
RATIO = 1.3
H = RATIO * DP
RHO0 = 1000.0


def lattice(nx, ny, nz, offset=(0.0, 0.0, 0.0)):
    axes = [(np.arange(n) + 0.5) * DP + o for n, o in zip((nx, ny, nz), offset)]
    return np.stack(np.meshgrid(*axes, indexing="ij"), axis=-1).reshape(-1, 3)


def _solver(fluid, walls, period, shifting=0.5, speed="largest", gravity=(0.0, 0.0, 0.0)):
    box_hi = np.where(period > 0.0, period, 1.0)
    s = FluidSolver(fluid, walls, H, period, np.zeros(3), box_hi, 0.1 * H)
    s.configure(rho0=RHO0, nu=0.0, gravity=gravity, tolerance=0.01, tolerance_on="max", coefficient=0.0, kappa=1.0,
                min_iterations=0, max_iterations=200, shifting=shifting, shifting_speed=speed, spacing=DP)
    return s


def _water_on_a_floor(jitter=0.05, seed=1, nx=8, nz=8):
    """An nx x 6 x nz block of water on a floor three layers deep, periodic along y (6 dp), free above and at its
    ends along x; jittered by `jitter` dp; moving at 1 m/s along x with a shear on top (0-0.5 m/s)."""
    water = lattice(nx, 6, nz)
    water += np.random.default_rng(seed).normal(0.0, jitter * DP, water.shape)
    fluid = FluidState.at_rest(water, RHO0, DP, mass_scale=lattice_density_scale(RATIO))
    fluid.vel[:, 0] = 1.0 + 0.5 * fluid.pos[:, 2] / (nz * DP)
    floor = lattice(nx + 4, 6, 3, offset=(-2 * DP, 0.0, -3 * DP))
    walls = SimpleNamespace(pos=floor, mass=np.full(len(floor), RHO0 * DP ** 3 * lattice_density_scale(RATIO)))
    return fluid, walls, np.array([0.0, 6 * DP, 0.0])


def _brute_force(pos, mass, wall_pos, wall_mass, period_y):
    """C_a and grad C_a of fluid/shifting.py's docstring over every pair (minimum image along y)."""
    points = np.vstack([pos, wall_pos])
    volume = np.concatenate([mass, wall_mass]) / RHO0
    d = pos[:, None, :] - points[None, :, :]
    d[:, :, 1] -= period_y * np.round(d[:, :, 1] / period_y)
    r = np.sqrt((d * d).sum(axis=2))
    w = np.vectorize(lambda x: cubic_spline_w(x, H))(r)
    f = np.vectorize(lambda x: cubic_spline_f(x, H) if x > 0.0 else 0.0)(r)
    anti_clump = 1.0 + ANTI_CLUMP_R * (w / cubic_spline_w(DP, H)) ** ANTI_CLUMP_N
    conc = (volume[None, :] * w).sum(axis=1)
    grad = ((volume[None, :] * anti_clump * f)[:, :, None] * d).sum(axis=1)
    near_surface = (r[:, :len(pos)] < 2.0 * H) & (conc[None, :] < SURFACE_CONCENTRATION)
    band = (conc < BAND_CONCENTRATION) | near_surface.any(axis=1) | \
        (H * np.linalg.norm(grad, axis=1) > BAND_GRADIENT)
    return conc, grad, band


@pytest.mark.parametrize("speed", ["largest", "own"])
def test_the_shift_is_the_brute_force_sums_and_leaves_the_free_surface_s_band(speed):
    """The compiled passes' C and grad C (half list, wall list, minimum image along y) are the all-pairs sums to
    1e-12, every particle in the band (C < 0.97, h |grad C| > 0.2, a surface neighbour within 2h) stays to the bit,
    and the others move by -A h U dt grad C with U the largest speed or their own."""
    fluid, walls, period = _water_on_a_floor()
    s = _solver(fluid, walls, period, shifting=0.5, speed=speed)
    before = fluid.pos.copy()
    conc, grad, band = _brute_force(before, fluid.mass, walls.pos, walls.mass, period[1])
    dt = 1.0e-4
    largest = s.shift(dt)
    got_conc, got_grad = s.shift_work[:2]
    assert got_conc == pytest.approx(conc, rel=1e-12, abs=1e-12)
    assert np.abs(got_grad - grad).max() < 1e-12 * np.abs(grad).max()
    # the block's top layers, its ends and its bottom near the floor's edge are in the band, its core is not
    assert 0.2 * len(conc) < band.sum() < 0.9 * len(conc)
    moved = fluid.pos - before
    assert np.array_equal(moved[band], np.zeros((band.sum(), 3)))
    speeds = np.linalg.norm(fluid.vel, axis=1)
    u = speeds.max() if speed == "largest" else speeds[~band]
    expected = -(0.5 * H * dt * u)[..., None] * grad[~band] if speed == "own" else -0.5 * H * dt * u * grad[~band]
    assert np.abs(moved[~band] - expected).max() < 1e-12 * np.abs(expected).max()
    assert largest == pytest.approx(np.linalg.norm(expected, axis=1).max(), rel=1e-12)
    # velocities are kept
    assert np.array_equal(fluid.vel[:, 1:], np.zeros((len(conc), 2)))


def test_a_lattice_is_left_as_it_is():
    """Water on its floor's lattice: every particle outside the free surface's band has a full kernel of water and
    floor on one lattice, and its grad C cancels by symmetry; moving at 1-1.5 m/s, it is shifted by less than
    1e-12 dp."""
    fluid, walls, period = _water_on_a_floor(jitter=0.0, nx=14, nz=12)
    _, _, band = _brute_force(fluid.pos, fluid.mass, walls.pos, walls.mass, period[1])
    assert (~band).sum() >= 60
    s = _solver(fluid, walls, period, shifting=2.0)
    assert s.shift(1.0e-3) < 1e-12 * DP


def test_a_jittered_lattice_is_evened_and_its_velocities_kept():
    """The same water jittered by 0.1 dp: 50 shifts at A = 2 (U dt = 0.2 h each, the advection limit's step) take
    the spread of the concentration of the particles outside the band down five-fold at least (0.030 to 0.003
    measured); the velocities are not touched."""
    fluid, walls, period = _water_on_a_floor(jitter=0.1, nx=14, nz=12)
    inside = ~_brute_force(fluid.pos, fluid.mass, walls.pos, walls.mass, period[1])[2]
    s = _solver(fluid, walls, period, shifting=2.0)
    vel = fluid.vel.copy()
    dt = 0.2 * H / np.linalg.norm(vel, axis=1).max()
    s.shift(dt)
    spread_before = s.shift_work[0][inside].std()
    for _ in range(50):
        if s.fluid_neighbours.is_stale(fluid.pos, fluid.pos):
            s.rebuild()
        s.shift(dt)
    s.shift(0.0)   # the concentration at the end
    spread_after = s.shift_work[0][inside].std()
    assert spread_before > 0.01
    assert spread_after < 0.2 * spread_before
    assert np.array_equal(fluid.vel, vel)


def test_the_energy_budget_books_the_shift_s_potential_energy():
    """The jittered block let fall from rest onto its floor: the steps' budget closes with the shift's column
    (kinetic + potential + what the correction and the shift took stays the start's to 1e-9 of the water's
    potential-energy scale), and the shift took some (about 2e-5 of it)."""
    fluid, walls, period = _water_on_a_floor(jitter=0.1)
    fluid.vel[:] = 0.0
    g = -9.81
    s = _solver(fluid, walls, period, shifting=2.0, gravity=(0.0, 0.0, g))

    def energy():
        kinetic = 0.5 * float((fluid.mass * (fluid.vel ** 2).sum(axis=1)).sum())
        return kinetic - g * float((fluid.mass * fluid.pos[:, 2]).sum())

    start = energy()
    scale = -g * float(fluid.mass.sum()) * 8 * DP
    taken = shifted = 0.0
    for _ in range(20):
        report = s.step(2.0e-4)
        taken += report.correction_loss + report.viscous_loss + report.shifting_loss
        shifted += abs(report.shifting_loss)
    assert energy() + taken == pytest.approx(start, abs=1e-9 * scale)
    assert shifted > 1e-6 * scale
