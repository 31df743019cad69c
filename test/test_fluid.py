"""The density-correction fluid (Okaji 2002; Satake et al. sec. 2.2): its passes and its step, on cases with known
answers. Scene-level checks (hydrostatic pressure, dam-break front) are in test/validation/test_fluid_quick.py."""
import math

import numpy as np
import pytest

from sph_fsi_core.diagnostics import Diverged, WaterLost
from sph_fsi_core.fluid.okaji import viscous_velocity
from sph_fsi_core.numerics.periodic import xz_periodic_marker
from sph_fsi_core.fluid.solver import FluidSolver
from sph_fsi_core.numerics.kernels import cubic_spline_w, lattice_density_scale, lattice_kernel_sum
from sph_fsi_core.scene import load_scene
from sph_fsi_core.schema import SceneError
from sph_fsi_core.simulation import Simulation
from sph_fsi_core.state import FluidState


def lattice(nx, ny, nz, spacing, offset=(0.0, 0.0, 0.0)):
    """Sites (i + 1/2) dp + offset for i < nx, j < ny, k < nz, x slowest."""
    axes = [(np.arange(n) + 0.5) * spacing + o for n, o in zip((nx, ny, nz), offset)]
    return np.stack(np.meshgrid(*axes, indexing="ij"), axis=-1).reshape(-1, 3)


DP = 1.0e-3
RATIO = 1.3
H = RATIO * DP


def _periodic_block(n, scale=1.0, jitter=0.0, seed=0):
    """An n^3 lattice, periodic on all axes (period n dp), mass rho0 dp^3 / lattice sum; positions scaled/jittered."""
    pos = lattice(n, n, n, DP) * scale
    if jitter:
        pos += np.random.default_rng(seed).normal(0.0, jitter * DP, pos.shape)
    fluid = FluidState.at_rest(pos, 1000.0, DP, mass_scale=lattice_density_scale(RATIO))
    period = np.full(3, n * DP * scale)
    return fluid, period


def _solver(fluid, period, **settings):
    s = FluidSolver(fluid, None, H, period, np.zeros(3), period, 0.1 * H)
    cfg = dict(rho0=1000.0, nu=0.0, gravity=(0.0, 0.0, 0.0), tolerance=0.01, tolerance_on="max", coefficient=0.0,
               kappa=1.0, min_iterations=0, max_iterations=200)
    cfg.update(settings)
    s.configure(**cfg)
    return s


def test_lattice_kernel_sum_brute_force():
    # Independent sum over a large lattice: the M4 kernel is not a partition of unity on a cubic lattice.
    r = np.arange(-4, 5)
    g = np.stack(np.meshgrid(r, r, r, indexing="ij"), axis=-1).reshape(-1, 3) * DP
    brute = sum(cubic_spline_w(float(np.sqrt((x * x).sum())), H) for x in g) * DP ** 3
    assert lattice_kernel_sum(RATIO) == pytest.approx(brute, rel=1e-13)
    assert lattice_kernel_sum(RATIO) == pytest.approx(0.99726, abs=1e-5)


def test_summation_density_of_a_full_lattice_is_rho0():
    fluid, period = _periodic_block(8)
    s = _solver(fluid, period)
    emax, emean = s.density()
    assert np.all(np.abs(fluid.rho - 1000.0) < 1e-10 * 1000.0)
    assert emax < 1e-12 and emean < 1e-12
    # The half list holds each pair within 2h + skin once: N x (lattice sites within the cutoff, self excluded) / 2.
    r = np.arange(-4, 5)
    g = np.stack(np.meshgrid(r, r, r, indexing="ij"), axis=-1).reshape(-1, 3) * DP
    d = np.sqrt((g * g).sum(axis=1))
    within = int(((d > 0) & (d < s.fluid_neighbours.cutoff)).sum())
    assert 2 * s.fluid_neighbours.pairs == fluid.count * within


