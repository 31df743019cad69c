"""A solid's and a water probe's own h (solid.smoothing_ratio; probes.<name>.smoothing_ratio and kernel): the water's
kernel and h (fluid.kernel, numerics.smoothing_ratio) reach neither when they have their own."""
import numpy as np
import pytest

from sph_fsi_core.numerics.kernels import CUBIC_SPLINE
from sph_fsi_core.probes import HEIGHT_SAMPLES_PER_SPACING, shepard_pressure, surface_height
from sph_fsi_core.scene import SceneError, load_scene
from sph_fsi_core.simulation import Simulation
from sph_fsi_core.validation.cases.hydrostatic_plate import SMALL_PLATE, SMALL_PLATE_PRESSURE, SMALL_PLATE_SOLID

pytestmark = pytest.mark.usefixtures("one_numba_thread")

DP = SMALL_PLATE["geometry.thickness"] / 4
WENDLAND_2 = {"fluid.kernel": "wendland_c2", "numerics.smoothing_ratio": 2.0}
# walls and slab for h / dp 2 in every build, so that builds differ by their h alone
GEOMETRY = {"geometry.wall_layers": 4, "geometry.span_layers": 9}


def _sets(overrides):
    return [f"{k}={v}" for k, v in overrides.items()]


def test_a_solid_alone_at_its_own_h_steps_to_the_bit_as_at_that_h():
    """The small plate alone under the water's exact pressure: with numerics.smoothing_ratio 2 and its own 1.3 it is
    the plate at 1.3, step for step (the water's h reaches no solid sum), and not the plate at 2."""
    plate = {"numerics.spacing": DP, **{k: v for k, v in SMALL_PLATE.items() if k in SMALL_PLATE_SOLID},
             "geometry.load_pressure": SMALL_PLATE_PRESSURE, "geometry.span_layers": 9}
    runs = {}
    for label, extra in (("own", {"numerics.smoothing_ratio": 2.0, "solid.smoothing_ratio": 1.3}),
                         ("shared_1.3", {}), ("shared_2", {"numerics.smoothing_ratio": 2.0})):
        sim = Simulation(load_scene("clamped_plate", _sets({**plate, **extra})))
        for _ in range(6):
            sim.step()
        runs[label] = sim
    own, at_13, at_2 = runs["own"], runs["shared_1.3"], runs["shared_2"]
    assert own.solid_phase.solver.h == at_13.solid_phase.solver.h == pytest.approx(1.3 * DP, rel=1e-15)
    assert own.solid_phase.steps == at_13.solid_phase.steps != at_2.solid_phase.steps
    for name in ("pos", "vel", "stress"):
        assert np.array_equal(getattr(own.solid, name), getattr(at_13.solid, name)), name
    assert not np.array_equal(own.solid.pos, at_2.solid.pos)


def test_a_coupled_solid_keeps_its_own_h_and_the_water_pairs_take_the_waters():
    """The small plate under water with Wendland's C2 at h / dp 2 and the solid at 1.3: the solid's passes, its
    stable step and its surface (the coupling's normals) are the plate's at 1.3, the water's pairs with it (the
    coupling's lists and kernel) the water's at 2; the surface is the plate's top and bottom faces and its ends."""
    plate = {"numerics.spacing": DP, **SMALL_PLATE, **GEOMETRY}
    own = Simulation(load_scene("hydrostatic_plate", _sets({**plate, **WENDLAND_2, "solid.smoothing_ratio": 1.3})))
    shared = Simulation(load_scene("hydrostatic_plate", _sets(plate)))
    assert own.solid_h == shared.solid_h == shared.h == pytest.approx(1.3 * DP, rel=1e-15)
    assert own.h == own.coupling.h == pytest.approx(2.0 * DP, rel=1e-15)
    assert own.coupling.solid_h == own.solid_phase.solver.h == shared.solid_phase.solver.h
    assert own.coupling.kernel != shared.coupling.kernel
    assert np.array_equal(own.solid.pos, shared.solid.pos)
    assert np.array_equal(own.coupling.surface, shared.coupling.surface)
    assert own.solid_phase.solver.stable_dt() == shared.solid_phase.solver.stable_dt()
    # the surface: the moving plate's top and bottom layers (its ends face the clamps, which are solid too)
    s = own.solid
    z = np.round(s.pos[:, 2] / DP - 0.5).astype(int)
    faces = s.movable & ((z == z[s.movable].min()) | (z == z[s.movable].max()))
    assert np.array_equal(own.coupling.surface & s.movable, faces)


@pytest.mark.parametrize("key, message", [
    ("solid.smoothing_ratio=0.5", r"solid.smoothing_ratio = 0.5: out of range; allowed: in \[1, 2\], or 0"),
    ("solid.smoothing_ratio=2.5", r"solid.smoothing_ratio = 2.5: out of range; allowed: in \[0, 2\]"),
])
def test_a_solid_smoothing_ratio_out_of_range_is_refused_by_name(key, message):
    with pytest.raises(SceneError, match=message):
        load_scene("hydrostatic_plate", [key])


