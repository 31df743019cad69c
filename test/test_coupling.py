"""Fluid-structure coupling (coupling/): phases, surface normals, the seed push's direction, pressure pair forces
that sum to zero, the sub-step ratio, and the solid as a moving wall of the fluid."""
import math

import numpy as np
import pytest

from sph_fsi_core.coupling.solver import Coupling
from sph_fsi_core.scene import load_scene
from sph_fsi_core.simulation import Simulation

# at 2 mm the gate is 2 particles thick: the paper's scheme (the default's quadratic fit needs 3)
COARSE = [("numerics.spacing", 0.002), ("geometry.gate_clamp_height", 0.004), ("geometry.span", 0.0),
          ("solid.scheme", "gray2001")]


@pytest.fixture(scope="module")
def gate_sim():
    return Simulation(load_scene("elastic_gate", COARSE))


def test_phases_build_only_what_the_scene_has():
    cant = Simulation(load_scene("cantilever", [("numerics.spacing", 0.002)]))
    assert cant.solid is not None and cant.fluid is None and cant.fluid_phase is None and cant.coupling is None
    dam = Simulation(load_scene("dam_break", [("numerics.spacing", 0.05715 / 10)]))
    assert dam.fluid is not None and dam.solid is None and dam.solid_phase is None and dam.coupling is None
    gate = Simulation(load_scene("elastic_gate", COARSE))
    assert gate.solid is not None and gate.fluid is not None and isinstance(gate.coupling, Coupling)
    # the fluid sums over walls + solid: the solid is a moving wall of the fluid, the boundary's last block, where
    # the solid is and with the coupling's mass for it
    boundary = gate.boundary
    assert gate.fluid_phase.solver.wall_pos is boundary.pos and boundary.count == gate.walls.count + gate.solid.count
    assert boundary.rows("walls") == slice(0, gate.walls.count) and not boundary.has("gate")
    assert np.array_equal(boundary.pos[boundary.rows("walls")], gate.walls.pos)
    assert np.array_equal(boundary.pos[boundary.rows("solid")], gate.solid.pos)
    assert np.array_equal(boundary.mass[boundary.rows("solid")], gate.coupling.wall_mass)
    built = gate.solid.pos.copy()
    gate.step()     # the boundary follows the solid before each fluid step: where it was at the last one's start
    after_one = gate.solid.pos.copy()
    gate.step()
    assert not np.array_equal(after_one, built) and not np.array_equal(boundary.pos[boundary.rows("solid")], built)
    assert boundary.follow_solid() and np.array_equal(boundary.pos[boundary.rows("solid")], gate.solid.pos)


def test_coupling_keys_only_in_coupled_scenes():
    from sph_fsi_core.schema import SceneError
    with pytest.raises(SceneError, match="coupling"):
        load_scene("dam_break", [("coupling.gamma", 5.0)])
    with pytest.raises(SceneError, match="coupling.model"):
        load_scene("elastic_gate", [("coupling.model", "magic")])


def test_paper_particle_counts_at_1mm():
    """Across the paper's 36 mm its counts (sec. 3.2: 5,760 gate, 27,648 water particles); the scene's narrowest
    slab (6 layers across) is a sixth of that in every phase."""
    sim = Simulation(load_scene("elastic_gate", [("geometry.span", 0.036)]))
    assert sim.solid.moving_count == 5760          # 4 x 36 x 40
    assert sim.fluid.count == 27648                # 27,360 + the 288 in the slot
    assert sim.solid.count - sim.solid.moving_count == 432   # clamp: 3 layers of 4 x 36
    narrow = Simulation(load_scene("elastic_gate"))
    assert (narrow.solid.moving_count, narrow.fluid.count, narrow.walls.count) == (960, 4608, 4320)
    assert 6 * narrow.walls.count == sim.walls.count


def test_surface_normals(gate_sim):
    s, c = gate_sim.solid, gate_sim.coupling
    n = s.surface_normal
    dp = 0.002
    mid = np.isclose(s.pos[:, 2], s.pos[:, 2].min() + 10 * dp)
    wet = mid & np.isclose(s.pos[:, 0], s.pos[:, 0].max())
    dry = mid & np.isclose(s.pos[:, 0], s.pos[:, 0].min())
    assert c.surface[wet].all() and c.surface[dry].all()
    np.testing.assert_allclose(n[wet], np.tile([1.0, 0.0, 0.0], (wet.sum(), 1)), atol=1e-9)
    np.testing.assert_allclose(n[dry], np.tile([-1.0, 0.0, 0.0], (dry.sum(), 1)), atol=1e-9)
    bottom = np.isclose(s.pos[:, 2], s.pos[:, 2].min())
    assert (n[bottom, 2] < -0.5).all()