def test_walls_continue_the_lattice():
    """In a tank at rest, every fluid particle whose kernel is not cut by the free surface has rho0 exactly,
    the ones next to the floor and the end walls included (walls: same lattice, same mass)."""
    spec = load_scene("hydrostatic", ["numerics.spacing=0.005"])
    sim = Simulation(spec)
    f = sim.fluid
    below_surface = f.pos[:, 2] < spec["geometry.depth"] - 2.0 * sim.h
    near_walls = (f.pos[:, 2] < 2.0 * sim.h) | (f.pos[:, 0] < 2.0 * sim.h)
    assert (below_surface & near_walls).sum() > 100
    assert np.all(np.abs(f.rho[below_surface] - 1000.0) < 1e-10 * 1000.0)
    # the free surface's kernel is cut: those densities are short of rho0, not compressed
    assert f.rho[~below_surface].min() < 0.8 * 1000.0
    assert sim.fluid_phase.last_error_max < 1e-12


def _free_block():
    """A free 10^3 block (no walls, not periodic) squeezed by 1 % in each direction (3 % compression), jittered."""
    fluid, _ = _periodic_block(10, scale=0.99, jitter=0.02)
    return fluid, np.zeros(3)


def test_correction_converges_on_a_compressed_block():
    """A compressed free block at rest, no gravity: the iterations must drive the max compression below 1 %,
    monotonically; the corrections are pair-symmetric, so the block's momentum (sum of m x correction
    displacement) stays zero."""
    fluid, period = _free_block()
    s = _solver(fluid, period, min_iterations=1, max_iterations=1)
    e0, _ = s.density()
    assert e0 > 0.03
    errors = []
    for _ in range(15):
        report = s.step(1e-3)
        fluid.vel[:] = 0.0
        errors.append(report.error_max)
    # one correction per call: the error after k corrections shrinks every time
    assert all(b < a for a, b in zip(errors, errors[1:]))
    fluid2, period2 = _free_block()
    s2 = _solver(fluid2, period2)
    report = s2.step(1e-3)
    assert not report.capped
    assert report.error_max <= 0.01
    assert 1 <= report.iterations <= 30
    momentum = (fluid2.mass[:, None] * fluid2.correction_displacement).sum(axis=0)
    scale = (fluid2.mass[:, None] * np.abs(fluid2.correction_displacement)).sum()
    assert np.all(np.abs(momentum) < 1e-12 * scale)


def test_iteration_cap_is_counted_and_reported():
    spec = load_scene("dam_break", ["numerics.spacing=0.005715", "fluid.max_iterations=1",
                                    "fluid.density_tolerance=1e-5"])
    sim = Simulation(spec)
    for _ in range(5):
        sim.step()
    assert sim.fluid_phase.capped_steps > 0
    assert sim.sample()["capped_steps"] > 0
    assert any("fluid.max_iterations = 1" in w for w in sim.warnings)


def test_mass_conserved_and_no_wall_crossing_in_a_dam_break():
    spec = load_scene("dam_break", ["numerics.spacing=0.005715", "scene.end_time=0.08"])
    sim = Simulation(spec)
    n0, m0 = sim.fluid.count, sim.fluid.mass.copy()
    while sim.time < 0.08 - 1e-12:
        sim.step()
        assert sim.sample()["outside_walls"] == 0
    assert sim.fluid.count == n0
    assert np.array_equal(sim.fluid.mass, m0)
    dp = spec["numerics.spacing"]
    assert sim.fluid.pos[:, 2].min() > -0.5 * dp and sim.fluid.pos[:, 0].min() > -0.5 * dp
    # the column has moved: the front is past its initial x = a
    assert sim.sample()["front_Z"] > 1.2


def test_phases_build_only_what_the_scene_has():
    fluid_only = Simulation(load_scene("hydrostatic", ["numerics.spacing=0.005"]))
    assert fluid_only.solid is None
    assert fluid_only.fluid is not None and fluid_only.walls is not None
    assert not hasattr(fluid_only, "solid_work") and not hasattr(fluid_only, "solid_neighbours")
    assert "solid_dt" not in fluid_only.sample() and "strain_energy" not in fluid_only.energies()
    solid_only = Simulation(load_scene("cantilever"))
    assert solid_only.fluid is None and solid_only.walls is None and solid_only.fluid_phase is None
    assert "fluid_dt" not in solid_only.sample() and "fluid_kinetic_energy" not in solid_only.energies()


