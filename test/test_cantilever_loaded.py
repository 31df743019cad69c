"""The cantilever under a dead load (config/cantilever_loaded.yaml, scenes/cases/cantilever_loaded.py) and its
exact reference, the elastica (answers/references.py: elastica_tip): the shooting solution against Bisshopp &
Drucker's tabulated values and the linear limits; the load the case applies, in total and where; the quick rung
settles within its bound."""
import math

import numpy as np
import pytest

from sph_fsi_core.run import run_scene
from sph_fsi_core.scene import load_scene
from sph_fsi_core.scenes.cases import cantilever_loaded
from sph_fsi_core.simulation import Simulation
from sph_fsi_core.answers.references import elastica_tip


def test_elastica_against_bisshopp_drucker_and_the_linear_limits():
    # Bisshopp & Drucker 1945, Table 1: P L^2 / (E I) = 1 -> vertical 0.30172 L, horizontal pull-back 0.05643 L
    one = elastica_tip(1.0)
    assert one["deflection"] == pytest.approx(0.30172, abs=2e-5)
    assert one["pull_back"] == pytest.approx(0.05643, abs=2e-5)
    # small loads: beam theory, P L^3 / (3 E I) and q L^4 / (8 E I); tip slopes P L^2 / (2 E I), q L^3 / (6 E I)
    small = 1e-3
    assert elastica_tip(small)["deflection"] == pytest.approx(small / 3, rel=1e-5)
    assert elastica_tip(small)["rotation"] == pytest.approx(small / 2, rel=1e-5)
    assert elastica_tip(small, distributed=True)["deflection"] == pytest.approx(small / 8, rel=1e-5)
    assert elastica_tip(small, distributed=True)["rotation"] == pytest.approx(small / 6, rel=1e-5)
    # the free end stays on a circle of radius <= L about the clamp, and stiffens: less than linear
    for a in (2.0, 4.0):
        e = elastica_tip(a, distributed=True)
        assert e["deflection"] ** 2 + (1 - e["pull_back"]) ** 2 < 1.0
        assert e["deflection"] < a / 8


@pytest.mark.parametrize("kind", ["distributed", "tip"])
def test_the_load_is_the_one_asked_for(kind):
    spec = load_scene("cantilever_loaded", [f"geometry.load_kind={kind}", "geometry.load_parameter=2"])
    v = spec.values
    sim = Simulation(spec)
    inertia = v["geometry.width"] * v["geometry.thickness"] ** 3 / 12
    total = 2.0 * v["solid.young_modulus"] * inertia / v["geometry.length"] ** 2
    assert sim.solid_phase.load[:, 2].sum() == pytest.approx(-total, rel=1e-12)
    assert np.all(sim.solid_phase.load[:, :2] == 0.0) and np.all(sim.solid_phase.load[~sim.solid.movable] == 0.0)
    loaded = np.flatnonzero(sim.solid_phase.load[:, 2])
    if kind == "tip":
        x = sim.solid.pos[loaded, 0]
        assert np.allclose(x, v["geometry.length"] - 0.5 * v["numerics.spacing"])
    else:
        assert len(loaded) == sim.solid.moving_count
    assert np.all(sim.solid.vel == 0.0)                  # at rest: no initial mode velocity
    omega = cantilever_loaded.first_mode_omega(v)
    assert sim.solid_phase.damping_rate == pytest.approx(2 * v["geometry.damping_ratio"] * omega)
    assert sim.solid_phase.load_ramp_time == pytest.approx(v["geometry.load_ramp_periods"] * 2 * math.pi / omega)


@pytest.mark.slow
def test_a_short_beam_settles_on_the_elastica():
    """L/H = 5, alpha = 2 (the free end turns 18 degrees): +2.5 % against the elastica, of which +1.3 % is already
    there at alpha = 0.05 (shear and the 3D section, which the elastica leaves out; measured 2026-12-03)."""
    s = run_scene(load_scene("cantilever_loaded", ["geometry.length=0.02", "geometry.load_parameter=2",
                                                   "scene.end_time=0.0625"]), progress=False)
    assert s["stable"] and s["status"] == "finished"
    assert s["tip_deflection_swing_m"] < 1e-3 * s["tip_deflection_m"]      # settled
    assert 0.0 < s["error_signed"] < 0.06
    assert abs(s["pull_back_error"]) < 0.05