def test_surface_interior_of_a_thick_block():
    """A 6-layer-thick gate has interior particles: no normal there, unit normals on the faces."""
    sim = Simulation(load_scene("elastic_gate", COARSE + [("geometry.gate_thickness", 0.012)]))
    c, s = sim.coupling, sim.solid
    x = s.pos[:, 0]
    inner = (x > x.min() + 1.5 * 0.002) & (x < x.max() - 1.5 * 0.002) & s.movable
    inner &= s.pos[:, 2] > s.pos[:, 2].min() + 3 * 0.002
    assert inner.any() and not c.surface[inner].any()
    assert np.allclose(np.linalg.norm(s.surface_normal[c.surface], axis=1), 1.0)
    assert np.allclose(s.surface_normal[~c.surface], 0.0)


def test_seed_push_opposes_the_waters_correction(gate_sim):
    """Eq. (11): water pushed away from the wet face (+x) pushes the face towards -x, scaled by gamma."""
    sim = gate_sim
    f, s, c = sim.fluid, sim.solid, sim.coupling
    c.configure("seed", 10.0, 0)
    dt = 1.0e-3
    f.correction_displacement[:] = 0.0
    f.correction_displacement[:, 0] = 1.0e-6          # every water particle moved +x by the correction
    acc = c.push(dt).copy()
    wet = c.surface & s.movable & (s.surface_normal[:, 0] > 0.9)
    assert (acc[wet, 0] < 0.0).all()
    interior_or_clamp = ~c.surface | ~s.movable
    assert np.allclose(acc[interior_or_clamp], 0.0)
    c.configure("seed", 20.0, 0)
    np.testing.assert_allclose(c.push(dt), 2.0 * acc, rtol=1e-12, atol=0.0)
    f.correction_displacement[:] = 0.0


def test_pressure_pair_forces_sum_to_zero(gate_sim):
    """'pressure' model: the pair forces on solid and fluid are equal and opposite, so they sum to zero."""
    sim = gate_sim
    f, c = sim.fluid, sim.coupling
    rng = np.random.default_rng(4)
    saved = f.pressure.copy()
    f.pressure[:] = rng.uniform(0.0, 500.0, f.count)
    on_solid = c.pressure_forces().copy()
    on_fluid = c.fluid_side_forces()
    total_solid = on_solid.sum(axis=0)
    total_fluid = on_fluid.sum(axis=0)
    scale = np.abs(on_solid).sum()
    assert scale > 0.0
    np.testing.assert_allclose(total_solid + total_fluid, 0.0, atol=1e-12 * scale)
    assert abs(total_solid[0]) > 1e-6 * scale     # not trivially zero: the wet face carries a net load
    f.pressure[:] = saved


def test_pressure_model_hydrostatic_load_direction():
    """A uniform pressure on the wet side only pushes the gate towards the dry side (-x)."""
    sim = Simulation(load_scene("elastic_gate", COARSE + [("coupling.model", "pressure")]))
    f = sim.fluid
    f.pressure[:] = 1000.0
    acc = sim.coupling.push(1e-3)
    assert acc[sim.solid.movable, 0].sum() < 0.0


def test_substep_ratio():
    sim = Simulation(load_scene("elastic_gate", COARSE))
    c = sim.coupling
    dts = sim.solid_phase.solver.stable_dt()
    n, warning = c.substeps(1.0e-3, dts)
    assert n == math.ceil(1.0e-3 / dts) and warning is None
    c.configure("seed", 10.0, 10 * n)
    assert c.substeps(1.0e-3, dts) == (10 * n, None)
    c.configure("seed", 10.0, 1)
    n1, warning = c.substeps(1.0e-3, dts)
    assert n1 == n and "coupling.substeps" in warning


def test_one_coupled_step_moves_both_phases_and_keeps_water_out_of_the_gate():
    sim = Simulation(load_scene("elastic_gate", COARSE + [("coupling.model", "pressure"),
                                                        ("output.timeseries_interval", 0.004)]))
    sim.step()
    assert sim.fluid_phase.steps >= 1 and sim.solid_phase.steps >= sim.fluid_phase.steps * 10
    assert np.abs(sim.solid.vel[sim.solid.movable]).max() > 0.0
    # the boundary the fluid saw holds the solid where it was at the last fluid step
    gate_x = (sim.solid.pos[:, 0].min(), sim.solid.pos[:, 0].max())
    top = sim.solid.pos[:, 2].max()
    inside = ((sim.fluid.pos[:, 0] > gate_x[0] + 0.001) & (sim.fluid.pos[:, 0] < gate_x[1] - 0.001)
              & (sim.fluid.pos[:, 2] > sim.solid.pos[:, 2].min() + 0.001) & (sim.fluid.pos[:, 2] < top))
    assert not inside.any()
    row = sim.sample()
    assert {"coupling_force_x", "tip_dx", "tip_dz", "strain_energy", "solid_substeps"} <= set(row)


