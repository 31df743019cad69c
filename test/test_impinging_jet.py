"""The plane jet on a wall (answers/impinging_jet.py, config/jet_on_wall.yaml): the hodograph solution against
momentum conservation and Bernoulli's stagnation pressure, the scene file's reference against it, and the scene
built as its file says."""
import math

import numpy as np
import pytest
from scipy.integrate import quad

from sph_fsi_core.answers import impinging_jet as jet
from sph_fsi_core.scene import load_scene
from sph_fsi_core.scenes import build_scene

RHO, U, B = 1000.0, 1.0, 0.05


def test_the_wall_pressure_integrates_to_the_jets_momentum_flux():
    """The pressure over the wall, from the hodograph's parametrisation, sums to rho U^2 b per span: the sheets leave
    along the wall, so the wall takes all the jet's x momentum (an independent check of the solution)."""
    # over v: dy/dv = (2 b / pi) 2 / (1 - v^4), p = p0 (1 - v^2); the integrand 2 p0 (2 b / pi) / (1 + v^2) is smooth
    one_side, _ = quad(lambda v: jet.stagnation_pressure(RHO, U) * (1.0 - v * v) * 4.0 * B / math.pi
                       / (1.0 - v ** 4), 0.0, 1.0 - 1e-15, limit=200)
    assert 2.0 * one_side == pytest.approx(jet.force_per_span(RHO, U, B), rel=1e-9)
    # over y with wall_pressure's own inversion: most of the load within a width of the stagnation point
    near, _ = quad(lambda y: jet.wall_pressure(y, B, RHO, U), 0.0, 4.0 * B, limit=200)
    assert 2.0 * near == pytest.approx(jet.force_per_span(RHO, U, B), rel=2e-3)
    assert 2.0 * near < jet.force_per_span(RHO, U, B)


def test_the_axis_pressure_is_bernoullis_and_the_scene_files_formula_holds_it_near_the_wall():
    assert jet.axis_pressure(0.0, B, RHO, U) == pytest.approx(0.5 * RHO * U * U)
    for q in (0.05, 0.3, 0.9):
        d = jet.axis_distance(q, B)
        assert jet.axis_pressure(d, B, RHO, U) == pytest.approx(0.5 * RHO * U * U * (1.0 - q * q), rel=1e-12)
    # far up the jet the water moves at U: the pressure falls to nothing
    assert jet.axis_pressure(3.0 * B, B, RHO, U) < 2e-3 * jet.stagnation_pressure(RHO, U)
    # config/jet_on_wall.yaml's reference, q = pi d / (4 b), within 1e-4 for d < b / 4
    for d in np.linspace(0.0, B / 4.0, 11):
        series = jet.stagnation_pressure(RHO, U) * (1.0 - (math.pi * d / (4.0 * B)) ** 2)
        assert series == pytest.approx(jet.axis_pressure(d, B, RHO, U), rel=1e-4)


def test_the_scene_builds_a_block_moving_at_the_jets_speed_and_a_wall_in_its_path():
    dp = 0.005
    spec = load_scene("config/jet_on_wall.yaml", overrides=[f"numerics.spacing={dp}"])
    built, _ = build_scene(spec.builder, spec.values)
    v = spec.values
    fluid = built.fluid.pos
    assert len(fluid) == round(v["geometry.width"] / dp) * round(v["geometry.length"] / dp) * v["geometry.span_layers"]
    assert np.all(built.fluid.vel[:, 0] == v["geometry.speed"]) and not built.fluid.vel[:, 1:].any()
    # the block's front a gap short of the wall's face at x = 0, and across the jet's width about its axis
    assert fluid[:, 0].max() == pytest.approx(-v["geometry.gap"] - dp / 2)
    assert fluid[:, 2].min() == pytest.approx(-v["geometry.width"] / 2 + dp / 2)
    assert built.walls.pos[:, 0].min() == pytest.approx(dp / 2)
    assert np.ptp(built.walls.pos[:, 2]) == pytest.approx(v["geometry.wall_height"] - dp)
    assert not any(v["scene.gravity"])


def test_a_jet_run_that_diverged_gets_a_row_that_says_where_it_stopped():
    """The tolerance on the mean compression at 0.1 % let the jet's impact compress 2 particles by 23 % at 0.075 s
    (the mean of 24,000 stayed within it): the watchdog stopped the run before its judges, and the default report's
    and the studies' tables say so instead of failing on the judges it does not have."""
    from sph_fsi_core.validation.cases import default_fluid, pressure_tolerance
    from sph_fsi_core.validation.report import measured_against
    from sph_fsi_core.validation.cases.setting_studies import setting_table

    summary = {"stable": False, "diverged": {"check": "density error", "time": 0.075}, "fluid_steps": 394,
               "fluid_iterations_per_step": 0.32, "wall_time_s": 8.5, "machine": {"numba_threads": 2}}
    assert measured_against(summary, "force") == ("-", "-", "-")
    rungs = [r for r in pressure_tolerance.rungs() if r.label == "mean_0.1pc__jet_on_wall_b_over_dp_20"]
    bases = {r.key: r for r in default_fluid.rungs()}
    lines = setting_table("pressure_tolerance", "## t", pressure_tolerance.__doc__, "tolerance", rungs,
                          {rungs[0].key: summary}, bases, None)
    assert lines[-1] == ("| jet_on_wall/b_over_dp_20 | mean_0.1pc | - (unstable) | density error at 0.075 s | 394 | "
                         "0.3 | 8 | 2 |")
