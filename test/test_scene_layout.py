"""Bad input for the fluid and coupled scenes, and the layout check every built scene passes before its first step:
bodies that overlap or leave the domain, and an empty scene, are refused with a message naming what is wrong.
(The cantilever's table of bad input is in test_scene.py.)"""
import numpy as np
import pytest
from scipy.spatial import cKDTree

from sph_fsi_core.scene import builtin_scenes, load_scene
from sph_fsi_core.scenes import BUILDERS
from sph_fsi_core.scenes.built import Built, check_layout
from sph_fsi_core.scenes.tank import bottom_compression
from sph_fsi_core.schema import SceneError
from sph_fsi_core.simulation import Simulation
from sph_fsi_core.state import FluidState, SolidState, WallState

# (scene, overrides, words the message must contain); every one refused before the first step
BAD_SCENES = [
    ("dam_break", ["geometry.tank_length=0.05"], ["geometry.tank_length", "allowed"]),      # column through the wall
    ("dam_break", ["geometry.wall_height=0.1"], ["geometry.wall_height", "allowed"]),       # water above the walls
    ("dam_break", ["geometry.column_width=0.05"], ["geometry.column_width", "allowed"]),    # not whole spacings
    ("dam_break", ["solid.young_modulus=1e6"], ["solid.young_modulus"]),                   # no solid in a dam break
    ("dam_break", ["coupling.gamma=10"], ["coupling.gamma"]),                              # nor a coupling
    ("hydrostatic", ["geometry.wall_height=0.05"], ["geometry.wall_height", "allowed"]),
    ("hydrostatic", ["geometry.wall_layers=1"], ["geometry.wall_layers", "allowed"]),      # kernel reaches past
    ("hydrostatic", ["geometry.span_layers=2"], ["geometry.span_layers", "allowed"]),      # periodic slab too thin
    ("hydrostatic", ["fluid.density_tolerance=0"], ["fluid.density_tolerance", "allowed"]),
    ("hydrostatic", ["fluid.density=-1000"], ["fluid.density", "allowed"]),
    ("elastic_gate", ["geometry.wall_height=0.03"], ["geometry.wall_height", "allowed"]),
    ("elastic_gate", ["numerics.spacing=0.003"], ["geometry.gate_thickness", "allowed"]),  # spacing beyond the body
    ("elastic_gate", ["geometry.gate_clearance=0.0003"], ["geometry.gate_clearance", "allowed"]),
    ("elastic_gate", ["geometry.gate_clearance=-0.002"], ["geometry.gate_clearance", "allowed"]),
    ("elastic_gate", ["coupling.gamma=-1"], ["coupling.gamma", "allowed"]),
    ("elastic_gate", ["coupling.model=glue"], ["coupling.model", "allowed"]),
    ("elastic_gate", ["solid.poisson_ratio=0.5"], ["solid.poisson_ratio", "allowed"]),
    ("antoci_gate", ["geometry.mirror=maybe"], ["geometry.mirror", "allowed"]),
    # two particles through the gate: the default scheme's quadratic fit is not determined (3 needed)
    ("elastic_gate", ["numerics.spacing=0.002"], ["numerics.spacing = 0.002", "2 particles", "needs 3",
                                                  "allowed numerics.spacing <= 0.001333", "gray2001"]),
    ("antoci_gate", ["numerics.spacing=0.0025"], ["2 particles", "allowed numerics.spacing <= 0.001667"]),
    ("antoci_gate_loaded", ["numerics.spacing=0.0025"], ["2 particles", "solid.scheme = quadratic_gradient"]),
    ("cantilever", ["coupling.gamma=10"], ["coupling.gamma"]),                             # no fluid, no coupling
    ("cantilever", ["fluid.density_tolerance=0.01"], ["fluid.density_tolerance"]),
]


@pytest.mark.parametrize("scene, overrides, words", BAD_SCENES,
                         ids=[f"{s}:{o[0]}" for s, o, _ in BAD_SCENES])
def test_bad_scene_input_is_refused_before_the_first_step(scene, overrides, words):
    with pytest.raises(SceneError) as info:
        Simulation(load_scene(scene, overrides))
    for word in words:
        assert word in str(info.value), (word, str(info.value))


