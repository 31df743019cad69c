"""What the gate scenes share (config/elastic_gate.yaml, antoci_gate.yaml, antoci_gate_static.yaml,
antoci_gate_loaded.yaml): a water column held by an elastic plate clamped at its top, released through the gap under
its free end. Their files lay the gate, the water, the tank and the plug out; this module has what the four cases'
code needs of that layout (its keys rounded to whole spacings, the refusals), their common columns (the free end's
velocity, the water past the gate) and the static gates' reference (plane-strain FE of the free length under the
water's hydrostatic pressure).

The layout, on one cubic lattice of spacing dp with sites at (i + 1/2) dp:
- gate: x in [0, T], z from the clearance G to G + L (its free, movable part), then `gate_clamp_height` more of
  fixed solid particles (the clamp; for Antoci's gate the rigid wall the gate hangs from, up to the walls' top);
  y across the whole periodic slab: the plate spans the channel, so water passes only under it;
- water: x in [T, T + A] on the gate's +x side, z in [0, H], plus the slot under the gate (x in [0, T], z < G);
- tank: a floor and end walls of `wall_layers` layers (>= 2h), the upstream end wall at x = T + A, the downstream one
  at x = -downstream_length, open top; periodic along y (no side walls), like the fluid scenes' slabs;
- plug: on the gate's dry side, closing the gap and rising `wall_layers` more along the gate's face, a gate part that
  holds the water while it settles (fluid.settle_time) and is gone at t = 0.
`mirror`: x -> -x, so the water sits on the gate's -x side (Antoci's experiment, whose data are for a gate bending
towards +x). Probe 'tip': the gate's free end, the lowest movable layer (all of its particles across x and y); its
mean displacement in x and z is the free-end displacement of Satake et al.'s Fig. 7 and Antoci's data.
"""
import math

import numpy as np

from ...schema import SceneError, solid_smoothing_ratio, widest_smoothing_ratio
from . import probe_named
from .hydrostatic import check_walls_and_span


def _round_layers(extent, dp, key, at_least=1):
    n = int(round(extent / dp))
    if n < at_least:
        raise SceneError(f"numerics.spacing = {dp:g} m is too coarse for {key} = {extent:g} m; allowed: at most "
                         f"{extent / at_least:g} m ({at_least} particle layers)")
    return n


def layer_counts(values):
    """The layers of each of the layout's extents (the keys rounded to whole spacings; SceneError below the least)."""
    dp = values["numerics.spacing"]
    h = solid_smoothing_ratio(values) * dp            # the solid's: its kernel must not reach past the clamp
    return dict(
        nt=_round_layers(values["geometry.gate_thickness"], dp, "geometry.gate_thickness", 2),
        nl=_round_layers(values["geometry.gate_length"], dp, "geometry.gate_length", 4),
        ng=(_round_layers(values["geometry.gate_clearance"], dp, "geometry.gate_clearance", 1)
            if values["geometry.gate_clearance"] > 0.0 else 0),
        nc=max(_round_layers(values["geometry.gate_clamp_height"], dp, "geometry.gate_clamp_height", 1),
               math.ceil(2.0 * h / dp - 1e-9)),
        na=_round_layers(values["geometry.water_width"], dp, "geometry.water_width", 2),
        nh=_round_layers(values["geometry.water_height"], dp, "geometry.water_height", 2),
        nd=_round_layers(values["geometry.downstream_length"], dp, "geometry.downstream_length", 2),
        nw=int(math.ceil(values["geometry.wall_height"] / dp - 1e-9)),
        ny=span_layers(values))


def span_layers(values):
    """Layers across the slab: geometry.span in whole spacings, at least the periodic minimum 2 (2h + skin) / dp."""
    dp = values["numerics.spacing"]
    cutoff = (2.0 + values["numerics.neighbour_skin"]) * widest_smoothing_ratio(values) * dp
    need = math.ceil(2.0 * cutoff / dp - 1e-9)
    return max(need, int(round(values["geometry.span"] / dp)))


# particle layers through the gate the quadratic fit needs to be determined (solid/fitted_gradient.py)
QUADRATIC_FIT_LAYERS = 3


def check(values):
    """The gate scenes' refusals: a layer count below its least, walls thinner than 2h or below the water, a slab too
    narrow, a gate too thin for the quadratic fit."""
    c = layer_counts(values)
    check_walls_and_span({**values, "geometry.periodic_y": True, "geometry.span_layers": c["ny"]})
    if c["nw"] < c["nh"]:
        raise SceneError(f"geometry.wall_height = {values['geometry.wall_height']:g} m: below the water; allowed: "
                         f"at least geometry.water_height")
    check_fit_layers(values)


