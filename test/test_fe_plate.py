"""The static FE reference of a clamped-clamped plane-strain strip (answers/fe_reference.py), which judges the
hydrostatic-plate case (Fourey et al. 2017; ../shared/reference/hydrostatic_plate_fourey2017.csv), against beam
theory and statics."""
import pytest

from sph_fsi_core.answers.fe_reference import clamped_plate_beam_deflection, clamped_plate_fe_deflection

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
    from sph_fsi_core.answers.fe_reference import cantilever_strip_fe_deflection
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


def test_cantilever_strip_own_weight_across_is_a_pressure_on_its_top():
    """A horizontal cantilever's own weight (body_force_across = -rho g, config/clamped_plate.yaml with
    geometry.supports = clamped_free) bends it as the same load per area as a pressure would: rho g t L^4 / (8 D)
    (Euler-Bernoulli, within 1 % at L/t = 30), the two add, and a body force along +z (towards the pressed face's
    outside) lifts the strip."""
    from sph_fsi_core.answers.fe_reference import cantilever_strip_fe_deflection
    length, thickness, e, nu, rho, g = 0.6, 0.02, 1.0e8, 0.3, 2700.0, 9.81
    rigidity = e * thickness ** 3 / (12.0 * (1.0 - nu ** 2))
    weight = cantilever_strip_fe_deflection(length, thickness, e, nu, 0.0, body_force_across=-rho * g)
    pressure = cantilever_strip_fe_deflection(length, thickness, e, nu, rho * g * thickness)
    both = cantilever_strip_fe_deflection(length, thickness, e, nu, rho * g * thickness, body_force_across=-rho * g)
    assert weight["tip_deflection_m"] == pytest.approx(rho * g * thickness * length ** 4 / (8.0 * rigidity), rel=0.01)
    assert weight["tip_deflection_m"] == pytest.approx(pressure["tip_deflection_m"], rel=1e-3)
    assert both["tip_deflection_m"] == pytest.approx(weight["tip_deflection_m"] + pressure["tip_deflection_m"],
                                                     rel=1e-9)
    up = cantilever_strip_fe_deflection(length, thickness, e, nu, 0.0, body_force_across=rho * g)
    assert up["tip_deflection_m"] == pytest.approx(-weight["tip_deflection_m"], rel=1e-9)


def test_3d_cantilever_static_against_euler_bernoulli():
    """The 3D clamped-free beam under a uniform body force (fe_reference.cantilever_fe_static_deflection, half the
    width meshed about its plane of symmetry): the free end's mean deflection is q L^4 / (8 E I) at L/H = 20
    within 1 % (shear adds about 0.3 %, the clamped root's held Poisson contraction takes a little), a point and
    its mirror image across y = W / 2 read the same, and the answer is linear in the load."""
    import numpy as np
    from sph_fsi_core.answers.fe_reference import cantilever_fe_static_deflection
    length, thickness, width, e, nu = 0.08, 0.004, 0.006, 1.0e6, 0.3
    end = [(length, y, z) for y in (0.0, 0.0015, 0.003, 0.0045, 0.006) for z in (0.0, 0.002, 0.004)]
    one = cantilever_fe_static_deflection(length, thickness, width, e, nu, -10.0, end, 0.001)
    two = cantilever_fe_static_deflection(length, thickness, width, e, nu, -20.0, end, 0.001)
    q = 10.0 * width * thickness                        # N/m
    beam = q * length ** 4 / (8.0 * e * width * thickness ** 3 / 12.0)
    assert -one["mean_uz_m"] == pytest.approx(beam, rel=0.01)
    uz = np.array(one["uz_m"]).reshape(5, 3)
    assert uz[0] == pytest.approx(uz[4], rel=1e-12) and uz[1] == pytest.approx(uz[3], rel=1e-12)
    assert two["mean_uz_m"] == pytest.approx(2.0 * one["mean_uz_m"], rel=1e-9)
