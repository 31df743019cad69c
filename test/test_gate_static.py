"""Antoci's gate held static (config/antoci_gate_static.yaml, coupled; config/antoci_gate_loaded.yaml, under the exact
pressure): the gap closed, the load the water puts on it, the relaxation rates and how a run is judged."""
import math

import numpy as np
import pytest

from sph_fsi_core.scene import load_scene
from sph_fsi_core.scenes import BUILDERS, tank
from sph_fsi_core.scenes.cases import antoci_gate_loaded, antoci_gate_static, gate


def test_static_gate_stands_on_the_floor_under_reduced_gravity():
    spec = load_scene("antoci_gate_static")
    v = spec.values
    b = BUILDERS[spec.builder].build(v)
    dp = v["numerics.spacing"]
    assert v["geometry.gate_clearance"] == 0.0 and v["scene.gravity"] == pytest.approx((0.0, 0.0, -1.0))
    moving = b.solid.pos[b.solid.movable]
    assert moving[:, 2].min() == pytest.approx(0.5 * dp)              # the free end's layer sits on the floor
    assert not np.any((b.fluid.pos[:, 0] > -5.0e-3) & (b.fluid.pos[:, 0] < 0.0))   # no water under the gate
    assert b.damping_rate == pytest.approx(2.0 * gate.first_mode_omega(v))
    period = 4 * 0.14 / math.sqrt(1.0 * 0.14 / 0.01)
    assert tank.breathing_period(gate.water_surface_z(v), v["scene.gravity"], 0.01) == pytest.approx(period, rel=1e-3)
    assert b.fluid_damping_rate == pytest.approx(2.0 * 0.3 * 2.0 * math.pi / period, rel=1e-3)


def test_loaded_gate_carries_the_hydrostatic_force_of_its_water():
    """The load on the wet layer integrates rho_f g (H - z) over the free length's wet face: by the midpoint rule,
    exact for a linear pressure, rho_f g W (H L - L^2 / 2) (clearance 0), all of it pushing +x (the water on the
    gate's -x side), none on the clamp."""
    spec = load_scene("antoci_gate_loaded")
    v = antoci_gate_loaded.layout_values(spec.values)
    b = BUILDERS[spec.builder].build(spec.values)
    geometry = gate.effective_geometry(v)
    length, width = geometry["gate_free_length_m"], geometry["span_m"]
    height = gate.water_surface_z(v)
    total = b.solid_load.sum(axis=0)
    assert total[0] == pytest.approx(1000.0 * 1.0 * width * (height * length - 0.5 * length ** 2), rel=1e-12)
    assert total[1] == 0.0 and total[2] == 0.0
    loaded = np.flatnonzero(b.solid_load[:, 0])
    assert np.all(b.solid.movable[loaded])
    assert np.allclose(b.solid.pos[loaded, 0], b.solid.pos[b.solid.movable, 0].min())    # the wet (-x) layer
    assert b.fluid is None and b.walls is None


def test_both_twins_are_judged_against_the_same_fe_value():
    static = load_scene("antoci_gate_static").values
    loaded = load_scene("antoci_gate_loaded").values
    ref_static = gate.static_tip_reference(static, static["fluid.density"], 1.0)
    ref_loaded = gate.static_tip_reference(antoci_gate_loaded.layout_values(loaded), loaded["geometry.water_density"], 1.0)
    assert ref_static["fe_tip_deflection_m"] == pytest.approx(ref_loaded["fe_tip_deflection_m"], rel=1e-12)
    # about 5 % of the free length (linear), the continuum within 1 % of the beam
    length = gate.effective_geometry(static)["gate_free_length_m"]
    assert 0.04 < ref_static["fe_tip_deflection_m"] / length < 0.06
    assert ref_static["fe_tip_deflection_m"] == pytest.approx(ref_static["beam_tip_deflection_m"], rel=0.01)
    t = np.linspace(0.0, 0.4, 401)
    series = {"time": t, "tip_dx": np.full_like(t, 1.03 * ref_loaded["fe_tip_deflection_m"])}
    out = antoci_gate_loaded.evaluate(series, loaded)
    assert out["error_signed"] == pytest.approx(0.03)
    assert out["tip_deflection_swing_m"] == 0.0


def test_coupled_twin_reports_the_water_load_against_the_hydrostatic_force():
    """rho_f g W (H L - L^2 / 2) on a free length L standing on the floor under water of depth H."""
    v = load_scene("antoci_gate_static").values
    geometry = gate.effective_geometry(v)
    length, width, height = geometry["gate_free_length_m"], geometry["span_m"], gate.water_surface_z(v)
    exact = 1000.0 * 1.0 * width * (height * length - 0.5 * length ** 2)
    fe = gate.static_tip_reference(v, 1000.0, 1.0)["fe_tip_deflection_m"]
    t = np.linspace(0.0, 0.6, 601)
    force = np.full_like(t, 0.98 * exact)
    out = antoci_gate_static.evaluate({"time": t, "tip_dx": np.full_like(t, fe), "coupling_force_x": force}, v)
    assert out["water_load_exact_n"] == pytest.approx(exact, rel=1e-12)
    assert out["water_load_error"] == pytest.approx(-0.02, abs=2e-3)
    assert out["error_signed"] == pytest.approx(0.0, abs=1e-12)


def test_fe_is_read_where_the_probe_sits():
    """The 'tip' probe is the lowest particle layer, half a spacing above the body's free end: the FE reference is
    read there, which is less than at the end by about the end's slope times dp / 2 (slope 4/3 of the deflection
    over L for a uniform load; a little less under the hydrostatic one, which is smaller near the end)."""
    spec = load_scene("antoci_gate_loaded")
    v = antoci_gate_loaded.layout_values(spec.values)
    dp = v["numerics.spacing"]
    length = gate.effective_geometry(v)["gate_free_length_m"]
    ref = gate.static_tip_reference(v, 1000.0, 1.0)
    assert ref["probe_from_clamp_m"] == pytest.approx(length - 0.5 * dp, rel=1e-12)
    drop = 1.0 - ref["fe_tip_deflection_m"] / ref["fe_free_end_deflection_m"]
    assert drop == pytest.approx(4.0 / 3.0 * 0.5 * dp / length, rel=0.15)
    # the probe's particles sit there: their mean height is the free end's plus half a spacing (clearance 0)
    b = BUILDERS[spec.builder].build(spec.values)
    assert b.solid.pos[b.probes[0].indices, 2].mean() == pytest.approx(0.5 * dp, rel=1e-9)
