"""Walls that move (parts.<name>.motion): the keys refused by name, the water's step kept short enough for the wall,
a commanded wall following its commands (and refusing those it cannot follow), a probe riding on a wall, the water's
wrench on a wall against hydrostatics, and a box pushed into water raising its level by the volume it displaces."""
import math

import numpy as np
import pytest
import yaml

from sph_fsi_core.scene import SceneError, load_scene
from sph_fsi_core.simulation import Simulation

DP = 0.01


def _scene(tmp_path, paddle, probes=(), end_time=0.05, **fluid):
    """A periodic slab of water 0.2 m long and 0.1 m deep in a tank, with the wall part `paddle` (its keys)."""
    tree = {"scene": {"builder": "geometry", "end_time": end_time, "gravity": [0.0, 0.0, -9.81]},
            "numerics": {"spacing": DP},
            "geometry": {"span": {"expression": "6 * dp", "unit": "m"}, "period": [0, "span", 0],
                         "domain_lo": [-0.1, 0, -0.1], "domain_hi": [0.3, "span", 0.4]},
            "fluid": {"density": 1000.0, "viscosity": 1.0e-6, **fluid},
            "output": {"timeseries_interval": 0.01},
            "parts": [{"name": "tank", "role": "wall", "shape": "box", "size": [0.2, "span", 0.2],
                       "position": [0.1, "span / 2", 0.1], "side": "outside", "open": "+z"},
                      {"name": "water", "role": "water", "shape": "box", "size": [0.2, "span", 0.1],
                       "position": [0.1, "span / 2", 0.05]},
                      {"name": "paddle", "role": "wall", "shape": "box", "size": [0.03, "span", 0.05],
                       "position": [0.1, "span / 2", 0.15], **paddle}],
            "probes": list(probes)}
    path = tmp_path / "scene.yaml"
    path.write_text(yaml.safe_dump(tree, sort_keys=False))
    return str(path)


def test_bad_motion_keys_are_refused_by_name(tmp_path):
    cases = [({"motion": "linear", "motion_velocity": [0, 0, 0]}, r"parts.paddle.motion_velocity = \[0, 0, 0\]"),
             ({"motion": "linear"}, "parts.paddle.motion_velocity: missing"),
             ({"motion": "sinusoid", "motion_amplitude": 0.01}, "parts.paddle.motion_frequency: missing"),
             ({"motion": "sinusoid", "motion_amplitude": 0.01, "motion_frequency": 1.0, "motion_axis": [0, 0, 0]},
              r"parts.paddle.motion_axis = \[0, 0, 0\]"),
             ({"motion": "table", "motion_file": "nosuch.csv"}, "parts.paddle.motion_file = .*not found"),
             ({"motion": "wobble"}, "parts.paddle.motion = 'wobble': not a known choice"),
             ({"motion": "ros", "motion_max_speed": 0.0}, "parts.paddle.motion_max_speed"),
             ({"motion_velocity": [0, 0, 1]}, "parts.paddle.motion_velocity"),         # a key of another motion
             ({"motion": "linear", "motion_velocity": [0, 0, 1], "motion_frequency": 2.0},
              "parts.paddle.motion_frequency")]
    for keys, message in cases:
        with pytest.raises(SceneError, match=message):
            Simulation(load_scene(_scene(tmp_path, keys)))
    (tmp_path / "poses.csv").write_text("t, x, y, z\n0, 0, 0, 0\n1, 0, 0, 0\n0.5, 0, 0, 0\n")
    with pytest.raises(SceneError, match="parts.paddle.motion_file = .*do not increase"):
        load_scene(_scene(tmp_path, {"motion": "table", "motion_file": "poses.csv"}))
    probe = {"name": "p", "kind": "pressure", "position": [0.0, 0.03, 0.05], "part": "tank"}
    with pytest.raises(SceneError, match=r"probes.p.part = 'tank': not a moving wall part; allowed: '' \(a probe "
                                         r"that stays\), 'paddle'"):
        load_scene(_scene(tmp_path, {"motion": "linear", "motion_velocity": [0, 0, -0.1]}, probes=[probe]))


