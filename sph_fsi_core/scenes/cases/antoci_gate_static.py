"""Antoci's gate held static under its water (config/antoci_gate_static.yaml): the coupled gate against FE, with
nothing moving in the end. What its file cannot say: the relaxation rates from the gate's first mode and the
column's breathing mode, and the reference.

The third of the gate's verification cases. Antoci et al. 2007's rubber gate (config/antoci_gate.yaml) with the gap
under it closed (the free end stands on the floor, so no water passes) and gravity reduced to 1 m/s^2, so the water at
rest pushes the free end about 5 % of the gate's length (3.9 mm against FE; 38 mm at 9.81, far beyond a linear
reference). Settled, the free end deflects as under the water's hydrostatic pressure rho_f g (H - z) on its wet face:
the answer of config/antoci_gate_loaded.yaml (the same gate under that pressure directly) and of plane-strain FE of the
free length (answers/fe_reference.py). The three together separate the load transfer (coupled against loaded) from the
gate's bending with 3-4 particles through it (loaded against FE).

Settling, as the hydrostatic plate's: the gate's mass-proportional damping (`damping_ratio` of its first dry
mode's critical damping) and the water's velocity relaxation at 2 zeta omega_b of the column's breathing mode
(`water_damping_ratio` = zeta; T_b = 4 H / sqrt(g H / tolerance)), each per outer step; neither changes the
static answer. zeta = 0.3: at 1.0 the water, which moves with the gate, overdamps the gate's wet mode, and the free
end was still creeping at 0.6 s with its load 4 % short (at 5/3 mm). The load on the gate comes in pulses at the
fluid step (the correction pressure, docs/validation/OPEN.md 1.4), and the free end swings with it by about a third
of its deflection: judged on its mean over the last half of the run, and on the water's mean push on the gate
against the exact hydrostatic force.

`water_start: compressed` builds the water as the hydrostatic plate does by default (tank.compress_column): at
rest from the start, the tank's walls level with it (its file's compressed_walls: all). The gate is not compressed:
it is the solid, whose lattice is its unstressed shape.
"""
from .. import tank
from . import Case, gate

SETTLED_FRACTION = 0.5   # the last half of the run: the load's pulses average out


def relaxation(values, built):
    """The gate's mass-proportional damping (damping_ratio of its first dry mode's critical) and the water's
    relaxation at 2 zeta omega_b of the column's breathing mode (water_damping_ratio = zeta)."""
    return (2.0 * values["geometry.damping_ratio"] * gate.first_mode_omega(values),
            tank.water_relaxation_rate(values, gate.water_surface_z(values)))


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


CASE = Case("antoci_gate_static", check=gate.check, relaxation=relaxation, sample=gate.sample,
            sample_fluid=gate.sample_fluid, evaluate=evaluate)
