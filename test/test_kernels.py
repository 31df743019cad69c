"""Tests of the M4 cubic spline kernel (sph_fsi_core.numerics.kernels) against the textbook formula, its normalisation,
its gradient, and the SPH gradient of a linear field on a lattice."""
import math

import numpy as np
import pytest

from sph_fsi_core.numerics.kernels import SUPPORT_RADIUS_IN_H, cubic_spline_f, cubic_spline_w
from sph_fsi_core.numerics.neighbours import NeighbourList, pair_kernel_values


def textbook_w(r, h):
    """Piecewise M4 spline in 3D, sigma = 1/(pi h^3)."""
    q = r / h
    sigma = 1.0 / (math.pi * h ** 3)
    if q < 1.0:
        return sigma * (1.0 - 1.5 * q * q + 0.75 * q ** 3)
    if q < 2.0:
        return sigma * 0.25 * (2.0 - q) ** 3
    return 0.0


def textbook_dwdr(r, h):
    q = r / h
    sigma = 1.0 / (math.pi * h ** 3)
    if q < 1.0:
        return sigma / h * (-3.0 * q + 2.25 * q * q)
    if q < 2.0:
        return sigma / h * (-0.75 * (2.0 - q) ** 2)
    return 0.0


def textbook_f(r, h):
    """(dW/dr)/r; its r -> 0 limit is -3 sigma / h^2."""
    if r == 0.0:
        return -3.0 / (math.pi * h ** 5)
    return textbook_dwdr(r, h) / r


H_VALUES = (1.0e-3, 1.3e-3, 0.37, 2.5)
Q_VALUES = (0.0, 1e-3, 0.01, 0.1, 0.25, 0.5, 0.7, 0.9, 0.999, 1.0, 1.001, 1.2, 1.5, 1.8, 1.99, 1.999999,
            2.0, 2.000001, 2.5, 3.0, 10.0)


@pytest.mark.parametrize("h", H_VALUES)
def test_w_matches_piecewise_formula(h):
    for q in Q_VALUES:
        r = q * h
        expected = textbook_w(r, h)
        got = cubic_spline_w(r, h)
        if expected == 0.0:
            assert got == 0.0, (q, got)
        else:
            assert abs(got - expected) <= 1e-12 * abs(expected), (q, got, expected)
    # spot values: W(0) = sigma, W(h) = sigma / 4
    sigma = 1.0 / (math.pi * h ** 3)
    assert cubic_spline_w(0.0, h) == pytest.approx(sigma, rel=1e-14)
    assert cubic_spline_w(h, h) == pytest.approx(0.25 * sigma, rel=1e-14)
    assert cubic_spline_w(2.0 * h, h) == 0.0


@pytest.mark.parametrize("h", H_VALUES)
def test_f_matches_piecewise_formula(h):
    for q in Q_VALUES:
        r = q * h
        expected = textbook_f(r, h)
        got = cubic_spline_f(r, h)
        if expected == 0.0:
            assert got == 0.0, (q, got)
        else:
            assert abs(got - expected) <= 1e-12 * abs(expected), (q, got, expected)
    # limit at r = 0 and the value at r = h: dW/dr(h) = -0.75 sigma / h, F = -0.75 / (pi h^5)
    assert cubic_spline_f(0.0, h) == pytest.approx(-3.0 / (math.pi * h ** 5), rel=1e-14)
    assert cubic_spline_f(h, h) == pytest.approx(-0.75 / (math.pi * h ** 5), rel=1e-14)


@pytest.mark.parametrize("h", H_VALUES)
def test_f_near_zero_radius(h):
    """For 1e-12 < q < 1e-3, F is evaluated as (-0.75 (2-q)^2 + 3 (1-q)^2) / q, whose numerator cancels:
    F's relative error grows like round-off / q (measured: 2e-7 at q = 1e-9, 2e-10 at q = 1e-6, at most
    2.2e-16 / q). The docstring's "exact there too" overstates it, but the gradient F (r_a - r_b) keeps an
    absolute error at round-off of the kernel's gradient scale sigma / h, which is what the solver uses."""
    grad_scale = 3.0 / (math.pi * h ** 4)   # |F(0)| h
    for q in (1e-13, 1e-11, 1e-10, 1e-9, 1e-8, 1e-7, 1e-6, 1e-5, 1e-4):
        r = q * h
        expected = textbook_f(r, h)
        got = cubic_spline_f(r, h)
        assert abs(got - expected) <= 1e-15 / q * abs(expected), (q, got, expected)
        assert abs(got - expected) * r <= 2e-15 * grad_scale, (q, got, expected)
    w_tiny = cubic_spline_w(1e-9 * h, h)
    assert w_tiny == pytest.approx(textbook_w(1e-9 * h, h), rel=1e-14)