def check_fit_layers(values):
    """The quadratic fit needs QUADRATIC_FIT_LAYERS particles through the gate; with fewer it is not determined
    across the gate and falls back to the linear fit, and the coupled gate stalls (docs/validation/OPEN.md, sec. 2)."""
    nt = layer_counts(values)["nt"]
    if values["solid.velocity_gradient"] == "quadratic" and nt < QUADRATIC_FIT_LAYERS:
        dp = values["numerics.spacing"]
        raise SceneError(
            f"numerics.spacing = {dp:g} m leaves {nt} particles through geometry.gate_thickness = "
            f"{values['geometry.gate_thickness']:g} m; solid.velocity_gradient = quadratic (solid.scheme = "
            f"{values['solid.scheme']}) needs {QUADRATIC_FIT_LAYERS}: allowed numerics.spacing <= "
            f"{values['geometry.gate_thickness'] / QUADRATIC_FIT_LAYERS:.4g} m, or solid.scheme = gray2001")


def effective_geometry(values):
    """The lattice's actual extents (the keys rounded to whole spacings), m."""
    dp = values["numerics.spacing"]
    c = layer_counts(values)
    return {"gate_thickness_m": c["nt"] * dp, "gate_free_length_m": c["nl"] * dp, "gate_clearance_m": c["ng"] * dp,
            "clamp_height_m": c["nc"] * dp, "water_width_m": c["na"] * dp, "water_height_m": c["nh"] * dp,
            "span_m": c["ny"] * dp}


def sample(solid, probes, vel):
    """Extra time-series columns: the free end's mean velocity in x and z (vel: Simulation.solid_velocity)."""
    tip = probe_named(probes, "tip").indices
    return {"tip_vx": float(vel[tip, 0].mean()), "tip_vz": float(vel[tip, 2].mean())}


def sample_fluid(sim):
    """Extra time-series column: the fraction of the water on the gate's dry side (it passed under the gate)."""
    x = sim.fluid.pos[:, 0]
    dry = x > 0.0 if sim.spec.values["geometry.mirror"] else x < 0.0
    return {"water_past_gate": float(dry.mean())}


def sigma_zz(solid):
    """sigma_zz = S_zz - p on every solid particle, Pa (the paper's sigma^22)."""
    return solid.stress[:, 2] - solid.pressure


# ---- the gate held static under its water (antoci_gate_static, antoci_gate_loaded) ---------------------------
CANTILEVER_BETA_L = 1.8751040687    # first clamped-free bending mode (Euler-Bernoulli)


def first_mode_omega(values):
    """omega_1 = (beta_1 L)^2 / L^2 sqrt(D / (rho T)) of the gate's free length as a plane-strain cantilever, rad/s
    (L and T rounded to whole spacings, as built)."""
    g = effective_geometry(values)
    length, thickness = g["gate_free_length_m"], g["gate_thickness_m"]
    nu = values["solid.poisson_ratio"]
    rigidity = values["solid.young_modulus"] * thickness ** 3 / (12.0 * (1.0 - nu * nu))
    return CANTILEVER_BETA_L ** 2 / length ** 2 * math.sqrt(rigidity / (values["solid.density"] * thickness))


def wet_face(values, pos, movable):
    """Indices of the gate's movable particles in its layer next to the water, and the unit x direction in which
    the water pushes them (+1 for a mirrored gate, whose water is on its -x side)."""
    dp = values["numerics.spacing"]
    nt = layer_counts(values)["nt"]
    x_wet = (nt - 0.5) * dp
    sign = 1.0
    if values["geometry.mirror"]:
        x_wet, sign = -x_wet, -1.0
    face = np.flatnonzero(movable & np.isclose(pos[:, 0], x_wet))
    return face, -sign


def water_surface_z(values):
    return layer_counts(values)["nh"] * values["numerics.spacing"]


def hydrostatic_gate_load(level, values):
    """The x force [N] of water at rest up to z = `level` on the wet face of the straight gate's free length (from
    its clearance up to the clamp), rho_f g W (H (top - c) - (top^2 - c^2) / 2) with top = H clipped to [c, c + L];
    exact for the gate at rest, and the load of the current level for a moving one."""
    geometry = effective_geometry(values)
    length, width = geometry["gate_free_length_m"], geometry["span_m"]
    clearance = geometry["gate_clearance_m"]
    g = abs(values["scene.gravity"][2])
    top = np.clip(level, clearance, clearance + length)     # a level below the gate wets none of it
    return values["fluid.density"] * g * width * (level * (top - clearance) - 0.5 * (top ** 2 - clearance ** 2))


