"""The cantilever under a dead load, settled to static (config/cantilever_loaded.yaml): large deflection against
the elastica. What its file cannot say: the load, its ramp and the damping that follow from the beam's first mode,
and the reference.

The cantilever scene's beam and clamp, at rest, with a vertical load fixed in direction (a dead load) that ramps in
over `load_ramp_periods` periods of the first mode, and mass-proportional damping (`damping_ratio` of the first mode)
that settles it. The load (`load_kind`): distributed, q per length shared by every moving particle like a weight
(alpha = q L^3 / (E I), I = W H^3 / 12: linear at alpha = 0.05, deflection alpha L / 8; at alpha = 4 the free end
drops 0.43 L and turns 34 degrees, at 8 0.64 L and 54 degrees, the regime of Antoci's gate, whose free end opens
36-46 mm over 79 mm), or a force P on the free end's last layer (the probe 'tip'; alpha = P L^2 / (E I): at
alpha = 2, 0.49 L and 45 degrees). Measured: both schemes lose the loaded tip layer at alpha = 2 on a beam of
L/H = 5 (it tears off the beam: a concentrated dead load on one particle layer), so the distributed load is the
case. Judged on the settled free end (the tip layer's mean over the last quarter) against the elastica of the same
load (answers/references.py: Euler-Bernoulli with exact rotation, no shear), its vertical and horizontal
displacement; a tip load acts on the last layer's centres, dp/2 short of the free end, so its reference is the
elastica of length L - dp/2 under the same P. What a 3D beam of L/H = 10 adds to the elastica (shear, the width's
bending stiffness, the clamp) is about the same at every load, so the change of the error from the linear rung to
the large one is what large rotation does to the solid scheme.
"""
import math

import numpy as np

from ...answers.references import beam_theory_frequency, elastica_tip
from . import Case, cantilever, probe_named

SETTLED_FRACTION = 0.25


def first_mode_omega(values):
    """Euler-Bernoulli first bending mode of the beam, rad/s (references.beam_theory_frequency)."""
    return 2.0 * math.pi * beam_theory_frequency(values["geometry.length"], values["geometry.thickness"],
                                                 values["solid.young_modulus"], values["solid.density"])


def total_load(values):
    """The load's resultant [N]: P = alpha E I / L^2 (tip), or q L = alpha E I / L^2 too (distributed)."""
    length, thickness, width = (values[f"geometry.{k}"] for k in ("length", "thickness", "width"))
    return values["geometry.load_parameter"] * values["solid.young_modulus"] * width * thickness ** 3 / 12.0 \
        / length ** 2


def load(values, built):
    """The dead load on the free end's layer (tip) or shared by every moving particle, down; ramped in over
    load_ramp_periods of the first mode."""
    solid = built.solid
    loaded = (probe_named(built.probes, "tip").indices if values["geometry.load_kind"] == "tip"
              else np.flatnonzero(solid.movable))
    force = np.zeros((solid.count, 3))
    force[loaded, 2] = -total_load(values) / len(loaded)
    return force, values["geometry.load_ramp_periods"] * 2.0 * math.pi / first_mode_omega(values)


def relaxation(values, built):
    """The beam's mass-proportional damping, damping_ratio of its first mode's critical; no water."""
    return 2.0 * values["geometry.damping_ratio"] * first_mode_omega(values), 0.0


def evaluate(series, values):
    """The free end's settled displacement (the tip layer's mean; z down and x back are positive here) against
    the elastica's at the same alpha."""
    t = series["time"]
    settled = t >= t[-1] * (1.0 - SETTLED_FRACTION)
    length = values["geometry.length"]
    down = -series["tip_dz"][settled]
    back = -series["tip_dx"][settled]
    distributed = values["geometry.load_kind"] == "distributed"
    # a tip load acts on the last layer's centres, dp/2 short of the free end; a distributed one over the whole L
    arm = length if distributed else length - 0.5 * values["numerics.spacing"]
    ref = elastica_tip(values["geometry.load_parameter"] * (arm / length) ** 2, distributed=distributed)
    measured_down, measured_back = float(down.mean()), float(back.mean())
    out = {"tip_deflection_m": measured_down, "tip_pull_back_m": measured_back,
           "tip_deflection_swing_m": float(down.max() - down.min()), "settled_from_s": float(t[settled][0]),
           "tip_deflection_over_length": measured_down / length,
           "load_arm_m": arm, "elastica_deflection_m": ref["deflection"] * arm,
           "elastica_pull_back_m": ref["pull_back"] * arm, "elastica_tip_rotation_deg": math.degrees(ref["rotation"]),
           "linear_deflection_over_length": values["geometry.load_parameter"] / (8.0 if distributed else 3.0),
           "reference": "the elastica (Euler-Bernoulli, exact rotation, no shear) under the same dead load, "
                        "alpha = q L^3 / (E I) or P L^2 / (E I), I = W H^3 / 12 (answers/references.py: "
                        "elastica_tip)",
           "error_metric": "relative error of the settled free end's vertical deflection against the elastica's"}
    error = measured_down / (ref["deflection"] * arm) - 1.0
    out["pull_back_error"] = (measured_back / (ref["pull_back"] * arm) - 1.0 if ref["pull_back"] > 1e-3
                              else None)
    out.update({"error_signed": error, "error": abs(error)})
    return out


CASE = Case("cantilever_loaded", check=cantilever.check, load=load, relaxation=relaxation, sample=cantilever.sample,
            evaluate=evaluate)