def test_forced_time_step_above_the_limit_is_refused():
    sim = Simulation(load_scene("hydrostatic", ["numerics.spacing=0.005"]))
    limit = sim.fluid_phase.stable_dt()
    with pytest.raises(SceneError, match="fluid.time_step"):
        sim.check({"fluid.time_step": 2.0 * limit})
    with pytest.raises(SceneError, match="fluid.time_step"):
        Simulation(load_scene("hydrostatic", ["numerics.spacing=0.005", f"fluid.time_step={2.0 * limit}"]))
    assert sim.apply({"fluid.time_step": 0.5 * limit}) == []
    sim.step()
    assert sim.fluid_phase.last_dt <= 0.5 * limit * (1 + 1e-12)


def test_watchdog_names_the_fluid_particle():
    sim = Simulation(load_scene("dam_break", ["numerics.spacing=0.005715"]))
    sim.fluid.vel[17, 0] = 1.0e3
    with pytest.raises(Diverged) as info:
        sim.watchdog.check()
    assert info.value.check == "speed" and info.value.phase == "fluid"
    assert info.value.particles[0] == 17 and "fluid particle 17" in str(info.value)


def test_water_that_splashes_out_is_held_still_and_counted():
    """A particle thrown over the tank's wall leaves the domain box: it is held still on the box's face where it
    left (it no longer falls), the run goes on with a warning naming it, the record counts it; where the scene sets
    watchdog.max_fluid_lost, more of the water outside stops the run (WaterLost, not Diverged) naming the check and
    the key."""
    sim = Simulation(load_scene("dam_break", ["numerics.spacing=0.005715", "watchdog.max_fluid_lost=0.01"]))
    n = sim.fluid.count
    sim.fluid.pos[17] = sim.domain_hi + np.array([-0.01, -0.01, 0.001])   # just above the box's lid, at rest
    sim.step()
    assert sim.fluid_phase.lost.sum() == 1 and sim.fluid_phase.lost[17]
    held = sim.fluid.pos[17].copy()
    assert held[2] == sim.domain_hi[2] and np.all(sim.fluid.vel[17] == 0.0)
    assert "water began to leave the domain box" in sim.warnings[-1] and "1 particle(s) over its +z face (e.g. " \
        "fluid particle 17, nearest parts.tank)" in sim.warnings[-1]
    assert sim.fluid_phase.lost_water.summary() == {"particles": 1, "fraction": 1 / n, "first_time_s": sim.time,
                                                    "faces": {"+z": 1}, "nearest_walls": {"tank": 1}}
    for _ in range(3):
        sim.step()
    assert np.array_equal(sim.fluid.pos[17], held) and np.all(sim.fluid.vel[17] == 0.0)
    too_many = int(0.01 * n) + 1
    sim.fluid.pos[-too_many:, 2] = sim.domain_lo[2] - 0.01
    with pytest.raises(WaterLost) as info:
        sim.step()
    assert info.value.check == "left the domain" and info.value.phase == "fluid"
    assert not isinstance(info.value, Diverged) and str(info.value).startswith("water lost: left the domain")
    assert f"{too_many + 1} water particle(s) left" in str(info.value) and "watchdog.max_fluid_lost" in str(info.value)


