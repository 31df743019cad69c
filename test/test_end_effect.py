"""validation/end_effect.py: the FE terms that split a strip's error (shear fraction, clamp-offset sensitivity, the
reference at the probe) against beam theory, and the fit recovering known parts."""
import numpy as np
import pytest

from sph_fsi_core.validation.end_effect import fit, strip_terms

T, DP = 0.02, 0.005


def values(ratio, supports):
    return {"geometry.span": ratio * T, "geometry.thickness": T, "numerics.spacing": DP,
            "solid.young_modulus": 1.0e8, "solid.poisson_ratio": 0.3, "solid.density": 2700.0,
            "geometry.supports": supports, "geometry.load_pressure": 100.0, "geometry.load_gradient": 0.0,
            "scene.gravity": (0.0, 0.0, -9.81)}


@pytest.mark.parametrize("supports, beam_factor", [("clamped_clamped", 8.0), ("clamped_free", 4.0)])
def test_offset_sensitivity_is_beam_theorys_on_a_slender_strip(supports, beam_factor):
    """A clamp face moved back by delta (the strip longer by delta there, unloaded) grows the deflection by
    beam_factor delta / L (L^4 scaling of bending; a rotational spring at the clamp, to first order): at L/t = 30
    within 5 %."""
    ratio = 30
    v = values(ratio, supports)
    x = 0.5 * v["geometry.span"] if supports == "clamped_clamped" else v["geometry.span"] - 0.5 * DP
    _, phi, sensitivity = strip_terms(v, [(x, 0.5 * T)])
    assert sensitivity == pytest.approx(beam_factor * DP / v["geometry.span"], rel=0.05)
    assert abs(phi) < 0.02           # a slender strip bends as Euler-Bernoulli to 2 %


def test_shear_fraction_is_timoshenkos_for_the_clamped_strip():
    """phi = 1 - w_EB / w_FE of a clamped-clamped strip against Timoshenko's shear deflection q L^2 / (8 kappa G t)
    over q L^4 / (384 D) (kappa 5/6): 13.7 (t / L)^2 at nu = 0.3, within 10 % at L/t = 10 (the continuum's clamp
    is not Timoshenko's)."""
    v = values(10, "clamped_clamped")
    reference, phi, _ = strip_terms(v, [(0.5 * v["geometry.span"], 0.5 * T)])
    ratio = 4.0 * 2.0 * 1.3 / ((5.0 / 6.0) * (1.0 - 0.09)) * (1.0 / 10.0) ** 2
    assert phi == pytest.approx(ratio / (1.0 + ratio), rel=0.10)
    assert reference < 0.0            # down, under the pressure and the weight


def test_reference_at_the_probe_is_the_mean_over_its_points():
    """Two columns dp / 2 either side of mid-span bend less than the centre: by about 2 dp^2 / L^2 (w ~ x^2 (L - x)^2
    near mid-span), 0.5 % at L/t = 5 with 4 particles through."""
    v = values(5, "clamped_clamped")
    mid = 0.5 * v["geometry.span"]
    centre, _, _ = strip_terms(v, [(mid, 0.5 * T)])
    probe, _, _ = strip_terms(v, [(mid + sx * 0.5 * DP, 0.5 * T) for sx in (-1.0, 1.0)])
    assert probe / centre - 1.0 == pytest.approx(-2.0 * DP ** 2 / v["geometry.span"] ** 2, rel=0.3)


def test_fit_recovers_known_parts():
    phis = np.array([0.34, 0.11, 0.05, 0.03, 0.01])
    sens = np.array([0.35, 0.19, 0.13, 0.10, 0.07])
    errors = 0.018 + 0.27 * phis + 0.05 * sens
    a, g, d, residuals = fit(errors, phis, sens)
    assert (a, g, d) == pytest.approx((0.018, 0.27, 0.05), abs=1e-12)
    assert np.abs(residuals).max() < 1e-12
    a, g, d, residuals = fit(errors, phis, sens, with_offset=False)
    assert d is None and np.abs(residuals).max() > 1e-4
