"""Antoci's gate held static under its water's exact pressure: the solid alone, against FE.

The twin of scenes/antoci_gate_static.py with the water replaced by the pressure it puts on the gate at rest,
p = rho_f g (H - z) on the wet face's particle layer (each particle carrying the force of its dp x dp of surface),
as scenes/clamped_plate.py does for the hydrostatic plate: the gate's bending with 3-4 particles through it, judged
apart from the fluid and the load transfer. The load ramps in over `load_ramp_periods` periods of the gate's first
dry mode and the gate's mass-proportional damping settles it. Gravity 1 m/s^2 as its twin: the free end deflects
about 5 % of the gate's length. No water, no tank: the scene has a solid only.
"""
import math

import numpy as np

from ..schema import Param
from . import gate
from .built import Built
from .antoci_gate_static import DEFAULTS as _STATIC_DEFAULTS, GEOMETRY as _STATIC_GEOMETRY
from .gate import sample  # noqa: F401  (builder interface)

PHASES = ("solid",)
CONSERVATIVE = False     # the load does work

# the static gate's keys less the water's and the tank's (this scene has neither; layout_values fills them in for
# gate.build, whose gate does not depend on them)
_NOT_HERE = ("geometry.water_damping_ratio", "geometry.water_start", "geometry.water_width",
             "geometry.downstream_length", "geometry.wall_height", "geometry.wall_layers")
GEOMETRY = [p for p in _STATIC_GEOMETRY if p.key not in _NOT_HERE] + [
    Param("geometry.water_density", 1000.0, "kg/m^3", "Density of the water whose hydrostatic pressure loads the gate",
          low=0.0, low_inclusive=False, high=1.0e5),
    Param("geometry.load_ramp_periods", 2.0, "1", "The load ramps in over this many periods of the gate's first "
          "dry mode (0: all at once)", low=0.0, high=1000.0),
]

DEFAULTS = {k: v for k, v in _STATIC_DEFAULTS.items() if not k.startswith("fluid.")}


_TWIN_TANK = {p.key: p.default for p in _STATIC_GEOMETRY if p.key in _NOT_HERE}


def layout_values(values):
    """The values gate.py's layout needs: the coupled twin's tank (its defaults; walls at least as high as the
    water) and water at this density. Only the gate is kept, and the domain box is the twin's."""
    return {**_TWIN_TANK, **values, "fluid.density": values["geometry.water_density"],
            "geometry.wall_height": max(_TWIN_TANK["geometry.wall_height"], values["geometry.water_height"])}


def check(values):
    gate.check_fit_layers(layout_values(values))


def particle_counts(values):
    """The particles build() keeps (the gate), without making them (the memory guard's estimate)."""
    return {"solid": gate.particle_counts(layout_values(values))["solid"]}


def build(values):
    v = layout_values(values)
    full = gate.build(v)
    solid = full.solid
    face, direction = gate.wet_face(v, solid.pos, solid.movable)
    dp = v["numerics.spacing"]
    depth = np.maximum(gate.water_surface_z(v) - solid.pos[face, 2], 0.0)
    load = np.zeros((solid.count, 3))     # N: the pressure on each wet particle's dp x dp of surface
    load[face, 0] = direction * v["geometry.water_density"] * abs(v["scene.gravity"][2]) * depth * dp * dp
    omega = gate.first_mode_omega(v)
    return Built(solid=solid, probes=full.probes, domain_lo=full.domain_lo, domain_hi=full.domain_hi,
                 period=full.period, clamp_mirror=full.clamp_mirror, solid_load=load,
                 load_ramp_time=v["geometry.load_ramp_periods"] * 2.0 * math.pi / omega,
                 damping_rate=2.0 * v["geometry.damping_ratio"] * omega)


def evaluate(series, values):
    return gate.evaluate_static(series, layout_values(values), values["geometry.water_density"],
                                abs(values["scene.gravity"][2]))