def test_a_table_moves_the_wall_and_the_domain_holds_its_sweep(tmp_path):
    (tmp_path / "poses.csv").write_text("# t, x, y, z (m)\nt,x,y,z\n0, 0, 0, 0\n0.02, 0.0, 0, -0.04\n")
    sim = Simulation(load_scene(_scene(tmp_path, {"motion": "table", "motion_file": "poses.csv"})))
    rows = sim.boundary.part_rows("paddle")
    built = sim.boundary.pos[rows].copy()
    assert sim.domain_lo[2] == -0.1     # the scene's box
    sim.step()
    sim.step()
    assert np.allclose(sim.boundary.pos[rows] - built, [0.0, 0.0, -0.04], atol=1e-15)
    assert not np.isin(rows, sim.boundary.part_rows("tank")).any()


def test_the_water_step_keeps_a_moving_wall_within_cfl_h(tmp_path):
    """dt <= fluid.cfl h / (the fastest particle of the wall): a sinusoid's bound A (2 pi f + pi / ramp)."""
    keys = {"motion": "sinusoid", "motion_amplitude": 0.02, "motion_frequency": 10.0, "motion_axis": [1, 0, 0]}
    sim = Simulation(load_scene(_scene(tmp_path, keys)))
    h, cfl = sim.h, sim.spec["fluid.cfl"]
    speed = 0.02 * 2.0 * math.pi * 10.0
    assert sim.boundary.wall_speed == pytest.approx(speed)
    assert sim.fluid_phase.stable_dt() == pytest.approx(cfl * h / speed)
    still = Simulation(load_scene(_scene(tmp_path, {})))
    assert still.boundary.wall_speed == 0.0 and still.fluid_phase.stable_dt() > 1.5 * cfl * h / speed
    with pytest.raises(SceneError, match=r"fluid.time_step = 0.005 s: above the stable limit .* moving walls"):
        Simulation(load_scene(_scene(tmp_path, keys, time_step=0.005)))


def test_a_commanded_wall_follows_its_commands_from_their_step(tmp_path):
    """A velocity command stamped t_c moves the wall from the first fluid step starting at or after t_c; a pose
    command is reached over motion_period; a command too fast for motion_max_speed is refused and the wall goes on;
    a part that takes no commands refuses them; a pressure probe rides on the wall."""
    probe = {"name": "face", "kind": "pressure", "position": [0.085, 0.03, 0.15], "part": "paddle"}
    keys = {"motion": "ros", "motion_max_speed": 0.5, "motion_period": 0.01, "motion_point": [0.1, 0.03, 0.15]}
    sim = Simulation(load_scene(_scene(tmp_path, keys, probes=[probe])))
    boundary = sim.boundary
    assert boundary.commanded() == ["paddle"]
    rows = boundary.part_rows("paddle")
    built = boundary.pos[rows].copy()
    boundary.command("paddle", 0.015, "velocity", ([0.0, 0.0, -0.2], [0.0, 0.0, 0.0]))
    boundary.command("paddle", 0.0, "velocity", ([0.0, 0.0, -5.0], [0.0, 0.0, 0.0]))      # too fast
    with pytest.raises(ValueError, match="part 'tank' takes no commands; allowed: paddle"):
        boundary.command("tank", 0.0, "velocity", ([0.0, 0.0, 0.0], [0.0, 0.0, 0.0]))
    sim.step()
    assert [r[1] for r in boundary.refused] == ["paddle"] and "faster than motion_max_speed" in boundary.refused[0][2]
    assert not boundary.applied and np.allclose(boundary.pos[rows], built, atol=1e-15, rtol=0.0)
    sim.step()
    (applied, name, kind, _, _), = boundary.applied
    assert name == "paddle" and kind == "velocity" and 0.015 <= applied < 0.015 + sim.fluid_phase.last_dt + 1e-12
    moved = boundary.pos[rows] - built
    assert np.allclose(moved, [0.0, 0.0, -0.2 * (sim.time - applied)], atol=1e-12)
    position, rotation = boundary.part_pose("paddle")
    assert np.allclose(position, [0.1, 0.03, 0.15 - 0.2 * (sim.time - applied)], atol=1e-12)
    assert np.allclose(boundary.carried("paddle", np.array([[0.085, 0.03, 0.15]])), [[0.085, 0.03, position[2]]])
    boundary.command("paddle", sim.time, "pose", (np.eye(3), [0.0, 0.0, -0.004]))
    sim.step()
    assert np.allclose(boundary.pos[rows] - built, [0.0, 0.0, -0.004], atol=1e-12)