@pytest.mark.parametrize("scene,overrides", [("cantilever", [("numerics.spacing", 0.002)]), ("elastic_gate", COARSE)])
def test_a_runaway_solid_stops_before_its_sub_steps(scene, overrides):
    """The solid's stable step falls as cfl h / (c + |v|max): a solid particle above watchdog.max_speed stops the run
    when its sub-steps are planned (Diverged naming the check and the particle), before any sub-step, instead of
    sub-stepping ever finer inside an outer step the end-of-step watchdog never reaches (Antoci's gate at cfl 0.35
    ran 13 minutes in one outer step). Alone (the cantilever) and inside the first fluid step (the gate)."""
    from sph_fsi_core.diagnostics import Diverged
    sim = Simulation(load_scene(scene, overrides))
    moving = np.flatnonzero(sim.solid.movable)
    sim.solid.vel[moving[2]] = [0.0, 0.0, 1.2 * sim.spec["watchdog.max_speed"]]
    moving = int(moving[5])
    sim.solid.vel[moving] = [0.0, 0.0, 1.5 * sim.spec["watchdog.max_speed"]]
    with pytest.raises(Diverged) as caught:
        sim.step()
    assert caught.value.check == "speed" and caught.value.particles[0] == moving   # the fastest first
    assert f"solid particle {moving}" in str(caught.value) and "before the solid's sub-steps" in str(caught.value)
    assert sim.solid_phase.steps == 0


@pytest.mark.parametrize("ratio", [2.0, 9.0])
def test_relaxed_push_damps_the_added_mass_alternation(gate_sim, ratio):
    """coupling.relaxation on the staggered model it is for: a rigid solid of mass m_s whose push answers its own
    acceleration of the step before through an added mass m_a (a_push = (F - m_a a_prev) / m_s, what an
    incompressible fluid's projection gives a staggered scheme). Unrelaxed the deviation from the coupled answer
    F / (m_s + m_a) alternates by -m_a / m_s per step; relaxed by w, by (1 - w) - w m_a / m_s: it converges for
    w < 2 / (1 + m_a / m_s), and to that answer (a fixed point is not moved). Through the Coupling's own code."""
    c = gate_sim.coupling
    saved = (c.relaxation, c.previous_acc, c.acc.copy())
    force, exact = 1.0, 1.0 / (1.0 + ratio)          # per unit m_s
    try:
        for w, converges in ((1.0, False), (0.9 * 2.0 / (1.0 + ratio), True), (1.0 / (1.0 + ratio), True),
                             (1.1 * 2.0 / (1.0 + ratio), False)):
            c.relaxation, c.previous_acc = w, None
            held, deviations = 0.0, []
            for _ in range(200):
                c.acc[:] = force - ratio * held        # the fluid's answer to the held push of the step before
                c._relax_push()
                held = float(c.acc[0, 0])
                deviations.append(held - exact)
            expected = (1.0 - w) - w * ratio
            if abs(expected) > 0.1:      # w = 1 / (1 + m_a / m_s) is exact in one step (the factor is 0)
                assert deviations[20] / deviations[19] == pytest.approx(expected, rel=1e-6)
            else:
                assert abs(deviations[2]) < 1e-12
            assert (abs(deviations[-1]) < 1e-9) == converges, (w, deviations[-1])
    finally:
        c.relaxation, c.previous_acc = saved[0], saved[1]
        c.acc[:] = saved[2]


def test_ramp_pieces_take_the_ramp_s_impulse_exactly():
    """coupling.push_ramp's pieces: whole sub-steps, nearly equal, covering the step; each held at the ramp's value
    at its middle, so their impulse sum_j len_j a(mid_j) is the ramp's own, n (a0 + a1) / 2 (the midpoint rule is
    exact on a linear function), and the last piece ends on the new push's side."""
    from sph_fsi_core.solid.phase import RAMP_PIECES, ramp_pieces
    for n in (1, 3, 16, 17, 3500, 3517):
        ends = ramp_pieces(n, RAMP_PIECES)
        lengths = np.diff(ends)
        assert ends[0] == 0 and ends[-1] == n and len(lengths) == min(n, RAMP_PIECES)
        assert lengths.min() >= 1 and lengths.max() - lengths.min() <= 1
        a0, a1 = -3.0, 5.0
        mids = 0.5 * (ends[:-1] + ends[1:]) / n
        assert float(np.sum(lengths * (a0 + mids * (a1 - a0)))) == pytest.approx(n * 0.5 * (a0 + a1), rel=1e-13)


