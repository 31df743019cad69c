"""What the node shows of a coupled scene (ROS-free: sph_fsi.points): water (phase 1) and the gate's moving particles
(phase 2) in ~/particles, the tank's walls and the gate's clamp in ~/walls, the gate's free end on
~/tip_displacement (and, as every probe, on ~/probes/tip/displacement) and its strain energy on ~/strain_energy."""
import numpy as np

from sph_fsi.points import PHASE_FLUID, PHASE_SOLID, particle_points, topic_plan, wall_positions
from sph_fsi_core.scene import load_scene
from sph_fsi_core.simulation import Simulation


def test_gate_scene_topics_and_points():
    sim = Simulation(load_scene("elastic_gate", ["numerics.spacing=0.002", "solid.scheme=gray2001",
                                                 "geometry.gate_clamp_height=0.004",
                                                 "geometry.span=0", "output.timeseries_interval=0.002"]))
    sim.step()
    assert topic_plan(sim) == {"particles", "walls", "tip_displacement", "strain_energy", "probes/tip/displacement"}
    points = particle_points(sim)
    assert len(points) == sim.fluid.count + sim.solid.moving_count
    assert np.count_nonzero(points["phase"] == PHASE_FLUID) == sim.fluid.count
    assert np.count_nonzero(points["phase"] == PHASE_SOLID) == sim.solid.moving_count
    solid = points[points["phase"] == PHASE_SOLID]
    assert solid["von_mises"].max() > 0.0
    clamp = sim.solid.count - sim.solid.moving_count
    assert len(wall_positions(sim)) == sim.walls.count + clamp
    assert np.all(np.isfinite(sim.probe_displacements()["tip"]))
    assert sim.energies()["strain_energy"] > 0.0
