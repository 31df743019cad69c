"""Gray's artificial stress against the tensile instability (METHOD sec. 1).

A short beam thrown hard into its first mode (free-end speed 3 m/s, a few per cent of bending strain at the
root) puts the particles near its surfaces under strong tension. Without the artificial stress, tension makes
SPH particles pair up (the tensile instability): neighbours close in far below the lattice spacing. With it, the
spacing stays near dp. The measure is the smallest particle distance over the run, in units of dp.
"""
import numpy as np
import pytest

from sph_fsi_core.diagnostics import Diverged
from sph_fsi_core.scene import load_scene
from sph_fsi_core.simulation import Simulation

PROVOKING = ["geometry.length=0.012", "geometry.width=0.003", "geometry.clamp_margin=2",
             "geometry.tip_velocity=3.0", "solid.artificial_viscosity_alpha=0.1", "output.snapshot_interval=0",
             "output.timeseries_interval=1e-4"]


def _closest_approach(art_eps, end_time=0.015):
    spec = load_scene("cantilever", PROVOKING + [f"solid.artificial_stress_epsilon={art_eps}"])
    sim = Simulation(spec)
    dp = spec["numerics.spacing"]
    closest = np.inf
    outcome = "stable"
    try:
        while sim.time < end_time:
            sim.step()
            p = sim.solid.pos[sim.solid.movable]
            d = np.sqrt(((p[:, None, :] - p[None, :, :]) ** 2).sum(-1))
            np.fill_diagonal(d, np.inf)
            closest = min(closest, d.min() / dp)
    except Diverged as exc:
        outcome = exc.check
    return closest, outcome


@pytest.fixture(scope="module")
def runs():
    return {eps: _closest_approach(eps) for eps in (0.0, 0.3)}


def test_artificial_stress_keeps_particles_apart(runs):
    with_stress, outcome_with = runs[0.3]
    without, outcome_without = runs[0.0]
    assert outcome_with == "stable"
    assert with_stress > 0.6
    # without it the particles pair up, or the run is stopped by the watchdog
    assert outcome_without != "stable" or without < 0.8 * with_stress
