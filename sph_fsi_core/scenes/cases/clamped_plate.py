"""A plate clamped at both ends under a prescribed pressure, settled to static (config/clamped_plate.yaml): the
solid alone against FE. What its file cannot say: the refusals of a plate that is not whole spacings, the load and
its ramp, the damping from the first mode, and the reference.

This is the hydrostatic-plate benchmark (Fourey et al. 2017; ../shared/reference/hydrostatic_plate_fourey2017.csv)
with the water replaced by the exact pressure it puts on the plate, so the solid's static answer is judged apart
from the fluid and the load transfer. The load: the pressure p(x) = load_pressure + load_gradient * x (Pa) pushes
the top layer of the span down, each particle carrying the force of its dp x dp of surface; it ramps in smoothly
over `load_ramp_periods` periods of the plate's first mode and a mass-proportional damping (`damping_ratio` of that
mode's critical damping) lets it settle. Neither changes the static answer; both only shorten the way to it.

Judged on the probe 'midspan' (the movable particles nearest mid-span and mid-thickness), its mean vertical
displacement over the last 25 % of the run, against the project's plane-strain FE value for the same plate and load
(answers/fe_reference.py). `geometry.supports = clamped_free`: the same strip clamped at x = 0 only, a cantilever
free at x = L, judged on its probe 'free_end' (x = L - dp / 2, mid-thickness) against FE at the same point. With the
two supports on one plate the clamp and the free end can be told apart: a clamp that acts as if the strip were
longer by delta moves the clamped-clamped mid-span by 8 delta / L and the cantilever's free end by 4 delta / L (beam
theory; a rotational spring at the clamp, to first order), so a ladder over L / t separates what the clamp does from
what the free end does (validation case clamp_effect).
"""
import math

import numpy as np

from ...schema import SceneError, solid_smoothing_ratio, widest_smoothing_ratio
from . import Case

# the benchmark's plate and water (hydrostatic_plate_fourey2017.csv)
WATER_PRESSURE = 1000.0 * 9.81 * 2.0
SETTLED_FRACTION = 0.25   # evaluate() averages over the last quarter of the run
# first bending mode, Euler-Bernoulli: beta_1 L = 4.7300 clamped-clamped, 1.8751 clamped-free
FIRST_MODE_BETA_L = {"clamped_clamped": 4.730040745, "clamped_free": 1.875104069}


def _layers(extent, dp, key, at_least):
    n = extent / dp
    if abs(n - round(n)) > 1e-6 * max(n, 1.0):
        raise SceneError(f"{key} = {extent:g} m is not a whole number of spacings (numerics.spacing = {dp:g} m); "
                         f"allowed: a multiple of the spacing")
    if round(n) < at_least:
        raise SceneError(f"numerics.spacing = {dp:g} m is too coarse for {key} = {extent:g} m; allowed: at most "
                         f"{extent / at_least:g} m ({at_least} particle layers)")
    return int(round(n))


def layer_counts(values):
    dp = values["numerics.spacing"]
    h = solid_smoothing_ratio(values) * dp            # the solid's: its kernel must not reach past the clamp
    cutoff = (2.0 + values["numerics.neighbour_skin"]) * widest_smoothing_ratio(values) * dp
    narrowest = math.ceil(2.0 * cutoff / dp - 1e-9)
    ny = values["geometry.span_layers"] or narrowest
    if ny < narrowest:
        raise SceneError(f"geometry.span_layers = {ny}: a periodic slab must be at least twice the neighbour cutoff "
                         f"(2h + skin) wide; allowed: at least {narrowest}, or 0")
    nc = values["geometry.clamp_layers"]
    if nc < math.ceil(2.0 * h / dp - 1e-9):
        raise SceneError(f"geometry.clamp_layers = {nc}: thinner than the kernel's reach 2h = {2 * h / dp:.3g} dp; "
                         f"allowed: at least {math.ceil(2.0 * h / dp - 1e-9)}")
    return dict(nx=_layers(values["geometry.span"], dp, "geometry.span", 4),
                nz=_layers(values["geometry.thickness"], dp, "geometry.thickness", 2), ny=ny, nc=nc)


def check(values):
    layer_counts(values)


def first_mode_omega(values):
    """omega_1 = (beta_1 L)^2 / L^2 sqrt(D / (rho t)) of the plane-strain strip on its supports, rad/s."""
    t, span = values["geometry.thickness"], values["geometry.span"]
    nu = values["solid.poisson_ratio"]
    rigidity = values["solid.young_modulus"] * t ** 3 / (12.0 * (1.0 - nu * nu))
    beta_l = FIRST_MODE_BETA_L[values.get("geometry.supports", "clamped_clamped")]
    return beta_l ** 2 / span ** 2 * math.sqrt(rigidity / (values["solid.density"] * t))


def _free_end(values):
    return values.get("geometry.supports", "clamped_clamped") == "clamped_free"


def pressure_at(values, x):
    return values["geometry.load_pressure"] + values["geometry.load_gradient"] * x


def load(values, built):
    """The pressure on the span's top layer, each particle's dp x dp of surface, down; ramped in over
    load_ramp_periods of the first mode."""
    solid = built.solid
    dp = values["numerics.spacing"]
    nz = layer_counts(values)["nz"]
    top = solid.movable & np.isclose(solid.pos[:, 2], (nz - 0.5) * dp)
    force = np.zeros((solid.count, 3))
    force[top, 2] = -pressure_at(values, solid.pos[top, 0]) * dp * dp     # N: the pressure on its dp x dp of surface
    return force, values["geometry.load_ramp_periods"] * 2.0 * math.pi / first_mode_omega(values)


