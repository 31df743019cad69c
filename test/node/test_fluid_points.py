"""What the node shows of a fluid-only scene (ROS-free: sph_fsi.points): fluid particles with phase 1 and their
pressure in ~/particles, the tank's walls in ~/walls, and no tip_displacement or strain_energy."""
import numpy as np

from sph_fsi.points import PHASE_FLUID, particle_points, topic_plan, wall_positions
from sph_fsi_core.scene import load_scene
from sph_fsi_core.simulation import Simulation


def test_fluid_scene_topics_and_points():
    sim = Simulation(load_scene("hydrostatic", ["numerics.spacing=0.005"]))
    for _ in range(4):
        sim.step()
    assert topic_plan(sim) == {"particles", "walls"}
    points = particle_points(sim)
    assert len(points) == sim.fluid.count == 1200
    assert np.all(points["phase"] == PHASE_FLUID)
    assert np.array_equal(points["pressure"], sim.fluid.pressure.astype(np.float32))
    assert points["pressure"].max() > 0.5 * 1000.0 * 9.81 * 0.1   # the bottom carries the column
    assert np.array_equal(points["z"], sim.fluid.pos[:, 2].astype(np.float32))
    assert np.all(points["von_mises"] == 0.0)
    assert len(wall_positions(sim)) == sim.walls.count
