"""The paper's cantilever (Satake et al. sec. 3.1, Fig. 1): a beam clamped at x = 0, set swinging in its first mode.

Beam: length L along x, thickness H along z (the paper's x^2), width W along y, particles on a cubic lattice of
spacing dp, centred on y = z = 0. Clamp: `clamp_layers` layers of fixed particles behind the root (x < 0),
reaching `clamp_margin` layers above and below the beam with the fixed clamp: with the defaults 4 x 14 x 6 = 336
particles, the paper's wall count, and 40 x 4 x 6 = 960 beam particles. The mirrored clamp (solid.clamp =
mirrored, the default scheme's) is the body's odd image across the clamp face, 4 x 4 x 6 ghosts: the margin's
particles have no image in the body, so they would stand at rest beside the root's top and bottom faces, inside the
kernel's reach of the body across the corner, holding the root's most strained layers; that stiffness is not the
clamp's (a clamped 3D continuum's top face is free up to the clamp's edge) and made the default scheme's beam
deflect 2.2 points more against 3D FE at L/H = 5 and 1.2 points at L/H = 10 (docs/validation/studies/clamp_effect), so
the mirrored clamp builds no margin. Initial velocity: eqs. (12)-(14) along z.
"""
import math

import numpy as np

from ..answers.oscillation import damping_ratio, measure_frequency, period_averaged
from ..answers.references import cantilever_mode_velocity, cantilever_references
from ..schema import Param, SceneError
from ..state import Probe, SolidState
from .built import Built, clamp_mirror_across

PHASES = ("solid",)
CONSERVATIVE = True

GEOMETRY = [
    Param("geometry.length", 0.04, "m", "Beam length L (x), clamp face to free end", low=0.0, low_inclusive=False,
          high=10.0),
    Param("geometry.thickness", 0.004, "m", "Beam thickness H (z, the bending direction)", low=0.0,
          low_inclusive=False, high=1.0),
    Param("geometry.width", 0.006, "m", "Beam width W (y)", low=0.0, low_inclusive=False, high=1.0),
    Param("geometry.clamp_layers", 4, "1", "Layers of fixed particles behind the root", kind="int", low=1,
          high=20),
    Param("geometry.clamp_margin", 5, "1", "Clamp layers above and below the beam (the fixed clamp's; the mirrored "
          "clamp has none)", kind="int", low=0, high=20),
    Param("geometry.tip_velocity", 0.01, "m/s", "Free-end speed Vf of the initial first-mode velocity, eq. (12)",
          low=-1.0e3, high=1.0e3),
]

DEFAULTS = {"scene.end_time": 0.3, "output.timeseries_interval": 2.5e-4}


def _layers(extent, spacing, key):
    n = extent / spacing
    if abs(n - round(n)) > 1e-6 * max(n, 1.0):
        raise SceneError(f"{key} = {extent:g} m is not a whole number of spacings "
                         f"(numerics.spacing = {spacing:g} m); allowed: a multiple of the spacing")
    n = int(round(n))
    if n < 2:
        raise SceneError(f"numerics.spacing = {spacing:g} m is too coarse for {key} = {extent:g} m; "
                         f"allowed: at most {extent / 2:g} m (two particle layers)")
    return n


def layer_counts(values):
    """(nl, nh, nw): layers along the length, through the thickness and across the width (SceneError if one is
    not whole or below 2)."""
    dp = values["numerics.spacing"]
    return tuple(_layers(values[key], dp, key) for key in ("geometry.length", "geometry.thickness",
                                                            "geometry.width"))


def check(values):
    layer_counts(values)


def particle_counts(values):
    """The particles build() makes, per phase, without making them (the memory guard's estimate)."""
    nl, nh, nw = layer_counts(values)
    ncl, margin = values["geometry.clamp_layers"], clamp_margin(values)
    return {"solid": nl * nw * nh + ncl * nw * (nh + 2 * margin)}


def clamp_margin(values):
    """The clamp's layers above and below the beam: geometry.clamp_margin with the fixed clamp, none with the
    mirrored one (module docstring)."""
    return 0 if values.get("solid.clamp") == "mirrored" else values["geometry.clamp_margin"]