def test_viscous_term_decays_a_shear_wave_at_nu_k2():
    """v_x = U sin(k z) on a periodic lattice: one step of eq. (9) (Morris form) changes it by -nu k^2 dt v."""
    n = 24
    fluid, period = _periodic_block(n)
    k = 2.0 * math.pi / (n * DP)
    fluid.vel[:, 0] = 0.01 * np.sin(k * fluid.pos[:, 2])
    s = _solver(fluid, period)
    s.density()
    nu, dt = 1.0e-4, 1.0e-4
    out = np.zeros_like(fluid.vel)
    assert s.neighbours().xz_periodic is xz_periodic_marker(period)
    viscous_velocity(fluid.pos, fluid.vel, fluid.mass, fluid.rho, s.neighbours(), s.buffers(), H, nu, dt, out)
    change = out[:, 0] - fluid.vel[:, 0]
    expected = -nu * k * k * dt * fluid.vel[:, 0]
    big = np.abs(expected) > 0.5 * np.abs(expected).max()
    ratio = change[big] / expected[big]
    assert np.all(np.abs(ratio - 1.0) < 0.05), (ratio.min(), ratio.max())
    assert np.abs(out[:, 1:]).max() < 1e-15
    # momentum conserved pair by pair
    assert abs((fluid.mass * change).sum()) < 1e-12 * (fluid.mass * np.abs(change)).sum()


@pytest.mark.parametrize("on, tolerance", [("max", 0.01), ("mean", 0.001)])
def test_each_step_meets_the_criterion_it_is_given(on, tolerance):
    """Both compression measures are reported every step; the one named by fluid.tolerance_on is within the
    tolerance at the end of every step (no step capped), and the time step respects the velocity CFL (the column
    accelerates over these 50 ms, so the speed at an interval's start bounds the steps within it)."""
    spec = load_scene("dam_break", ["numerics.spacing=0.005715", f"fluid.tolerance_on={on}",
                                    f"fluid.density_tolerance={tolerance}"])
    sim = Simulation(spec)
    cfl, h = spec["fluid.cfl"], sim.h
    for _ in range(25):
        vmax = sim.fluid_phase.solver.max_speed()
        sim.step()
        row = sim.sample()
        assert row["capped_steps"] == 0
        governed = row["density_error_max"] if on == "max" else row["density_error_mean"]
        assert governed <= tolerance
        assert row["density_error_mean"] <= row["density_error_max"]
        if vmax > 0.0:
            assert row["fluid_dt"] <= cfl * h / vmax * (1 + 1e-9)
    assert sim.sample()["front_Z"] > 1.05


def test_periodic_or_closed_span_and_refusals():
    """Periodic y (default): no side walls, the slab wraps; closed: side walls at y = 0 and y = span. A slab
    thinner than twice the neighbour cutoff, or walls thinner than 2h, are refused by name."""
    periodic = Simulation(load_scene("hydrostatic", ["numerics.spacing=0.005"]))
    closed = Simulation(load_scene("hydrostatic", ["numerics.spacing=0.005", "geometry.periodic_y=false"]))
    assert periodic.period[1] == pytest.approx(6 * 0.005) and periodic.period[0] == periodic.period[2] == 0.0
    assert closed.period.tolist() == [0.0, 0.0, 0.0]
    assert periodic.walls.pos[:, 1].min() > 0.0 and closed.walls.pos[:, 1].min() < 0.0
    # the closed slab's fluid sees its side walls: same rest density everywhere below the surface
    f = closed.fluid
    below = f.pos[:, 2] < 0.1 - 2.0 * closed.h
    assert np.all(np.abs(f.rho[below] - 1000.0) < 1e-10 * 1000.0)
    for _ in range(10):
        closed.step()
        periodic.step()
    assert closed.sample()["outside_walls"] == 0 and periodic.sample()["outside_walls"] == 0
    assert np.all((periodic.fluid.pos[:, 1] >= 0.0) & (periodic.fluid.pos[:, 1] < periodic.period[1]))
    with pytest.raises(SceneError, match="geometry.span_layers"):
        load_scene("hydrostatic", ["numerics.spacing=0.005", "geometry.span_layers=5"])
    with pytest.raises(SceneError, match="geometry.wall_layers"):
        load_scene("dam_break", ["numerics.spacing=0.005715", "geometry.wall_layers=2"])