def test_the_waters_wrench_on_a_wall_at_rest_is_hydrostatic(tmp_path):
    """The tank's end wall under water at rest, from the water's last step: the force's mean over steps against
    rho g H^2 / 2 per width and its moment's arm against H / 3 above the floor (the centre of pressure)."""
    keys = {"motion": "ros", "motion_max_speed": 0.1, "motion_point": [0.1, 0.03, 0.15]}
    path = _scene(tmp_path, keys, end_time=0.3, density_tolerance=0.01)
    sim = Simulation(load_scene(path, ["geometry.water_start=compressed"]))
    tank = sim.boundary.part_rows("tank")
    end_wall = tank[sim.boundary.pos[tank, 0] < 0.0]           # the wall behind x = 0
    forces, arms = [], []
    while sim.time < 0.3 - 1e-9:
        sim.step()
        if sim.time > 0.1:
            force, moment = sim.fluid_phase.wrench(end_wall, np.array([0.0, 0.0, 0.0]))
            forces.append(-force[0])
            arms.append(moment[1] / force[0])                   # M_y = z F_x about the floor's corner
    width, depth = 6 * DP, 0.1
    exact = 1000.0 * 9.81 * depth ** 2 / 2 * width
    assert np.mean(forces) == pytest.approx(exact, rel=0.05)
    assert np.median(arms) == pytest.approx(depth / 3, rel=0.1)


def test_a_recorded_runs_commands_replay_to_the_same_bits(tmp_path):
    """Commands given as the node gives them (a message's numbers), recorded to MCAP stamped when they applied, read
    back and given to a new run of the scene: the same steps, the same bits; a command for a part the scene does
    not drive is refused by name."""
    from sph_fsi.points import command_values
    from sph_fsi.recording import Recorder
    from sph_fsi.recording.commands import check_parts, queue_commands, read_commands
    keys = {"motion": "ros", "motion_max_speed": 0.5, "motion_period": 0.02, "motion_point": [0.1, 0.03, 0.15]}
    spec = load_scene(_scene(tmp_path, keys))
    given = [(0.0031, "twist_cmd", ((0.0, 0.0, -0.1), (0.0, 0.0, 0.0))),
             (0.0123, "pose_cmd", ((0.101, 0.03, 0.146), (0.0, 0.0, math.sin(0.01), math.cos(0.01)))),
             (0.0205, "twist_cmd", ((0.05, 0.0, -0.05), (0.0, 0.3, 0.0)))]
    sim = Simulation(spec)
    point = sim.boundary.part_motion("paddle").point
    for stamp, what, numbers in given:
        kind, values = command_values(point, what, numbers)
        sim.boundary.command("paddle", stamp, kind, values, (what, numbers))
    mcap = tmp_path / "run.mcap"
    rec = Recorder(sim, mcap_path=str(mcap), rrd_path=str(tmp_path / "run.rrd"), interval=0.0)
    for _ in range(3):
        sim.step()
        rec.maybe_record(sim)
    rec.close(sim)
    assert not sim.boundary.refused
    commands = read_commands(mcap)
    assert [(c[0], c[2], c[3]) for c in commands] == [("paddle", what, numbers) for _, what, numbers in given]
    assert [c[1] for c in commands] == pytest.approx([a[0] for a in sim.boundary.applied], abs=1e-9)
    again = Simulation(spec)
    queue_commands(again, commands)
    for _ in range(3):
        again.step()
    assert np.array_equal(again.boundary.pos, sim.boundary.pos) and np.array_equal(again.fluid.pos, sim.fluid.pos)
    assert [a[0] for a in again.boundary.applied] == [a[0] for a in sim.boundary.applied]
    with pytest.raises(ValueError, match="a command for part 'tank', which this scene does not drive by commands; "
                                         "allowed: paddle"):
        check_parts([("tank",) + commands[0][1:]], spec.values)