def test_w_and_f_random_radii():
    rng = np.random.default_rng(7)
    for _ in range(500):
        h = 10 ** rng.uniform(-4, 1)
        r = rng.uniform(1e-3, 2.2) * h
        w_ref = textbook_w(r, h)
        f_ref = textbook_f(r, h)
        assert abs(cubic_spline_w(r, h) - w_ref) <= 1e-12 * abs(w_ref)
        assert abs(cubic_spline_f(r, h) - f_ref) <= 1e-12 * abs(f_ref)


@pytest.mark.parametrize("h", (1e-3, 1.0))
def test_integral_over_support_is_one(h):
    """4 pi int_0^2h r^2 W dr = 1: Gauss-Legendre on [0, h] and [h, 2h], exact for the polynomial pieces."""
    x, wq = np.polynomial.legendre.leggauss(20)
    total = 0.0
    for a, b in ((0.0, h), (h, 2.0 * h)):
        r = 0.5 * (b - a) * x + 0.5 * (a + b)
        vals = np.array([cubic_spline_w(ri, h) for ri in r])
        total += 0.5 * (b - a) * np.sum(wq * 4.0 * math.pi * r * r * vals)
    assert abs(total - 1.0) < 1e-10, total
    # and the kernel vanishes beyond the support
    assert cubic_spline_w(SUPPORT_RADIUS_IN_H * h * (1 + 1e-12), h) == 0.0


def _lattice(dp, n):
    g = np.arange(-n, n + 1) * dp
    return np.ascontiguousarray(np.stack(np.meshgrid(g, g, g, indexing="ij"), -1).reshape(-1, 3))


def _interior_pairs(dp, ratio):
    """A cubic lattice with the origin particle far from its edges; the origin's neighbour rows."""
    h = ratio * dp
    pos = _lattice(dp, 6)   # 13^3 points, half width 6 dp > 2h = 3 dp
    centre = int(np.flatnonzero(np.all(pos == 0.0, axis=1))[0])
    nl = NeighbourList(2.0 * h, 0.05 * h)
    nl.build(pos, pos)
    w = np.empty(nl.pairs)
    f = np.empty(nl.pairs)
    period = np.zeros(3)
    pair_kernel_values(pos, pos, nl.start, nl.index, h, period, w, f)
    s = slice(nl.start[centre], nl.start[centre + 1])
    return pos, centre, nl.index[s], w[s], f[s], h


# Interior lattice sums sum_b dp^3 W_ab, measured (independent of dp, which only scales):
#   h = 1.0 dp: 0.99997247  (error 2.8e-5)
#   h = 1.3 dp: 0.99726183  (error 2.7e-3: ABOVE the 1e-3 first asked for; a property of the M4 kernel on a
#                           cubic lattice at this h, reproduced below with the independent textbook formula)
#   h = 1.5 dp: 1.00179471  (error 1.8e-3)
# The tolerance is about 3x the observed error.
LATTICE_SUM = {1.0: (0.99997247, 1e-4), 1.3: (0.99726183, 8e-3), 1.5: (1.00179471, 6e-3)}


@pytest.mark.parametrize("ratio", sorted(LATTICE_SUM))
@pytest.mark.parametrize("dp", (1e-3, 0.02))
def test_lattice_kernel_sum(ratio, dp):
    pos, centre, nb, w, f, h = _interior_pairs(dp, ratio)
    total = dp ** 3 * w.sum()
    measured, tol = LATTICE_SUM[ratio]
    assert abs(total - 1.0) < tol, total
    assert total == pytest.approx(measured, abs=1e-8)
    # the same sum from the textbook formula over every lattice point (not only the listed neighbours)
    r = np.linalg.norm(pos - pos[centre], axis=1)
    independent = dp ** 3 * sum(textbook_w(ri, h) for ri in r)
    assert total == pytest.approx(independent, rel=1e-12)
    # every lattice point inside the support is listed (r < 2h + skin)
    assert len(nb) == int(np.count_nonzero(r < 2.05 * h))