def test_the_tank_relaxes_its_water_only_when_asked():
    """geometry.water_damping_ratio (default 0: the tank's water is left alone) relaxes the water's velocities at
    2 zeta omega_b, omega_b of the column's breathing mode (tank.breathing_period: 4 H / sqrt(g H / tolerance)), as
    hydrostatic_plate does: the same column on a rigid floor."""
    spec = load_scene("hydrostatic", ["numerics.spacing=0.005"])
    assert spec.build()[0].fluid_damping_rate == 0.0
    spec = load_scene("hydrostatic", ["numerics.spacing=0.005", "geometry.water_damping_ratio=0.5"])
    period = 4 * 0.1 / math.sqrt(9.81 * 0.1 / 0.01)
    assert spec.build()[0].fluid_damping_rate == pytest.approx(2.0 * 0.5 * 2.0 * math.pi / period)


def test_the_tank_builds_its_water_compressed_with_its_end_walls_in_register():
    """geometry.water_start = compressed: the water's layers at depth d spaced dp (1 - c d / H), c the tolerance;
    the end walls' layers at the water's heights (in register), the floor and the water's mass as on the lattice."""
    flat = load_scene("hydrostatic", ["numerics.spacing=0.005"]).build()[0]
    spec = load_scene("hydrostatic", ["numerics.spacing=0.005", "geometry.water_start=compressed"])
    b = spec.build()[0]
    dp, height, tol = 0.005, spec["geometry.depth"], spec["fluid.density_tolerance"]
    z0 = np.unique(flat.fluid.pos[:, 2])
    z = np.unique(np.round(b.fluid.pos[:, 2], 12))
    assert np.allclose(np.diff(z), dp * (1.0 - tol * (height - 0.5 * (z0[1:] + z0[:-1])) / height), atol=1e-12)
    walls = np.unique(np.round(b.walls.pos[:, 2], 12))
    floor = walls[walls < 0.0]
    assert np.array_equal(floor, np.unique(np.round(flat.walls.pos[:, 2], 12))[:len(floor)])
    assert np.array_equal(walls[len(floor):len(floor) + len(z)], z)
    assert np.array_equal(b.fluid.mass, flat.fluid.mass)



@pytest.mark.parametrize("tolerance, swing_range", [((), (0.2, 1.0)),
                                                   ((("fluid.tolerance_on", "mean"),
                                                     ("fluid.density_tolerance", 0.0003)), (0.0, 0.1))])
def test_the_pressure_at_rest_comes_in_pulses_unless_the_correction_holds_the_mean(tolerance, swing_range):
    """Water at rest stepped at 0.5 ms (a coupled run's step): gravity's g dt^2 per step is far inside the paper's
    tolerance (the largest compression within 1 %), so most steps take no correction and read no pressure, and the
    next ones catch up: the end wall's probe swings from step to step by a large fraction of rho g H (measured 59 %
    over 0.7-1 s at this H/dp 20). With the tolerance on the mean compression at 0.03 % every step corrects and the
    swing falls to 7 % (the pressure is known to about c^2 rho0 times the tolerance: docs/validation/studies/
    pressure_tolerance), its mean on rho g (H - z) as before."""
    from sph_fsi_core.run import run_scene
    spec = load_scene("hydrostatic", [("numerics.spacing", 0.005), ("fluid.time_step", 0.0005),
                                      ("output.timeseries_interval", 0.0005), ("scene.end_time", 0.4),
                                      ("output.snapshot_interval", 0.0), ("geometry.pressure_probes", True),
                                      *tolerance])
    judges = run_scene(spec, None, progress=False)["judges"]
    lo, hi = swing_range
    assert lo <= judges["wall_swing"]["error"] <= hi
    assert lo <= judges["bulk_swing"]["error"] <= hi
    assert abs(judges["wall_mean"]["error"]) < 0.03 and abs(judges["bulk_mean"]["error"]) < 0.03