@pytest.mark.parametrize("scene", sorted(builtin_scenes()))
def test_every_builtin_scene_is_one_lattice_inside_its_domain(scene):
    """Every particle of every body (the release plates too) has its nearest neighbour (of any body) exactly one
    spacing away, lies inside the domain box, and a periodic axis closes the lattice: each body spans the period less one spacing. The
    layout check passes. Water built compressed (geometry.water_start, tank.compress_column) and the walls beside
    it are closer along z, by at most the compression the correction holds at the floor (twice the tolerance on the
    mean)."""
    spec = load_scene(scene)
    dp = spec["numerics.spacing"]
    built = BUILDERS[spec.builder].build(spec.values)
    bodies = [s.pos for s in (built.solid, built.fluid, built.walls, built.release_walls)
              if s is not None and len(s.pos)]
    pos = np.concatenate(bodies)
    assert len(pos) > 1000
    nearest, _ = cKDTree(pos).query(pos, k=2)
    if spec.values.get("geometry.water_start") == "compressed":
        squeezed = dp * (1.0 - bottom_compression(spec["fluid.density_tolerance"], spec["fluid.tolerance_on"]))
        assert np.all(nearest[:, 1] >= squeezed * (1.0 - 1e-9)) and np.all(nearest[:, 1] <= dp * (1.0 + 1e-9))
        assert np.sum(nearest[:, 1] < dp * (1.0 - 1e-9)) > len(built.fluid.pos) // 2
    else:
        assert nearest[:, 1] == pytest.approx(np.full(len(pos), dp), rel=1e-9)
    assert np.all(pos.min(axis=0) >= built.domain_lo) and np.all(pos.max(axis=0) <= built.domain_hi)
    for axis in np.flatnonzero(built.period > 0.0):
        assert built.period[axis] / dp == pytest.approx(round(built.period[axis] / dp), abs=1e-9)
        for body in bodies:
            assert np.ptp(body[:, axis]) + dp == pytest.approx(built.period[axis], rel=1e-9)
    assert check_layout(built, dp) is None


def _block(n, dp, offset):
    axes = [(np.arange(n) + 0.5) * dp + o for o in offset]
    return np.stack(np.meshgrid(*axes, indexing="ij"), axis=-1).reshape(-1, 3)


def _built(fluid_offset, dp=0.01):
    solid = SolidState.at_rest(_block(4, dp, (0.0, 0.0, 0.0)), np.ones(64, bool), 1000.0, dp)
    fluid = FluidState.at_rest(_block(4, dp, fluid_offset), 1000.0, dp)
    walls = WallState.lattice(_block(2, dp, (0.0, 0.0, -0.03)), 1000.0, dp)
    return Built(solid=solid, fluid=fluid, walls=walls, domain_lo=np.full(3, -0.1), domain_hi=np.full(3, 0.2))


@pytest.mark.parametrize("gap", [0.01, 0.0055])
def test_bodies_more_than_half_a_spacing_apart_pass(gap):
    """The solid block's face is at x = 0.035: a fluid block one spacing or 0.55 spacings from it passes."""
    built = _built((0.035 + gap - 0.005, 0.0, 0.0))
    assert cKDTree(built.solid.pos).query(built.fluid.pos)[0].min() == pytest.approx(gap, rel=1e-9)
    assert check_layout(built, 0.01) is None


def test_bodies_less_than_half_a_spacing_apart_are_refused():
    """0.45 spacings apart: the 4 x 4 particles of the facing layers, one pair each."""
    with pytest.raises(SceneError, match=r"overlap: 16 particle pair\(s\) closer than half numerics.spacing = 0.005 m"):
        check_layout(_built((0.035 + 0.0045 - 0.005, 0.0, 0.0)), 0.01)


def test_overlapping_bodies_are_refused_naming_both_particles():
    with pytest.raises(SceneError) as info:
        check_layout(_built((0.02, 0.0, 0.0)), 0.01)   # two of the four layers on top of the solid's
    message = str(info.value)
    assert "overlap" in message and "32 particle pair(s)" in message
    assert "solid particle" in message and "fluid particle" in message and "allowed" in message


def test_a_body_outside_the_domain_is_refused():
    with pytest.raises(SceneError) as info:
        check_layout(_built((0.5, 0.0, 0.0)), 0.01)
    message = str(info.value)
    assert "64 particle(s) outside the scene's domain" in message and "fluid particle 0" in message


def test_an_empty_scene_is_refused():
    with pytest.raises(SceneError, match="no particles"):
        check_layout(Built(domain_lo=np.zeros(3), domain_hi=np.ones(3)), 0.01)


def test_gate_without_a_gap_stands_on_the_floor():
    """geometry.gate_clearance = 0: the gate's lowest layer sits one spacing above the floor's top layer, the slot
    under it is gone, and the layout check passes."""
    coarse = ["numerics.spacing=0.002", "geometry.gate_clamp_height=0.004", "solid.scheme=gray2001"]
    spec = load_scene("elastic_gate", coarse + ["geometry.gate_clearance=0"])
    with_gap = Simulation(load_scene("elastic_gate", coarse))
    sim = Simulation(spec)
    assert sim.solid.pos[:, 2].min() == pytest.approx(0.001)
    assert sim.walls.pos[sim.walls.pos[:, 2] < 0, 2].max() == pytest.approx(-0.001)
    # the slot under the gate (2 x 6 x 1 sites at 2 mm: 2 through the gate, 6 across the narrowest slab) is water
    # in the gapped gate only
    assert with_gap.fluid.count - sim.fluid.count == 2 * 6 * 1