def relaxation(values, built):
    """The plate's mass-proportional damping, damping_ratio of its first mode's critical; no water."""
    return 2.0 * values["geometry.damping_ratio"] * first_mode_omega(values), 0.0


def block_means(x, blocks=3):
    """Means of `blocks` equal consecutive parts of x: their spread says how settled a mean over x is."""
    x = np.asarray(x)
    return [float(b.mean()) for b in np.array_split(x, max(1, min(blocks, len(x))))]


def evaluate(series, values, settled_fraction=SETTLED_FRACTION):
    """Mid-span deflection, settled, against the plane-strain FE value (and the beam values beside it); the free
    end's with geometry.supports = clamped_free (evaluate_free_end)."""
    if _free_end(values):
        return evaluate_free_end(series, values, settled_fraction)
    from ...answers.fe_reference import clamped_plate_beam_deflection, clamped_plate_fe_deflection
    t = series["time"]
    settled = t >= t[-1] * (1.0 - settled_fraction)
    w = series["midspan_dz"][settled]
    deflection = float(w.mean())
    span, thickness = values["geometry.span"], values["geometry.thickness"]
    e, nu, rho = values["solid.young_modulus"], values["solid.poisson_ratio"], values["solid.density"]
    gz = values["scene.gravity"][2]
    mean_load = pressure_at(values, 0.5 * span) - rho * gz * thickness
    beam = -clamped_plate_beam_deflection(span, thickness, e, nu, mean_load, shear=False)
    out = {
        "midspan_deflection_m": deflection,
        "midspan_deflection_swing_m": float(w.max() - w.min()),
        "midspan_deflection_blocks_m": block_means(w),
        "settled_from_s": float(t[settled][0]),
        "beam_theory_midspan_deflection_m": beam if values["geometry.load_gradient"] == 0.0 else None,
        "error_metric": "relative error of the settled mid-span deflection against plane-strain FE",
    }
    try:
        fe = clamped_plate_fe_deflection(span, thickness, e, nu, lambda x: pressure_at(values, x), rho * gz)
    except ImportError as exc:    # scikit-fem and scipy are the validation's (requirements-dev.txt), not the core's
        return {**out, "reference_midspan_deflection_m": None, "error_signed": None, "error": None,
                "reference_note": str(exc)}
    reference = fe["midspan_deflection_m"]
    error = (deflection - reference) / reference
    return {**out, "reference_midspan_deflection_m": reference,
            "reference": "plane-strain FE, biquadratic quadrilaterals, t / 8 (answers/fe_reference.py)",
            "error_signed": error, "error": abs(error)}


def evaluate_free_end(series, values, settled_fraction=SETTLED_FRACTION):
    """A cantilever's free-end deflection (x = L - dp / 2, mid-thickness), settled, against plane-strain FE at the
    same point; the beam value (Euler-Bernoulli, at x = L) beside it."""
    from ...answers.fe_reference import cantilever_strip_fe_deflection
    t = series["time"]
    settled = t >= t[-1] * (1.0 - settled_fraction)
    w = series["free_end_dz"][settled]
    deflection = float(w.mean())
    span, thickness, dp = values["geometry.span"], values["geometry.thickness"], values["numerics.spacing"]
    e, nu, rho = values["solid.young_modulus"], values["solid.poisson_ratio"], values["solid.density"]
    gz = values["scene.gravity"][2]
    mean_load = pressure_at(values, 0.5 * span) - rho * gz * thickness
    rigidity = e * thickness ** 3 / (12.0 * (1.0 - nu * nu))
    out = {
        "free_end_deflection_m": deflection,
        "free_end_deflection_swing_m": float(w.max() - w.min()),
        "free_end_deflection_blocks_m": block_means(w),
        "settled_from_s": float(t[settled][0]),
        "beam_theory_free_end_deflection_m": (-mean_load * span ** 4 / (8.0 * rigidity)
                                              if values["geometry.load_gradient"] == 0.0 else None),
        "error_metric": "relative error of the settled free-end deflection (x = L - dp / 2) against plane-strain FE",
    }
    # the probe's x must be a node of the FE mesh (a multiple of half its element): elements of dp / k <= t / 8
    element = dp / max(1, math.ceil(8.0 * dp / thickness - 1e-9))
    try:
        fe = cantilever_strip_fe_deflection(span, thickness, e, nu, lambda x: pressure_at(values, x),
                                            body_force_across=rho * gz, element_size=element,
                                            probe_x=span - 0.5 * dp)
    except ImportError as exc:    # scikit-fem and scipy are the validation's (requirements-dev.txt), not the core's
        return {**out, "reference_free_end_deflection_m": None, "error_signed": None, "error": None,
                "reference_note": str(exc)}
    reference = -fe["tip_deflection_m"]
    error = (deflection - reference) / reference
    return {**out, "reference_free_end_deflection_m": reference,
            "reference": f"plane-strain FE, biquadratic quadrilaterals of {element:g} m at x = L - dp / 2 "
                         "(answers/fe_reference.py)",
            "error_signed": error, "error": abs(error)}


CASE = Case("clamped_plate", check=check, load=load, relaxation=relaxation, evaluate=evaluate)
