"""Antoci's gate held static under its water's exact pressure (config/antoci_gate_loaded.yaml): the solid alone,
against FE. What its file cannot say: the load on the wet face, its ramp and the damping from the gate's first
mode, and the reference.

The twin of config/antoci_gate_static.yaml with the water replaced by the pressure it puts on the gate at rest,
p = rho_f g (H - z) on the wet face's particle layer (each particle carrying the force of its dp x dp of surface),
as the clamped plate's case does for the hydrostatic plate: the gate's bending with 3-4 particles through it, judged
apart from the fluid and the load transfer. The load ramps in over `load_ramp_periods` periods of the gate's first
dry mode and the gate's mass-proportional damping settles it. Gravity 1 m/s^2 as its twin: the free end deflects
about 5 % of the gate's length. No water, no tank: the scene has a solid only.
"""
import math

import numpy as np

from . import Case, gate

# the coupled twin's tank and water (config/antoci_gate_static.yaml), which this scene has not: its layout (the
# domain, the free length's water level) is the twin's
TWIN_TANK = {"geometry.water_damping_ratio": 0.3, "geometry.water_start": "lattice", "geometry.water_width": 0.1,
             "geometry.downstream_length": 0.05, "geometry.wall_height": 0.15, "geometry.wall_layers": 3}


def layout_values(values):
    """The values the gate family's layout needs: the coupled twin's tank (walls at least as high as the water)
    and water at this density."""
    return {**TWIN_TANK, **values, "fluid.density": values["geometry.water_density"],
            "geometry.wall_height": max(TWIN_TANK["geometry.wall_height"], values["geometry.water_height"])}


def check(values):
    gate.check_fit_layers(layout_values(values))


def load(values, built):
    """The water's hydrostatic pressure rho_f g (H - z) on the wet face's particle layer, each particle the force
    of its dp x dp of surface, pushing the gate away from the water; ramped in over load_ramp_periods of the gate's
    first dry mode."""
    v = layout_values(values)
    solid = built.solid
    face, direction = gate.wet_face(v, solid.pos, solid.movable)
    dp = v["numerics.spacing"]
    depth = np.maximum(gate.water_surface_z(v) - solid.pos[face, 2], 0.0)
    force = np.zeros((solid.count, 3))     # N: the pressure on each wet particle's dp x dp of surface
    force[face, 0] = direction * v["geometry.water_density"] * abs(v["scene.gravity"][2]) * depth * dp * dp
    return force, v["geometry.load_ramp_periods"] * 2.0 * math.pi / gate.first_mode_omega(v)


def relaxation(values, built):
    """The gate's mass-proportional damping, damping_ratio of its first dry mode's critical; no water."""
    return 2.0 * values["geometry.damping_ratio"] * gate.first_mode_omega(layout_values(values)), 0.0


def evaluate(series, values):
    return gate.evaluate_static(series, layout_values(values), values["geometry.water_density"],
                                abs(values["scene.gravity"][2]))


CASE = Case("antoci_gate_loaded", check=check, load=load, relaxation=relaxation, sample=gate.sample,
            evaluate=evaluate)
