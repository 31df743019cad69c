"""Water at rest on a clamped plate, coupled, against the same plate under the water's exact pressure and FE
(config/hydrostatic_plate.yaml, config/clamped_plate.yaml): a small soft plate so CI can afford it (0.2 m x 0.02 m, 4
particles through, L/t = 10 as test_solid_static_quick's, under 0.1 m of water). The benchmark's ladder is
`sph-fsi validate hydrostatic_plate` (docs/validation/studies/hydrostatic_plate/REPORT.md)."""
import pytest

from sph_fsi_core.run import run_scene
from sph_fsi_core.scene import load_scene

pytestmark = pytest.mark.slow

PLATE = ["geometry.span=0.2", "geometry.thickness=0.02", "numerics.spacing=0.005", "solid.young_modulus=1.0e8"]
WATER = ["geometry.water_height=0.1", "geometry.wall_height=0.11", "fluid.time_step=1.0e-3"]


@pytest.fixture(scope="module")
def coupled():
    # 3 breathing periods of the 0.1 m column (0.04 s each), judged on the last quarter
    return run_scene(load_scene("hydrostatic_plate", PLATE + WATER + ["scene.end_time=0.12"]), progress=False)


def test_water_load_is_the_column_weight(coupled):
    """Settled, the water presses on the plate with its weight rho_f g H L W: the 'pressure' coupling's pair
    forces carry the hydrostatic load across (-0.5 % on the span, +0.7 % with the clamps' share, measured)."""
    assert coupled["status"] == "finished" and coupled["stable"]
    assert abs(coupled["water_load_error"]) < 0.02
    assert coupled["water_load_all_n"] == pytest.approx(coupled["water_weight_n"], rel=0.02)


def test_coupled_deflection_matches_the_directly_loaded_plate(coupled):
    """The coupled plate settles where the same plate under the exact pressure rho_f g H does (the load transfer's
    error: +0.6 % measured), and both are within the solid's own error of FE (+5.0 % at L/t = 10, 4 through;
    coupled +5.6 %)."""
    direct = run_scene(load_scene("clamped_plate", PLATE + ["geometry.load_pressure=981.0", "scene.end_time=0.06"]),
                       progress=False)
    assert direct["reference_midspan_deflection_m"] == pytest.approx(coupled["reference_midspan_deflection_m"],
                                                                     rel=1e-9)
    w_coupled, w_direct = coupled["midspan_deflection_m"], direct["midspan_deflection_m"]
    assert w_coupled < 0 and w_direct < 0
    assert w_coupled / w_direct - 1.0 == pytest.approx(0.0, abs=0.02)
    assert 0.0 < coupled["error_signed"] < 0.08
    # the water's load is noisy from step to step (the correction pressure comes in pulses), the plate follows it
    # (swing 11 % of the deflection), but settled: the thirds of the window agree to 0.1 % (measured)
    assert coupled["midspan_deflection_swing_m"] < 0.25 * abs(w_coupled)
    thirds = coupled["midspan_deflection_blocks_m"]
    assert max(thirds) - min(thirds) < 0.01 * abs(w_coupled)
