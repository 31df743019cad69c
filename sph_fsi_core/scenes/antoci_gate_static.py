"""Antoci's gate held static under its water: the coupled gate against FE, with nothing moving in the end.

The third of the gate's verification cases. Antoci et al. 2007's rubber gate (scenes/antoci_gate.py) with the gap under it
closed (the free end stands on the floor, so no water passes) and gravity reduced to 1 m/s^2, so the water at rest
pushes the free end about 5 % of the gate's length (3.9 mm against FE; 38 mm at 9.81, far beyond a linear
reference). Settled, the free end deflects as under the water's hydrostatic pressure rho_f g (H - z) on its wet
face: the answer of scenes/antoci_gate_loaded.py (the same gate under that pressure directly) and of plane-strain
FE of the free length (answers/fe_reference.py). The three together separate the load transfer (coupled against
loaded) from the gate's bending with 3-4 particles through it (loaded against FE).

Settling, as scenes/hydrostatic_plate.py: the gate's mass-proportional damping (`damping_ratio` of its first dry
mode's critical damping) and the water's velocity relaxation at 2 zeta omega_b of the column's breathing mode
(`water_damping_ratio` = zeta; T_b = 4 H / sqrt(g H / tolerance)), each per outer step; neither changes the
static answer. zeta = 0.3: at 1.0 the water, which moves with the gate, overdamps the gate's wet mode, and the free
end was still creeping at 0.6 s with its load 4 % short (at 5/3 mm). The load on the gate comes in pulses at the
fluid step (the correction pressure, docs/validation/OPEN.md 1.4), and the free end swings with it by about a third
of its deflection: judged on its mean over the last half of the run, and on the water's mean push on the gate
against the exact hydrostatic force.

`water_start: compressed` builds the water as scenes/hydrostatic_plate.py does by default (tank.compress_column): at
rest from the start, the tank's walls beside it level with it. The gate is not compressed: it is the solid, whose
lattice is its unstressed shape.
"""

from ..schema import Param
from . import gate, tank
from .antoci_gate import DEFAULTS as _ANTOCI_DEFAULTS
from .gate import CONSERVATIVE, PHASES, particle_counts, sample, sample_fluid  # noqa: F401  (builder interface)

GEOMETRY = gate.geometry_params(dict(
    gate_thickness=0.005, gate_length=0.079, gate_clearance=0.0, gate_clamp_height=0.0685, water_width=0.1,
    water_height=0.14, downstream_length=0.05, wall_height=0.15, span=0.0, mirror=True)) + gate.static_params(1.0, 0.3) + [
    Param("geometry.water_start", "lattice", "", "How the water is built: 'lattice' on its lattice with no pressure "
          "(the paper's; it first falls into the correction's band), 'compressed' as the density correction holds it "
          "at rest (compression linear in depth to the tolerance at the floor) with the tank's walls compressed the "
          "same way (tank.compress_column); the gate stays on its lattice", kind="str", choices=tank.WATER_STARTS)]

SETTLED_FRACTION = 0.5   # the last half of the run: the load's pulses average out

DEFAULTS = {**_ANTOCI_DEFAULTS, "scene.end_time": 1.0, "scene.gravity": (0.0, 0.0, -1.0),
            "numerics.spacing": 0.005 / 3, "output.timeseries_interval": 1.0e-3, "output.snapshot_interval": 0.0}


def check(values):
    gate.check(values)


def build(values):
    built = gate.build(values)
    tank.build_water_start(values, 0.0, gate.water_surface_z(values), built.fluid.pos, built.walls.pos)
    built.damping_rate = 2.0 * values["geometry.damping_ratio"] * gate.first_mode_omega(values)
    built.fluid_damping_rate = tank.water_relaxation_rate(values, gate.water_surface_z(values))
    return built


def evaluate(series, values):
    """The free end against FE (gate.evaluate_static), and the water's settled push on the gate (the movable
    particles: the free length) against the hydrostatic force on its wet face, rho_f g W (H L - L^2 / 2) for a
    gate standing on the floor (exact at rest)."""
    g = abs(values["scene.gravity"][2])
    out = gate.evaluate_static(series, values, values["fluid.density"], g, settled_fraction=SETTLED_FRACTION)
    exact = float(gate.hydrostatic_gate_load(gate.water_surface_z(values), values))
    t = series["time"]
    settled = t >= t[-1] * (1.0 - SETTLED_FRACTION)
    push = 1.0 if values["geometry.mirror"] else -1.0
    load = float(push * series["coupling_force_x"][settled].mean())
    out.update({"water_load_n": load, "water_load_exact_n": exact, "water_load_error": load / exact - 1.0})
    return out