@pytest.mark.parametrize("ratio", (1.0, 1.3, 1.5))
def test_linear_field_gradient_on_lattice(ratio):
    """SPH gradient sum_b V_b (phi_b - phi_a) grad_a W_ab of phi = c.r + d at an interior lattice particle.

    For phi linear this equals M^T c with M_ij = sum_b V_b (r_b - r_a)_i (grad_a W_ab)_j. Since
    grad_a W_ab = F (r_a - r_b) with F < 0, M_ij = -sum_b V_b F r_i r_j (r = r_b - r_a) is symmetric positive and,
    on a lattice with the cube's symmetry, exactly k * delta_ij (the off-diagonal sums cancel pairwise, the three
    diagonal sums are permutations of one another). So:
      exact to round-off: M is k I (off-diagonals ~ 0, equal diagonals) and the gradient is k c, parallel to c,
                          with the constant d cancelling;
      not exact: k itself, the lattice's first-moment normalisation, close to 1 but not 1
                 (measured k = 1.02004 at h = 1.0 dp, 0.99348 at 1.3 dp, 1.01012 at 1.5 dp).
    """
    dp = 1e-3
    pos, centre, nb, w, f, h = _interior_pairs(dp, ratio)
    vol = dp ** 3
    d = pos[nb] - pos[centre]                           # r_b - r_a
    grad = f[:, None] * (-d)                            # grad_a W_ab = F (r_a - r_b)
    m = vol * np.einsum("si,sj->ij", d, grad)
    k = np.trace(m) / 3.0
    scale = abs(k)
    off = m - np.diag(np.diag(m))
    assert np.abs(off).max() < 1e-13 * scale, m
    assert np.ptp(np.diag(m)) < 1e-13 * scale, m
    expected_k = {1.0: 1.0200417, 1.3: 0.9934837, 1.5: 1.0101228}[ratio]
    assert k == pytest.approx(expected_k, abs=1e-6)
    if ratio == 1.3:
        assert abs(k - 1.0) < 1e-2

    rng = np.random.default_rng(3)
    for _ in range(5):
        c = rng.normal(size=3) * 10.0 ** rng.uniform(-3, 3)
        d0 = rng.normal() * 1e3
        phi = pos @ c + d0
        g = vol * ((phi[nb] - phi[centre])[:, None] * grad).sum(axis=0)
        # exact part: the SPH gradient is k c
        assert np.linalg.norm(g - k * c) < 1e-10 * np.linalg.norm(c), (g, k * c)
        # approximate part: it is c to within the lattice's |k - 1|
        assert np.linalg.norm(g - c) <= (abs(k - 1.0) + 1e-10) * np.linalg.norm(c)


def test_gradient_matches_finite_difference():
    """grad W = F(r) x (x = r_a - r_b) against a central difference of W(|x|) in 3D."""
    rng = np.random.default_rng(11)
    checked = 0
    for _ in range(300):
        h = 10 ** rng.uniform(-3, 0)
        direction = rng.normal(size=3)
        direction /= np.linalg.norm(direction)
        q = rng.uniform(0.02, 1.98)
        x = direction * q * h
        grad = cubic_spline_f(q * h, h) * x
        eps = 1e-5 * h
        fd = np.empty(3)
        for k in range(3):
            xp = x.copy()
            xm = x.copy()
            xp[k] += eps
            xm[k] -= eps
            fd[k] = (cubic_spline_w(np.linalg.norm(xp), h) - cubic_spline_w(np.linalg.norm(xm), h)) / (2 * eps)
        # relative to the kernel gradient's scale sigma/h, so points near q = 2 (where grad -> 0) count too
        scale = 1.0 / (math.pi * h ** 4)
        assert np.linalg.norm(fd - grad) < 1e-6 * max(np.linalg.norm(grad), 1e-2 * scale), (q, fd, grad)
        if q < 1.9:
            assert np.linalg.norm(fd - grad) < 1e-6 * np.linalg.norm(grad), (q, fd, grad)
        checked += 1
    assert checked == 300