def test_the_last_iteration_taken_in_part_ends_a_step_at_the_tolerance():
    """fluid.partial_iteration: the iteration that crosses the tolerance is taken in the part that brings the largest
    compression to it (the error taken as linear in the fraction), so every step that corrects ends at the tolerance
    (here within 1 % of it, 0.4 % measured, anew at the step's end positions) and reports that error; the paper's whole
    iterations end anywhere below (0.64-0.97 % on this tank at rest against its 1 %)."""
    def steps(partial):
        spec = load_scene("hydrostatic", [("numerics.spacing", 0.005), ("fluid.time_step", 0.0005),
                                          ("fluid.partial_iteration", partial), ("output.snapshot_interval", 0.0)])
        solver = Simulation(spec).fluid_phase.solver
        ends = []
        for _ in range(200):
            report = solver.step(0.0005)
            if report.iterations:
                ends.append((report.error_max, solver.density()[0]))
        return np.array(ends), spec["fluid.density_tolerance"]
    ends, tol = steps(True)
    assert len(ends) > 150                                          # at rest under gravity, nearly every step corrects
    assert np.all(np.abs(ends[:, 1] - tol) < 1e-2 * tol)
    assert np.all(np.abs(ends[:, 0] - ends[:, 1]) < 1e-2 * tol)     # the reported error is the one reached
    whole, _ = steps(False)
    assert np.all(whole[:, 1] <= tol) and np.ptp(whole[:, 1]) > 0.2 * tol


def test_with_the_last_iteration_taken_in_part_the_water_at_rest_reads_a_steady_pressure():
    """The default suite's rest_pressure rung at H/dp 20 (the tank stepped at 0.5 ms, one sample per fluid step) with
    fluid.partial_iteration: the end wall's and the bulk's probes swing by under 2 % of rho g H over 0.7-1 s (the
    issue's goal; the paper's correction: 59 %), their means within 1 % of rho g (H - z), at the paper's tolerance
    and about one iteration a step (docs/validation/studies/partial_iteration)."""
    from sph_fsi_core.run import run_scene
    spec = load_scene("hydrostatic", [("numerics.spacing", 0.005), ("fluid.time_step", 0.0005),
                                      ("output.timeseries_interval", 0.0005), ("scene.end_time", 1.0),
                                      ("output.snapshot_interval", 0.0), ("geometry.pressure_probes", True),
                                      ("fluid.partial_iteration", True)])
    summary = run_scene(spec, None, progress=False)
    judges = summary["judges"]
    assert judges["wall_swing"]["error"] < 0.02 and judges["bulk_swing"]["error"] < 0.02
    assert abs(judges["wall_mean"]["error"]) < 0.01 and abs(judges["bulk_mean"]["error"]) < 0.01
    assert summary["fluid_iterations_per_step"] < 1.5


def test_the_energy_budget_of_a_decaying_shear_wave_is_the_viscous_terms():
    """A shear wave u_x = U sin(k z) in a periodic block decays as exp(-nu k^2 t) (its kinetic energy as
    exp(-2 nu k^2 t): the viscous diffusion equation's exact answer). The step's energy budget (StepReport) gives
    what it loses to the viscous term: its sum over the run equals the kinetic energy lost to 1e-9 of the start's,
    the correction takes almost none (the flow does not compress the block), and the decay's viscosity is nu's
    within 4 % at 16 particles per wavelength (2.5 % short measured: Morris's form)."""
    n, nu, U, dt, steps = 16, 1.0e-3, 0.01, 1.0e-4, 50
    fluid, period = _periodic_block(n)
    k = 2.0 * math.pi / period[2]
    fluid.vel[:, 0] = U * np.sin(k * fluid.pos[:, 2])
    s = _solver(fluid, period, nu=nu)
    start = 0.5 * float((fluid.mass * (fluid.vel ** 2).sum(axis=1)).sum())
    viscous = correction = 0.0
    for _ in range(steps):
        report = s.step(dt)
        viscous += report.viscous_loss
        correction += report.correction_loss
    end = 0.5 * float((fluid.mass * (fluid.vel ** 2).sum(axis=1)).sum())
    assert viscous + correction == pytest.approx(start - end, abs=1e-9 * start)
    assert abs(correction) < 1e-3 * start
    effective_nu = -math.log(end / start) / (2.0 * k * k * steps * dt)
    assert effective_nu == pytest.approx(nu, rel=0.04)
