"""The water's walls and who owns their rows (boundary.py): blocks by kind, parts by name, the gate's release and lift,
the solid followed. On a made-up scene of three wall particles, two gate particles and two solid particles."""
import numpy as np
import pytest

from sph_fsi_core.boundary import Boundary
from sph_fsi_core.scene import load_scene
from sph_fsi_core.scenes.built import Built
from sph_fsi_core.simulation import Simulation
from sph_fsi_core.state import SolidState, WallState


def _built(lifted=False):
    walls = WallState(pos=np.arange(9.0).reshape(3, 3), mass=np.array([1.0, 2.0, 3.0]), rho0=1000.0)
    gate = WallState(pos=10.0 + np.arange(6.0).reshape(2, 3), mass=np.array([4.0, 5.0]), rho0=1000.0)
    built = Built(walls=walls, release_walls=gate,
                  parts={"tank": ("walls", np.array([0, 1])), "post": ("walls", np.array([2])),
                         "door": ("gate", np.array([0, 1])), "water": ("fluid", np.arange(5)),
                         "flap": ("solid", np.array([1]))})
    if lifted:
        built.release_velocity, built.release_travel = np.array([0.0, 0.0, 2.0]), 0.5
    solid = SolidState.at_rest(20.0 + np.arange(6.0).reshape(2, 3), np.array([True, True]), 1000.0, 0.1)
    return built, solid


def test_blocks_and_parts_are_found_by_name():
    built, solid = _built()
    b = Boundary.of(built, 1000.0, gates=True, solid=solid, solid_mass=np.array([6.0, 7.0]))
    assert b.count == 7 and b.rows("walls") == slice(0, 3) and b.rows("gate") == slice(3, 5)
    assert b.rows("solid") == slice(5, 7)
    assert np.array_equal(b.mass, [1, 2, 3, 4, 5, 6, 7])
    assert np.array_equal(b.pos[b.rows("gate")], built.release_walls.pos)
    assert list(b.part_rows("post")) == [2] and list(b.part_rows("door")) == [3, 4] and list(b.part_rows("flap")) == [6]
    assert b.part_rows("water") is None and b.part_rows("nosuch") is None
    with pytest.raises(KeyError):
        Boundary.of(built, 1000.0).rows("solid")


def test_the_release_removes_the_gates_rows_and_keeps_the_rest():
    built, solid = _built()
    b = Boundary.of(built, 1000.0, gates=True, solid=solid, solid_mass=np.array([6.0, 7.0]))
    after = b.without_gates()
    assert not after.has("gate") and after.count == 5 and after.part_rows("door") is None
    assert np.array_equal(after.mass, [1, 2, 3, 6, 7]) and list(after.part_rows("flap")) == [4]
    assert np.array_equal(after.pos[after.rows("solid")], b.pos[b.rows("solid")]) and after.pos is not b.pos
    # the gate that never stood has no rows either
    assert not Boundary.of(built, 1000.0).has("gate")


def test_a_lifted_gate_moves_at_its_speed_until_its_travel_then_stays():
    built, solid = _built(lifted=True)
    b = Boundary.of(built, 1000.0, gates=True)
    start = built.release_walls.pos.copy()
    assert b.move_parts(0.1) and np.allclose(b.pos[b.rows("gate")] - start, [0.0, 0.0, 0.2], atol=1e-15)
    assert np.array_equal(b.pos[b.rows("walls")], built.walls.pos)      # the fixed walls stay
    assert b.move_parts(1.0) and np.allclose(b.pos[b.rows("gate")] - start, [0.0, 0.0, 0.5], atol=1e-15)
    assert not b.move_parts(2.0) and b.gate_motion is None           # parked at its travel: nothing moves
    assert np.allclose(b.pos[b.rows("gate")] - start, [0.0, 0.0, 0.5], atol=1e-15)


def test_the_solid_block_follows_the_solid():
    built, solid = _built()
    b = Boundary.of(built, 1000.0, solid=solid, solid_mass=np.array([6.0, 7.0]))
    solid.pos += 0.25
    assert np.array_equal(b.pos[b.rows("solid")], solid.pos - 0.25)
    assert b.follow_solid() and np.array_equal(b.pos[b.rows("solid")], solid.pos)
    assert not Boundary.of(built, 1000.0).follow_solid()


def test_a_force_probe_finds_its_wall_by_name():
    """The example tank's force probe on the tank: the rows the boundary gives the part `tank` are that part's wall
    particles, and with one fluid step per sample the probe reads the pair forces on exactly those rows."""
    spec = load_scene("config/examples/hydrostatic_geometry.yaml", ["numerics.spacing=0.005",
                                                                    "output.timeseries_interval=0.0005"])
    sim = Simulation(spec)
    rows = sim.boundary.part_rows("tank")
    probe = [p for p in sim.probes if p.kind == "force"][0]
    assert probe.part == "tank" and probe.phase == "walls" and np.array_equal(rows, probe.indices)
    assert len(rows) == sim.walls.count
    groups = np.full(sim.boundary.count, -1, dtype=np.int64)
    groups[rows] = 0
    down = []
    for _ in range(20):
        sim.step()
        assert sim.fluid_phase.last_substeps == 1
        by_hand = sim.fluid_phase.solver.wall_forces(groups, 1)[0]
        assert np.array_equal(np.array(sim.probe_readings()[probe.name][1]["force"]), by_hand)
        down.append(by_hand[2])
    assert np.mean(down) < 0.0      # the water presses down on the tank