# ---- Wendland's C2 kernel (fluid.kernel: wendland_c2) ----------------------------------------------------------
def textbook_wendland_w(r, h):
    """Wendland's C2 in 3D with support 2h (Wendland 1995; Dehnen & Aly 2012, table 1, with their H = 2h):
    W = 21 / (16 pi h^3) (1 - q/2)^4 (2q + 1), q = r / h < 2."""
    q = r / h
    return 21.0 / (16.0 * math.pi * h ** 3) * (1.0 - 0.5 * q) ** 4 * (2.0 * q + 1.0) if q < 2.0 else 0.0


def test_wendland_matches_the_formula_integrates_to_one_and_its_f_is_the_derivative():
    from sph_fsi_core.numerics.kernels import (WENDLAND_C2, kernel_f, kernel_sigma, kernel_w, kernel_wf,
                                               wendland_c2_normalisation)
    x, wq = np.polynomial.legendre.leggauss(20)
    for h in H_VALUES:
        sigma = kernel_sigma(h, WENDLAND_C2)
        assert sigma == wendland_c2_normalisation(h) == pytest.approx(21.0 / (16.0 * math.pi * h ** 3), rel=1e-15)
        for q in Q_VALUES:
            expected = textbook_wendland_w(q * h, h)
            w, f = kernel_wf(q * h, 1.0 / h, sigma, WENDLAND_C2)
            assert w == pytest.approx(expected, rel=1e-12, abs=0.0), (q, w, expected)
            assert kernel_w(q * h, h, WENDLAND_C2) == pytest.approx(expected, rel=1e-12, abs=0.0)
            assert kernel_f(q * h, h, WENDLAND_C2) == f
            if q >= 2.0:
                assert w == 0.0 and f == 0.0
            elif q > 0.0:   # F = (dW/dr) / r against a central difference of the formula
                eps = 1e-6 * h
                dwdr = (textbook_wendland_w(q * h + eps, h) - textbook_wendland_w(q * h - eps, h)) / (2.0 * eps)
                assert f * q * h == pytest.approx(dwdr, rel=1e-6, abs=1e-9 * sigma / h), (q, f * q * h, dwdr)
        w0, f0 = kernel_wf(0.0, 1.0 / h, sigma, WENDLAND_C2)
        assert w0 == sigma and f0 == pytest.approx(-5.0 * sigma / (h * h), rel=1e-15)   # W(0) and F's limit
        # 4 pi int_0^2h r^2 W dr = 1 (Gauss-Legendre, exact for the degree-7 integrand)
        r = h * (x + 1.0)
        total = h * np.sum(wq * 4.0 * math.pi * r * r * np.array([kernel_w(ri, h, WENDLAND_C2) for ri in r]))
        assert total == pytest.approx(1.0, abs=1e-12)


def test_the_water_kernels_cubic_spline_is_the_splines_to_the_bit():
    from sph_fsi_core.numerics.kernels import (CUBIC_SPLINE, cubic_spline_wf, kernel_f, kernel_normalisation,
                                               kernel_sigma, kernel_w, kernel_wf)
    rng = np.random.default_rng(5)
    for _ in range(200):
        h = 10 ** rng.uniform(-4, 0)
        r = rng.uniform(0.0, 2.2) * h
        sigma = kernel_sigma(h, CUBIC_SPLINE)
        assert sigma == kernel_normalisation(h)
        assert kernel_wf(r, 1.0 / h, sigma, CUBIC_SPLINE) == cubic_spline_wf(r, 1.0 / h, sigma)
        assert kernel_w(r, h, CUBIC_SPLINE) == cubic_spline_w(r, h)
        assert kernel_f(r, h, CUBIC_SPLINE) == cubic_spline_f(r, h)