def static_tip_reference(values, water_density, gravity):
    """The static deflection (m, + along the water's push) where the 'tip' probe sits, under the hydrostatic
    pressure of the water at rest, p = rho_f g (H - z), on the wet face of the free length, and the gate's own
    weight along it: plane-strain FE of the built gate (answers/fe_reference.py), with the Euler-Bernoulli value
    of the same load beside it.

    The probe is the lowest particle layer, whose centres sit half a spacing above the body's free end: the FE is
    read there, at mid-thickness, not at the end itself (the slope there, 4/3 of the deflection over L, makes the
    difference 1.4 % at 3 particles through). Elements of dp / 4 put a node on that point."""
    from ...answers.fe_reference import cantilever_strip_fe_deflection
    g = effective_geometry(values)
    length, thickness, clearance = g["gate_free_length_m"], g["gate_thickness_m"], g["gate_clearance_m"]
    dp = values["numerics.spacing"]
    height = water_surface_z(values)
    clamp_z = clearance + length
    probe = length - 0.5 * dp

    def pressure(x):            # x: distance from the clamp face down the gate
        return water_density * gravity * np.maximum(height - (clamp_z - x), 0.0)

    fe = cantilever_strip_fe_deflection(length, thickness, values["solid.young_modulus"],
                                        values["solid.poisson_ratio"], pressure,
                                        values["solid.density"] * gravity, element_size=0.25 * dp, probe_x=probe)
    # Euler-Bernoulli with a distributed load q(s): w(x) = integral q(s) G(x, s) ds, G(x, s) = s^2 (3 x - s) / (6 D)
    # for s <= x and x^2 (3 s - x) / (6 D) beyond, s and x from the clamp
    nu = values["solid.poisson_ratio"]
    rigidity = values["solid.young_modulus"] * thickness ** 3 / (12.0 * (1.0 - nu * nu))
    s = np.linspace(0.0, length, 4001)
    green = np.where(s <= probe, s * s * (3.0 * probe - s), probe * probe * (3.0 * s - probe)) / (6.0 * rigidity)
    integrand = pressure(s) * green
    beam = float(np.sum(0.5 * (integrand[1:] + integrand[:-1]) * np.diff(s)))
    return {"fe_tip_deflection_m": fe["tip_deflection_m"], "fe_free_end_deflection_m": fe["free_end_deflection_m"],
            "beam_tip_deflection_m": beam, "probe_from_clamp_m": probe, "fe_elements": list(fe["elements"])}


def evaluate_static(series, values, water_density, gravity, settled_fraction=0.25):
    """The free end's settled x displacement (mean over the last `settled_fraction` of the run, + along the water's
    push) against the plane-strain FE value (static_tip_reference)."""
    t = series["time"]
    settled = t >= t[-1] * (1.0 - settled_fraction)
    push = -1.0 if not values["geometry.mirror"] else 1.0
    tip = push * series["tip_dx"][settled]
    measured = float(tip.mean())
    out = {"tip_deflection_m": measured, "tip_deflection_swing_m": float(tip.max() - tip.min()),
           "settled_from_s": float(t[settled][0]), "geometry_effective": effective_geometry(values),
           "error_metric": "relative error of the free end's settled deflection against plane-strain FE under the "
                           "water's hydrostatic pressure and the gate's weight"}
    try:
        ref = static_tip_reference(values, water_density, gravity)
    except ImportError as exc:
        return {**out, "reference_tip_deflection_m": None, "error_signed": None, "error": None,
                "reference_note": str(exc)}
    error = measured / ref["fe_tip_deflection_m"] - 1.0
    return {**out, "reference_tip_deflection_m": ref["fe_tip_deflection_m"],
            "beam_tip_deflection_m": ref["beam_tip_deflection_m"],
            "fe_free_end_deflection_m": ref["fe_free_end_deflection_m"],
            "reference": "plane-strain FE of the free length, biquadratic quadrilaterals of dp / 4, read at the "
                         "probe's layer (half a spacing above the free end), mid-thickness (answers/fe_reference.py)",
            "tip_deflection_over_length": measured / effective_geometry(values)["gate_free_length_m"],
            "error_signed": error, "error": abs(error)}