def test_a_box_moved_through_water_and_stopped_gives_it_the_impulse_of_the_walls_forces(tmp_path):
    """Water in a channel periodic along x (no end walls) on a floor; a submerged box moves at 0.2 m/s for 0.25 s and
    stops. The water's change of x momentum against minus the impulse of the force probes on the box and the floor
    (the only walls): within 6 % at each time. The floor's share is not small: water moving over its particles
    feels their bumps (the lattice's; docs/validation/OPEN.md), about 30-40 % of the box's impulse once the water
    moves."""
    tree = {"scene": {"builder": "geometry", "end_time": 0.6, "gravity": [0.0, 0.0, -9.81]},
            "numerics": {"spacing": DP},
            "geometry": {"span": {"expression": "6 * dp", "unit": "m"}, "period": [0.4, "span", 0],
                         "domain_lo": [0, 0, -0.1], "domain_hi": [0.4, "span", 0.4]},
            "fluid": {"density": 1000.0, "viscosity": 1.0e-6},
            "output": {"timeseries_interval": 0.005},
            "parts": [{"name": "floor", "role": "wall", "shape": "box", "size": [0.4, "span", 0.03],
                       "position": [0.2, "span / 2", -0.015]},
                      {"name": "water", "role": "water", "shape": "box", "size": [0.4, "span", 0.1],
                       "position": [0.2, "span / 2", 0.05]},
                      {"name": "box", "role": "wall", "shape": "box", "size": [0.04, "span", 0.04],
                       "position": [0.1, "span / 2", 0.05], "motion": "linear", "motion_velocity": [0.2, 0, 0],
                       "motion_start": 0.05, "motion_travel": 0.05}],
            "probes": [{"name": "box_force", "kind": "force", "part": "box"},
                       {"name": "floor_force", "kind": "force", "part": "floor"}]}
    path = tmp_path / "impulse.yaml"
    path.write_text(yaml.safe_dump(tree, sort_keys=False))
    sim = Simulation(load_scene(str(path)))
    water = sim.fluid
    start = water.mass @ water.vel[:, 0]
    impulse = {"box_force": 0.0, "floor_force": 0.0}
    dt = sim.outer_step_duration()
    checked = 0
    while sim.time < 0.6 - 1e-9:
        sim.step()
        for name in impulse:
            impulse[name] += sim.probe_readings()[name][1]["force"][0] * dt
        if round(sim.time / dt) % 30 == 0:
            gained = water.mass @ water.vel[:, 0] - start
            assert gained == pytest.approx(-(impulse["box_force"] + impulse["floor_force"]), rel=0.06), sim.time
            checked += 1
    assert checked == 4 and -impulse["box_force"] > 0.03 and -impulse["floor_force"] < -0.2 * -impulse["box_force"]


def test_a_moving_wall_is_shown_among_the_moving_particles(tmp_path):
    """~/particles (and the recordings) carry a moving wall's particles as phase 3 where they are, at their motion's
    velocity; ~/walls only the walls that stay."""
    from sph_fsi.points import PHASE_WALL, particle_points, wall_positions
    keys = {"motion": "linear", "motion_velocity": [0.0, 0.0, -0.2]}
    sim = Simulation(load_scene(_scene(tmp_path, keys)))
    sim.step()
    rows = sim.boundary.part_rows("paddle")
    points = particle_points(sim)
    wall = points[points["phase"] == PHASE_WALL]
    assert len(wall) == len(rows) and len(points) == sim.fluid.count + len(rows)
    assert np.array_equal(wall["z"], sim.boundary.pos[rows, 2].astype(np.float32))
    assert np.allclose(wall["vz"], -0.2, rtol=1e-6) and not wall["vx"].any()
    assert len(wall_positions(sim)) == sim.walls.count - len(rows)