def test_ramped_push_held_constant_is_the_held_push_to_the_bit():
    """The solid's sub-steps taken in the ramp's pieces under a push that does not change give the held push's
    steps to the bit (the pieces only cut the same leapfrog into runs), and the sub-steps are counted once."""
    runs = []
    for ramp in (False, True):
        sim = Simulation(load_scene("elastic_gate", COARSE))
        push = np.zeros((sim.solid.count, 3))
        push[sim.solid.movable, 0] = 0.3
        n, _ = sim.coupling.substeps(5e-4, sim.solid_phase.solver.stable_dt())
        for _ in range(3):
            sim.solid_phase.advance_coupled(push, 5e-4, sim.coupling.substeps, 0.0, sim.watchdog,
                                            push.copy() if ramp else None)
        assert sim.solid_phase.steps == 3 * n and sim.solid_phase.last_substeps == n
        runs.append((sim.solid.pos.copy(), sim.solid.vel.copy()))
    assert n > 16 and np.array_equal(runs[0][0], runs[1][0]) and np.array_equal(runs[0][1], runs[1][1])


def test_push_ramp_starts_from_the_last_step_s_push_and_reports_what_the_solid_felt():
    """With coupling.push_ramp the first fluid step's push is held (nothing before it to ramp from), each later one
    ramps from the push before it, and the outer step's mean push is the mean of what the solid felt over each step,
    (a_before + a_now) / 2: the impulse balance's bookkeeping."""
    sim = Simulation(load_scene("elastic_gate", COARSE + [("coupling.push_ramp", True),
                                                          ("output.timeseries_interval", 0.002)]))
    c = sim.coupling
    pushes, starts, dts = [], [], []
    original = sim.solid_phase.advance_coupled

    def spy(push, dt, substeps, time, watchdog, push_start=None):
        pushes.append(push.copy())
        starts.append(None if push_start is None else push_start.copy())
        dts.append(dt)
        return original(push, dt, substeps, time, watchdog, push_start)
    sim.solid_phase.advance_coupled = spy
    for _ in range(4):
        sim.step()
    assert starts[0] is None and len(pushes) >= 4
    for before, start in zip(pushes[:-1], starts[1:]):
        assert np.array_equal(before, start)
    felt = [pushes[0]] + [0.5 * (a + b) for a, b in zip(pushes[1:], pushes[:-1])]
    steps_last = [len(dts) - 1]
    while sum(dts[k] for k in steps_last) < sim.outer_step_duration() * (1 - 1e-9):
        steps_last.append(steps_last[-1] - 1)
    expected = sum(dts[k] * (sim.solid.mass @ felt[k]) for k in steps_last) / sum(dts[k] for k in steps_last)
    assert np.allclose(c.mean_push, expected, rtol=1e-12, atol=1e-15)
    assert np.abs(c.mean_push).max() > 0.0


def test_steel_gate_cells_read_the_swing_and_the_beam_s_static_deflection(tmp_path):
    """The push_ramp and fixed_iterations studies' steel gate cells: the free end's standard deviation and mean over
    0.02-0.04 s from the run's time series, and beam theory's F L^3 / 8 E I (I = w T^3 / 12) for the mean push, on a
    series whose numbers are known."""
    from sph_fsi_core.validation.cases import push_ramp
    from sph_fsi_core.validation.cases.setting_studies import steel_gate_cells, with_steel_ringing
    rung = next(r for r in push_ramp.rungs() if r.label == "min_3__steel_gate_E_2e11")
    run = tmp_path / "runs" / rung.case / rung.label
    run.mkdir(parents=True)
    times = np.arange(41) * 0.001
    dx = np.where(np.arange(41) % 2 == 0, -1.0e-7, -3.0e-7)      # mean -0.2 um, standard deviation 0.1 um inside
    rows = ["time,tip_dx,coupling_force_x"] + [f"{t:.6g},{d:.6g},-0.5" for t, d in zip(times, dx)]
    (run / "timeseries.csv").write_text("\n".join(rows) + "\n")
    settings = {"geometry.slab": 0.012, "geometry.thick": 0.004, "geometry.free": 0.04, "solid.young_modulus": 2e11}
    summaries = with_steel_ringing(tmp_path, [rung], {rung.key: {"settings": settings}})
    ringing = summaries[rung.key]["ringing"]
    assert ringing["mean_m"] == pytest.approx(-2.0e-7, rel=0.06) and ringing["std_m"] == pytest.approx(1.0e-7, rel=0.01)
    measure, beside = steel_gate_cells(summaries[rung.key])
    static = 0.5 * 0.04 ** 3 / (8 * 2e11 * 0.012 * 0.004 ** 3 / 12)      # 0.3125 um
    assert measure.startswith("swing 0.100 um") and f"{1e6 * static:.3f} um" in beside and "push -0.500 N" in beside