def build(values):
    dp = values["numerics.spacing"]
    nl, nh, nw = layer_counts(values)
    ncl, margin = values["geometry.clamp_layers"], clamp_margin(values)
    y = (np.arange(nw) + 0.5) * dp - 0.5 * nw * dp
    z = (np.arange(nh) + 0.5) * dp - 0.5 * nh * dp
    beam = np.stack(np.meshgrid((np.arange(nl) + 0.5) * dp, y, z, indexing="ij"), axis=-1).reshape(-1, 3)
    zc = (np.arange(-margin, nh + margin) + 0.5) * dp - 0.5 * nh * dp
    clamp = np.stack(np.meshgrid(-(np.arange(ncl) + 0.5) * dp, y, zc, indexing="ij"), axis=-1).reshape(-1, 3)
    pos = np.concatenate([beam, clamp])
    movable = np.concatenate([np.ones(len(beam), bool), np.zeros(len(clamp), bool)])
    solid = SolidState.at_rest(pos, movable, values["solid.density"], dp)
    solid.vel[: len(beam), 2] = cantilever_mode_velocity(beam[:, 0], values["geometry.length"],
                                                        values["geometry.tip_velocity"])
    tip = np.flatnonzero(np.isclose(pos[:, 0], (nl - 0.5) * dp) & movable)
    probes = [Probe("tip", "solid", tip, pos[tip].mean(axis=0))]
    span = values["geometry.length"] + 10 * dp
    lo = np.array([-span, -span, -span])
    hi = np.array([2 * span, span, span])
    return Built(solid=solid, probes=probes, domain_lo=lo, domain_hi=hi,
                 clamp_mirror=clamp_mirror_across(pos, movable, 0, 0.0, dp))


def sample(solid, probes, vel):
    """Extra time-series column: the free end's mean sideways (y) velocity, where a spurious sideways mode shows
    (vel: Simulation.solid_velocity).

    The mean, not the largest particle speed: bending with nu = 0.49 makes the cross-section breathe in y
    (anticlastic curvature), a symmetric motion that is physical and cancels in the mean.
    """
    return {"tip_vy": float(vel[probes[0].indices, 1].mean())}


# the shortest record, in periods of the reference frequency, whose frequency is measured and judged
MIN_REFERENCE_PERIODS = 1.0


def evaluate(series, values):
    """Frequency of the free end's vertical motion against the 3D, beam and eq. (15) references."""
    t = series["time"]
    z = series["tip_dz"]
    refs = cantilever_references(values["geometry.length"], values["geometry.thickness"],
                                 values["geometry.width"], values["solid.young_modulus"],
                                 values["solid.poisson_ratio"], values["solid.density"])
    metric = f"relative frequency error against {refs['judged_against']} ({refs['fe3d_source']})"
    covered = (float(t[-1] - t[0]) if len(t) else 0.0) * refs["reference_hz"]
    if covered < MIN_REFERENCE_PERIODS:
        # a part of one swing has crossings of ripples about its own mean, which would pass for a frequency
        return {"frequency_hz": None, "periods": None, **refs, "error_metric": metric, "error": None,
                "frequency_note": f"not measured: the run covers {covered:.2f} periods of the expected "
                                  f"{refs['reference_hz']:.4g} Hz; at least {MIN_REFERENCE_PERIODS:g} are needed"}
    est = measure_frequency(t, z)
    out = {"frequency_hz": est.frequency, "frequency_uncertainty_hz": est.uncertainty,
           "frequency_method": est.method, "periods": est.periods, **refs}
    f = est.frequency
    for name in ("fe3d_hz", "euler_bernoulli_hz", "eq15_hz"):
        ref = refs[name]
        out[f"error_vs_{name[:-3]}_percent"] = (100.0 * (f - ref) / ref if ref and math.isfinite(f)
                                                else None)
    ref = refs["reference_hz"]
    out["error_metric"] = metric
    out["error"] = abs(f - ref) / ref if math.isfinite(f) else None
    zeta, zeta_err = (damping_ratio(t, z, f) if math.isfinite(f) else (float("nan"), float("nan")))
    out["damping_ratio"] = zeta
    out["damping_ratio_uncertainty"] = zeta_err
    if math.isfinite(f):
        energy = series["kinetic_energy"] + series["strain_energy"]
        mids, means = period_averaged(t, energy, f)
        if len(means) >= 2:
            out["energy_period_averaged_first_j"] = float(means[0])
            out["energy_period_averaged_last_j"] = float(means[-1])
            out["energy_max_period_growth"] = float(np.max(means[1:] / means[:-1]) - 1.0)
        after_first = t >= 1.0 / f
        vf = abs(values["geometry.tip_velocity"])
        if after_first.any() and vf > 0:
            out["max_sideways_speed_over_tip_speed"] = float(np.abs(series["tip_vy"][after_first]).max() / vf)
    return out
