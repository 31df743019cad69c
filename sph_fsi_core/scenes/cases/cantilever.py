"""The paper's cantilever (config/cantilever.yaml; Satake et al. sec. 3.1, Fig. 1): a beam clamped at x = 0, set
swinging in its first mode. What its file cannot say: the refusal of a beam that is not whole spacings long, thick
and wide, the free end's mean sideways velocity at every sample, and its own reference: the frequency of the free
end's vertical motion against the 3D FE table of answers/reference_data/cantilever_frequencies.csv (interpolated to
the beam's length, thickness, width and material), with beam theory and the paper's eq. (15) beside it.
"""
import math

import numpy as np

from ...answers.oscillation import damping_ratio, measure_frequency, period_averaged
from ...answers.references import cantilever_references
from ...schema import SceneError
from . import Case, probe_named


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


def sample(solid, probes, vel):
    """Extra time-series column: the free end's mean sideways (y) velocity, where a spurious sideways mode shows
    (vel: Simulation.solid_velocity).

    The mean, not the largest particle speed: bending with nu = 0.49 makes the cross-section breathe in y
    (anticlastic curvature), a symmetric motion that is physical and cancels in the mean.
    """
    return {"tip_vy": float(vel[probe_named(probes, "tip").indices, 1].mean())}


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


CASE = Case("cantilever", check=check, sample=sample, evaluate=evaluate)