def _level_scene(tmp_path, gauge, probes=()):
    import yaml
    tree = {"scene": {"builder": "geometry", "end_time": 0.01}, "numerics": {"spacing": 0.01, "smoothing_ratio": 2.0},
            "fluid": {"kernel": "wendland_c2", "time_step": 0.001}, "output": {"timeseries_interval": 0.001},
            "parts": [{"name": "tank", "role": "wall", "shape": "box", "size": [0.3, 0.1, 0.2],
                       "position": [0.15, 0.05, 0.1], "side": "outside", "open": "+z"},
                      {"name": "water", "role": "water", "shape": "box", "size": [0.3, 0.1, 0.1],
                       "position": [0.15, 0.05, 0.05]}],
            "probes": [{"name": "level", "kind": "water_height", "position": [0.15, 0.05, 0.0], **gauge}, *probes]}
    path = tmp_path / "level.yaml"
    path.write_text(yaml.safe_dump(tree, sort_keys=False))
    return str(path)


def test_a_water_height_gauge_reads_with_its_own_kernel_and_h(tmp_path):
    """A still level 0.1 m deep (10 layers) under Wendland's C2 at h / dp 2: a gauge with the cubic spline at 1.3 dp
    reads what surface_height reads with them by hand, the water's own gauge what it reads with the water's; both
    the level within a spacing."""
    own = Simulation(load_scene(_level_scene(tmp_path, {"kernel": "cubic_spline", "smoothing_ratio": 1.3})))
    water_pos, water_volume, wall_pos, wall_volume = own.fluid_phase.filling_particles()
    step = 0.01 / HEIGHT_SAMPLES_PER_SPACING
    by_hand = {h: surface_height(0.15, 0.05, 0.0, water_pos, water_volume, wall_pos, wall_volume, h, kernel, step)
               for h, kernel in ((0.013, CUBIC_SPLINE), (0.02, own.fluid_kernel))}
    assert own.probe_readings()["level"][1]["height"] == by_hand[0.013]
    shared = Simulation(load_scene(_level_scene(tmp_path, {})))
    assert shared.probe_readings()["level"][1]["height"] == by_hand[0.02]
    assert by_hand[0.013] != by_hand[0.02]
    for height in by_hand.values():
        assert height == pytest.approx(0.1, abs=0.01)


def test_a_pressure_probe_reads_with_its_own_kernel_and_h(tmp_path):
    """Two pressure probes at one point on the tank's end wall, one with the water's kernel and h (Wendland's C2 at
    2 dp), one with the cubic spline at 1.3 dp: after a fluid step that corrects each reads Shepard's average of
    that step's pressures with its own (by hand), and the two differ."""
    at = [0.0, 0.05, 0.03]
    probes = [{"name": "wall_p", "kind": "pressure", "position": at},
              {"name": "wall_p_own", "kind": "pressure", "position": at, "kernel": "cubic_spline",
               "smoothing_ratio": 1.3}]
    sim = Simulation(load_scene(_level_scene(tmp_path, {}, probes)))
    sim.step()
    while sim.fluid_phase.last_iterations == 0:     # to a step that corrects (and so has pressures); one fluid
        sim.step()                                  # step an outer step: its mean is that step's reading
    f, point = sim.fluid, np.array([at])
    read = sim.probe_readings()
    own = shepard_pressure(point, f.pos, f.mass, f.rho, f.pressure, 0.013, CUBIC_SPLINE)[0]
    water = shepard_pressure(point, f.pos, f.mass, f.rho, f.pressure, 0.02, sim.fluid_kernel)[0]
    # the outer step's mean of its one fluid step: dt p / dt, to round-off
    assert read["wall_p_own"][1]["pressure"] == pytest.approx(own, rel=1e-12)
    assert read["wall_p"][1]["pressure"] == pytest.approx(water, rel=1e-12)
    assert own > 0.0 and water > 0.0 and abs(own - water) > 1.0


def test_a_probe_smoothing_ratio_below_one_or_an_unknown_kernel_is_refused_by_name(tmp_path):
    with pytest.raises(SceneError, match=r"probes.level.smoothing_ratio = 0.5: out of range; allowed: in \[1, 2\]"):
        load_scene(_level_scene(tmp_path, {"smoothing_ratio": 0.5}))
    with pytest.raises(SceneError, match=r"probes.level.kernel = 'gauss': not a known choice; allowed: one of "
                                         r"'water', 'cubic_spline', 'wendland_c2'"):
        load_scene(_level_scene(tmp_path, {"kernel": "gauss"}))