@pytest.mark.parametrize("ratio", (1.3, 2.0))
def test_a_full_lattice_sums_to_rho0_with_either_kernel(ratio):
    """The water's masses (lattice_density_scale of its kernel) make a periodic lattice's summation density rho0,
    through the fluid solver's own density pass, to round-off; the scale itself against a brute-force sum of the
    textbook formulas over the lattice."""
    from sph_fsi_core.fluid.solver import FluidSolver
    from sph_fsi_core.numerics.kernels import KERNELS, lattice_density_scale
    from sph_fsi_core.state import FluidState
    dp, n = 0.01, 10
    g = (np.arange(n) + 0.5) * dp
    pos = np.ascontiguousarray(np.stack(np.meshgrid(g, g, g, indexing="ij"), -1).reshape(-1, 3))
    period = np.full(3, n * dp)
    brute = {"cubic_spline": textbook_w, "wendland_c2": textbook_wendland_w}
    d = np.linalg.norm(_lattice(1.0, int(np.ceil(2.0 * ratio)) + 1), axis=1)
    for name, kernel in KERNELS.items():
        scale = lattice_density_scale(ratio, kernel)
        assert scale == pytest.approx(1.0 / sum(brute[name](x, ratio) for x in d), rel=1e-13)
        water = FluidState.at_rest(pos.copy(), 1000.0, dp, mass_scale=scale)
        solver = FluidSolver(water, None, ratio * dp, period, np.zeros(3), period, 0.1 * ratio * dp, kernel)
        solver.configure(1000.0, 1e-6, (0.0, 0.0, 0.0), 0.01, "max", 0.0, 1.0, 0, 10)
        solver.density()
        assert np.abs(water.rho - 1000.0).max() < 1e-10, (name, np.abs(water.rho - 1000.0).max())
    # the two kernels' scales differ (the masses do follow the kernel)
    assert abs(lattice_density_scale(ratio, KERNELS["wendland_c2"]) - lattice_density_scale(ratio)) > 1e-4


def test_the_waters_probes_and_push_on_a_solid_take_its_kernel():
    """With Wendland's C2 the water's pressure probe (probes.shepard_pressure) and the 'pressure' coupling's pair
    forces on a solid (coupling/forces.pressure_pair_forces) equal brute-force sums of the textbook kernel over
    every pair, and differ from the cubic spline's by far more than round-off."""
    from sph_fsi_core.coupling.forces import pressure_pair_forces
    from sph_fsi_core.numerics.kernels import CUBIC_SPLINE, WENDLAND_C2
    from sph_fsi_core.probes import shepard_pressure
    rng = np.random.default_rng(17)
    h = 0.01
    water = rng.uniform(0.0, 0.05, (300, 3))
    mass = rng.uniform(0.9e-3, 1.1e-3, 300)
    rho = rng.uniform(990.0, 1010.0, 300)
    pressure = rng.uniform(0.0, 500.0, 300)
    points = rng.uniform(0.01, 0.04, (7, 3))
    got = shepard_pressure(points, water, mass, rho, pressure, h, WENDLAND_C2)
    for i, x in enumerate(points):
        w = np.array([textbook_wendland_w(r, h) for r in np.linalg.norm(water - x, axis=1)]) * mass / rho
        assert got[i] == pytest.approx((w * pressure).sum() / w.sum(), rel=1e-12)
    assert np.abs(got - shepard_pressure(points, water, mass, rho, pressure, h, CUBIC_SPLINE)).max() > 1e-3

    solid = rng.uniform(0.01, 0.04, (9, 3))
    solid_mass, solid_p = rng.uniform(1e-3, 2e-3, 9), rng.uniform(0.0, 300.0, 9)
    nl = NeighbourList(2.0 * h, 0.1 * h)
    nl.build(solid, water)
    force = np.zeros((9, 3))
    pressure_pair_forces(solid, solid_mass, solid_p, nl.start, nl.index, water, mass, pressure, np.zeros(3), h,
                         WENDLAND_C2, 1000.0, force)
    for s in range(9):
        d = water - solid[s]                     # r_u - r_t
        r = np.linalg.norm(d, axis=1)
        q = r / h
        f = np.where(q < 2.0, -5.0 * 21.0 / (16.0 * math.pi * h ** 5) * np.clip(1.0 - 0.5 * q, 0.0, None) ** 3, 0.0)
        c = solid_mass[s] * mass * (solid_p[s] + pressure) / 1000.0 ** 2 * f
        np.testing.assert_allclose(force[s], (c[:, None] * d).sum(axis=0), rtol=1e-11, atol=1e-14)
    assert np.abs(force).max() > 1e-6
