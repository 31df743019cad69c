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
