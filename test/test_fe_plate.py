"""The static FE reference of a clamped-clamped plane-strain strip (validation/fe_reference.py), which judges the
hydrostatic-plate case (Fourey et al. 2017; ../shared/reference/hydrostatic_plate_fourey2017.csv), against beam
theory and statics."""
import pytest

from sph_fsi_core.validation.fe_reference import clamped_plate_beam_deflection, clamped_plate_fe_deflection

# The benchmark's plate (hydrostatic_plate_fourey2017.csv): 1 m span, 0.05 m thick aluminium, 2 m of water on top.
SPAN, THICKNESS, E, NU, RHO_S = 1.0, 0.05, 67.5e9, 0.3, 2700.0
WATER = 1000.0 * 9.81 * 2.0


def test_beam_formula_is_the_reference_files_value():
    load = WATER + RHO_S * 9.81 * THICKNESS       # 20944.35 Pa, the file's load_q_with_self_weight
    assert load == pytest.approx(20944.35, rel=1e-9)
    # the file quotes 0.0026 q L^4 / D (1/384 rounded): -7.0477e-5 m
    euler_bernoulli = clamped_plate_beam_deflection(SPAN, THICKNESS, E, NU, load, shear=False)
    assert euler_bernoulli * 384 * 0.0026 == pytest.approx(7.0477e-5, rel=1e-4)
    # the shear deflection is the file's 'about +3.4 %'
    timoshenko = clamped_plate_beam_deflection(SPAN, THICKNESS, E, NU, load)
    assert timoshenko / euler_bernoulli - 1 == pytest.approx(0.0343, abs=5e-4)


def test_benchmark_plate_lies_between_the_beams_and_converges():
    load = WATER + RHO_S * 9.81 * THICKNESS
    coarse = clamped_plate_fe_deflection(SPAN, THICKNESS, E, NU, WATER, -RHO_S * 9.81, element_size=THICKNESS / 4)
    fine = clamped_plate_fe_deflection(SPAN, THICKNESS, E, NU, WATER, -RHO_S * 9.81, element_size=THICKNESS / 8)
    w = -fine["midspan_deflection_m"]
    # statics: the clamps carry the whole load, water and plate (N per m of width)
    assert fine["clamp_reaction_z_n_per_m"] == pytest.approx(load * SPAN, rel=1e-8)
    # converged to 0.1 % between 4 and 8 elements through the thickness
    assert abs(coarse["midspan_deflection_m"] / fine["midspan_deflection_m"] - 1) < 1e-3
    # a thick plate (L/t = 20) bends more than Euler-Bernoulli and a little less than Timoshenko, whose clamp lets
    # the section warp; the continuum value is about 3 % above the beam value that peers quote
    euler_bernoulli = clamped_plate_beam_deflection(SPAN, THICKNESS, E, NU, load, shear=False)
    timoshenko = clamped_plate_beam_deflection(SPAN, THICKNESS, E, NU, load)
    assert euler_bernoulli < w < timoshenko
    assert w / timoshenko - 1 == pytest.approx(0.0, abs=0.01)


def test_thin_strip_is_euler_bernoulli_and_linear_in_the_load():
    span, thickness = 1.0, 0.01     # L/t = 100: shear deflection 0.14 % of the bending
    a = clamped_plate_fe_deflection(span, thickness, E, NU, 1000.0, element_size=thickness / 2)
    b = clamped_plate_fe_deflection(span, thickness, E, NU, lambda x: 2000.0 + 0.0 * x, element_size=thickness / 2)
    beam = clamped_plate_beam_deflection(span, thickness, E, NU, 1000.0)
    assert -a["midspan_deflection_m"] == pytest.approx(beam, rel=3e-3)
    assert b["midspan_deflection_m"] == pytest.approx(2.0 * a["midspan_deflection_m"], rel=1e-9)


def test_cantilever_strip_against_beam_theory():
    """The one-end-clamped strip (a gate held static): a uniform pressure gives q L^4 / (8 D) (Euler-Bernoulli)
    plus the shear deflection q L^2 / (2 kappa G t) at L/t = 16 (Antoci's gate), and twice the pressure twice the
    deflection."""
    from sph_fsi_core.validation.fe_reference import cantilever_strip_fe_deflection
    length, thickness, e, nu = 0.079, 0.005, 12.0e6, 0.4
    rigidity = e * thickness ** 3 / (12.0 * (1.0 - nu ** 2))
    one = cantilever_strip_fe_deflection(length, thickness, e, nu, 100.0)
    two = cantilever_strip_fe_deflection(length, thickness, e, nu, 200.0)
    beam = 100.0 * length ** 4 / (8.0 * rigidity)
    shear = 100.0 * length ** 2 / (2.0 * (5.0 / 6.0) * e / (2.0 * (1.0 + nu)) * thickness)
    assert two["tip_deflection_m"] == pytest.approx(2.0 * one["tip_deflection_m"], rel=1e-9)
    # between Euler-Bernoulli (less 0.3 %: the clamped face holds the root's Poisson contraction, which stiffens it)
    # and Timoshenko, whose section may shear freely at the root (measured: 0.06 % below Euler-Bernoulli)
    assert 0.997 * beam < one["tip_deflection_m"] < beam + shear
    # a linearly varying pressure p(x) = q x / L (zero at the clamp): 11 q L^4 / (120 D)
    ramp = cantilever_strip_fe_deflection(length, thickness, e, nu, lambda x: 100.0 * x / length)
    assert ramp["tip_deflection_m"] == pytest.approx(11.0 * 100.0 * length ** 4 / (120.0 * rigidity), rel=5e-3)
