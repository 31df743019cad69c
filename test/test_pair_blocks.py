"""The block passes (sph_fsi_core/numerics/pair_blocks.py: gather, SIMD loop, scatter) against brute force.

Each pass is checked against the same equation evaluated with NumPy over every pair of a small disordered cloud
(no neighbour list, no blocks): eq. (1) for the fluid, eq. (5) for Gray's solid (with Monaghan's viscosity,
Gray's artificial stress at n = 4 and n = 3, and the kernel-corrected gradient), and the quadratic fit's force
with the stress gradient's. The clouds are dense enough that some rows hold more than one block of pairs, and
one axis is periodic, so the minimum-image and several-block paths are exercised.
"""
import numpy as np
import pytest

import fluid_bundles
import solid_bundles

from sph_fsi_core.fluid.okaji import summation_density, viscous_velocity
from sph_fsi_core.numerics.kernels import cubic_spline_f, cubic_spline_w
from sph_fsi_core.numerics.neighbours import NeighbourList
from sph_fsi_core.numerics.periodic import xz_periodic_marker
from sph_fsi_core.numerics.pair_blocks import BLOCK
from sph_fsi_core.solid.gradient_integration import gradient_force_rows
from sph_fsi_core.schema import MAX_ART_EXPONENT
from sph_fsi_core.solid.gray2001 import continuity_rate, integer_power, momentum_rate, xsph_velocity_and_gradient
from sph_fsi_core.solid.fitted_gradient import MOMENT_COUNT, N_BASIS, mls_fit_rows, momentum_rate_mls, pair_variant
from sph_fsi_core.numerics.tensors import SYM_INDEX
from sph_fsi_core.solid.stepper import driver_variant

DP = 1e-3
H = 1.6e-3                          # a wide kernel, so that the first rows of the half list exceed one block
SPAN = 8 * DP                       # periodic along y
PERIOD = np.array([0.0, SPAN, 0.0])
CHUNKS = 2


def _cloud(nx=8, nz=6, seed=1):
    rng = np.random.default_rng(seed)
    g = (np.arange(max(nx, nz, 8)) + 0.5) * DP
    pos = np.stack(np.meshgrid(g[:nx], g[:8], g[:nz], indexing="ij"), -1).reshape(-1, 3)
    pos = pos + rng.uniform(-0.12, 0.12, pos.shape) * DP
    pos[:, 1] %= SPAN
    return np.ascontiguousarray(pos), rng


def _separations(a_pos, b_pos):
    """r_a - r_b for every (a, b), minimum image along y."""
    d = a_pos[:, None, :] - b_pos[None, :, :]
    d[..., 1] -= SPAN * np.round(d[..., 1] / SPAN)
    return d


def _kernel_pairs(d):
    r = np.sqrt((d * d).sum(-1))
    w = np.vectorize(lambda x: cubic_spline_w(x, H))(r)
    f = np.vectorize(lambda x: cubic_spline_f(x, H))(r)
    return r, w, f


def _half_list(pos):
    nl = NeighbourList(2 * H, 0.1 * H, period=PERIOD, box_lo=np.zeros(3), box_hi=np.array([1.0, SPAN, 1.0]),
                       half=True)
    nl.build(pos, pos)
    assert np.diff(nl.start).max() > BLOCK   # some rows take two blocks
    return nl


@pytest.mark.parametrize("images", ["rows", "y", "all"])
def test_summation_density_equals_the_sum_over_every_particle(images):
    """Each compilation of the pass against brute force, and all give the same bits: the minimum image along y only
    (periodic.xz_periodic_marker(PERIOD)) and skipped in the rows the lists' `crossing` flags leave out
    ("rows"), along y in every row ("y"), along every axis ("all")."""
    pos, rng = _cloud()
    n = len(pos)
    mass = rng.uniform(0.9, 1.1, n) * 1e-6
    walls = np.ascontiguousarray(np.stack([pos[:, 0], pos[:, 1], np.full(n, -0.5 * DP)], -1)[: n // 2])
    wall_mass = np.full(len(walls), 1e-6)
    box = dict(period=PERIOD, box_lo=np.zeros(3), box_hi=np.array([1.0, SPAN, 1.0]))
    fluid = NeighbourList(2 * H, 0.1 * H, half=True, **box)
    fluid.build(pos, pos)
    assert np.diff(fluid.start).max() > BLOCK   # some rows take two blocks
    wall_list = NeighbourList(2 * H, 0.1 * H, **box)
    wall_list.build(pos, walls)
    flags = fluid.crossing | wall_list.crossing
    assert 0 < flags.sum() < n   # both kinds of row
    assert xz_periodic_marker(PERIOD) is None

    def density(xz_periodic, crossing):
        arrays = fluid_bundles.arrays(pos, mass)
        work = fluid_bundles.buffers(n, fluid.pairs, wall_list.pairs, CHUNKS)
        summation_density(arrays, fluid_bundles.walls(walls, wall_mass),
                          fluid_bundles.neighbours(fluid, wall_list, PERIOD, xz_periodic, crossing),
                          fluid_bundles.params(H), work)
        return arrays.rho, work.f_fluid, work.f_wall

    everywhere = np.ones(n, dtype=np.bool_)
    rho, f_fluid, f_wall = density(*{"rows": (None, flags), "y": (None, everywhere), "all": (True, flags)}[images])
    _, w_ff, _ = _kernel_pairs(_separations(pos, pos))
    _, w_fw, _ = _kernel_pairs(_separations(pos, walls))
    expected = w_ff @ mass + w_fw @ wall_mass
    assert np.abs(rho / expected - 1.0).max() < 1e-13
    for nl, src, cache in ((fluid, pos, f_fluid), (wall_list, walls, f_wall)):
        a = np.repeat(np.arange(n), np.diff(nl.start))
        d = pos[a] - src[nl.index]
        d[:, 1] -= SPAN * np.round(d[:, 1] / SPAN)
        r = np.sqrt((d * d).sum(-1))
        f_ref = np.array([cubic_spline_f(x, H) if x < 2 * H else 0.0 for x in r])
        assert np.abs(cache[:nl.pairs] - f_ref).max() < 1e-12 * np.abs(f_ref).max()
    reference = density(None, everywhere)
    assert all(np.array_equal(x, y) for x, y in zip(reference, (rho, f_fluid, f_wall)))


@pytest.mark.parametrize("images", ["rows", "y", "all"])
def test_viscous_pass_equals_the_sum_over_every_particle(images):
    """Eq. (9) (Morris form) in blocks against NumPy over every pair, each compilation of the pass (as for the
    density), and the three give the same bits."""
    pos, rng = _cloud(seed=3)
    n = len(pos)
    mass = rng.uniform(0.9, 1.1, n) * 1e-6
    rho = rng.uniform(990.0, 1010.0, n)
    vel = rng.normal(0.0, 0.1, (n, 3))
    nl = NeighbourList(2 * H, 0.1 * H, half=True, period=PERIOD, box_lo=np.zeros(3),
                       box_hi=np.array([1.0, SPAN, 1.0]))
    nl.build(pos, pos)
    assert np.diff(nl.start).max() > BLOCK   # some rows take two blocks
    assert 0 < nl.crossing.sum() < n
    a = np.repeat(np.arange(n), np.diff(nl.start))
    d = pos[a] - pos[nl.index]
    d[:, 1] -= SPAN * np.round(d[:, 1] / SPAN)
    f = np.array([cubic_spline_f(x, H) if x < 2 * H else 0.0 for x in np.sqrt((d * d).sum(-1))])
    nu, dt = 1e-4, 1e-4
    everywhere = np.ones(n, dtype=np.bool_)

    def viscous(xz_periodic, crossing):
        out = np.zeros_like(vel)
        viscous_velocity(pos, vel, mass, rho, fluid_bundles.neighbours(nl, None, PERIOD, xz_periodic, crossing),
                         fluid_bundles.buffers(n, nl.pairs, chunks=CHUNKS, f_fluid=f), H, nu, dt, out)
        return out

    out = viscous(*{"rows": (None, nl.crossing), "y": (None, everywhere), "all": (True, nl.crossing)}[images])
    dd = _separations(pos, pos)
    r2 = (dd * dd).sum(-1)
    ff = np.vectorize(lambda x: cubic_spline_f(x, H) if x < 2 * H else 0.0)(np.sqrt(r2))
    mu = rho * nu
    coef = (mu[:, None] + mu[None, :]) / (rho[:, None] * rho[None, :]) * ff * r2 / (r2 + 0.01 * H * H)
    expected = vel + dt * np.einsum("ab,b,abk->ak", coef, mass, vel[:, None, :] - vel[None, :, :])
    change = expected - vel
    assert np.abs(change).max() > 1e-6 * np.abs(vel).max()
    assert np.abs(out - expected).max() < 1e-11 * np.abs(change).max()
    assert np.array_equal(out, viscous(None, everywhere))


@pytest.mark.parametrize("periodic_axes", [(1,), (0, 2)])
def test_crossing_flags_mark_every_row_that_the_minimum_image_changes(periodic_axes):
    """NeighbourList.crossing against brute force: a row is flagged exactly when one of its pairs lies at least
    half the period less 1.1 skins apart along some periodic axis as stored, so every row holding a pair across a
    periodic face is flagged, and rows with no such pair are not; along y alone (the scenes' slabs, the scan's
    y-only compilation) and along x and z (the scan's every-axis compilation, y open)."""
    pos, _ = _cloud()
    period = np.zeros(3)
    for k in periodic_axes:
        period[k] = SPAN
        pos[:, k] %= SPAN
    pos = np.ascontiguousarray(pos)
    nl = NeighbourList(2 * H, 0.1 * H, period=period, box_lo=np.zeros(3), box_hi=np.full(3, SPAN), half=True)
    nl.build(pos, pos)
    assert (nl.xz_periodic is None) == (periodic_axes == (1,))
    a = np.repeat(np.arange(len(pos)), np.diff(nl.start))
    far = np.zeros(len(pos), dtype=bool)
    across = np.zeros(len(pos), dtype=bool)
    for k in periodic_axes:
        stored = np.abs(pos[a, k] - pos[nl.index, k])
        np.logical_or.at(far, a, stored >= 0.5 * SPAN - 1.1 * 0.1 * H)
        np.logical_or.at(across, a, stored > 0.5 * SPAN)
    assert across.any() and not far.all()
    assert np.array_equal(nl.crossing, far)
    assert not (across & ~nl.crossing).any()


def test_solid_passes_skip_the_minimum_image_only_where_it_changes_nothing():
    """NeighbourList.crossing against brute force (a row is flagged when one of its pairs lies at least half the
    period less 1.1 skins apart as stored along the periodic axis), and Gray's three passes (eq. (4) velocity and
    gradient, eq. (3), eq. (5)) with those flags give the same bits as with the image on every row, after every
    particle has moved almost half the skin since the build."""
    pos, rng = _cloud(seed=4)
    n = len(pos)
    nl = _half_list(pos)
    a = np.repeat(np.arange(n), np.diff(nl.start))
    stored = np.abs(pos[a, 1] - pos[nl.index, 1])
    far = np.zeros(n, dtype=bool)
    np.logical_or.at(far, a, stored >= 0.5 * SPAN - 1.1 * 0.1 * H)
    assert 0 < far.sum() < n and np.array_equal(nl.crossing, far)
    step = rng.normal(size=(n, 3))
    moved = pos + 0.499 * 0.1 * H * step / np.linalg.norm(step, axis=1)[:, None]
    mass, rho, vel, sor2, art = _solid_state(moved, rng)
    volume = mass / rho

    def passes(crossing):
        state = solid_bundles.state(moved, vel, rho, mass)
        lists = solid_bundles.neighbours(nl, PERIOD, crossing)
        prm = solid_bundles.params(H, DP, sound_speed=30.0, art_exponent=4)
        work = solid_bundles.buffers(n, nl.pairs, CHUNKS, volume=volume, sigma_over_rho2=sor2, art_stress=art)
        momentum_rate(state, lists, prm, work, np.zeros(3))
        xsph_velocity_and_gradient(state, lists, prm, work)
        continuity_rate(state, lists, work)
        return state.acc, work.w, work.vhat, work.grad_v, work.drho

    flagged, everywhere = passes(nl.crossing), passes(np.ones(n, dtype=np.bool_))
    assert all(np.array_equal(x, y) for x, y in zip(flagged, everywhere))
    wrong = passes(np.zeros(n, dtype=np.bool_))   # the flagged rows do need the image
    assert not np.array_equal(wrong[0], everywhere[0])


def _solid_state(pos, rng):
    n = len(pos)
    mass = rng.uniform(0.9, 1.1, n) * 1e-6
    rho = 1000.0 * (1.0 + rng.uniform(-0.01, 0.01, n))
    vel = rng.normal(scale=0.05, size=(n, 3))
    sigma = rng.normal(scale=1e3, size=(n, 6))
    art = rng.normal(scale=1e2, size=(n, 6))
    return mass, rho, vel, sigma / rho[:, None] ** 2, art / rho[:, None] ** 2


def _full(t):
    """(N, 6) symmetric tensors -> (N, 3, 3)."""
    return t[:, SYM_INDEX]


def _viscous_and_artificial(d, dv, rho, w, alpha, beta, c0, art, exponent, w_dp):
    """-Pi_ab I + R_ab f_ab^n for every pair (a, b) as (N, N, 3, 3)."""
    r2 = (d * d).sum(-1)
    vr = (dv * d).sum(-1)
    mu = H * np.minimum(vr, 0.0) / (r2 + 0.01 * H * H)
    pi = (-alpha * c0 * mu + beta * mu * mu) / (0.5 * (rho[:, None] + rho[None, :]))
    t = -pi[..., None, None] * np.eye(3)
    if exponent:
        ra = _full(art)
        t = t + (ra[:, None] + ra[None, :]) * ((w / w_dp) ** exponent)[..., None, None]
    return t


@pytest.mark.parametrize("exponent, correct", [(0, False), (4, False), (3, False), (4, True)])
def test_gray_momentum_pass_equals_eq_5_summed_over_every_pair(exponent, correct):
    pos, rng = _cloud(seed=2)
    n = len(pos)
    mass, rho, vel, sor2, art = _solid_state(pos, rng)
    kinv = np.linalg.inv(np.eye(3) + 0.1 * rng.normal(size=(n, 3, 3)))
    kinv = np.ascontiguousarray(0.5 * (kinv + kinv.transpose(0, 2, 1)))
    nl = _half_list(pos)
    alpha, beta, c0, w_dp = 1.0, 1.0, 30.0, cubic_spline_w(DP, H)
    acc = np.zeros((n, 3))
    work = solid_bundles.buffers(n, nl.pairs, CHUNKS, sigma_over_rho2=sor2, art_stress=art, kinv=kinv)
    prm = solid_bundles.params(H, DP, sound_speed=c0, alpha=alpha, beta=beta, art_exponent=exponent,
                               inv_w_dp=1.0 / w_dp, velocity_gradient="linear" if correct else "sph")
    momentum_rate(solid_bundles.state(pos, vel, rho, mass, acc=acc), solid_bundles.neighbours(nl, PERIOD), prm, work,
                  np.zeros(3))
    w = work.w
    d = _separations(pos, pos)
    r, wk, fk = _kernel_pairs(d)
    inside = (r < 2 * H) & (r > 0.0)
    g = np.where(inside, fk, 0.0)[..., None] * d                       # grad_a W_ab
    t = _viscous_and_artificial(d, vel[:, None] - vel[None, :], rho, wk, alpha, beta, c0, art, exponent, w_dp)
    s = _full(sor2)
    if correct:
        ga = np.einsum("aij,abj->abi", kinv, g)                           # K_a^-1 g
        gb = np.einsum("bij,abj->abi", kinv, g)
        pair = (np.einsum("aij,abj->abi", s, ga) + np.einsum("bij,abj->abi", s, gb)
                + np.einsum("abij,abj->abi", t, 0.5 * (ga + gb)))
    else:
        pair = np.einsum("abij,abj->abi", s[:, None] + s[None, :] + t, g)
    expected = np.einsum("b,abi->ai", mass, np.where(inside[..., None], pair, 0.0))
    assert np.abs(acc - expected).max() < 1e-11 * np.abs(expected).max()
    a_of = np.repeat(np.arange(n), np.diff(nl.start))
    assert np.abs(w - wk[a_of, nl.index]).max() < 1e-12 * wk.max()


def _basis(u):
    """p(u) of the quadratic fit for (..., 3) offsets u."""
    ux, uy, uz = u[..., 0], u[..., 1], u[..., 2]
    return np.stack([ux, uy, uz, 0.5 * ux * ux, 0.5 * uy * uy, 0.5 * uz * uz, ux * uy, ux * uz, uy * uz], -1)


@pytest.mark.parametrize("exponent, gradient", [(0, False), (4, False), (0, True)])
def test_quadratic_fit_momentum_pass_equals_its_pair_forces_summed_over_every_pair(exponent, gradient):
    pos, rng = _cloud(seed=3)
    n = len(pos)
    mass, rho, vel, sor2, art = _solid_state(pos, rng)
    nl = _half_list(pos)
    rows = np.zeros((n, N_BASIS, N_BASIS))
    mls_fit_rows(pos, PERIOD, mass, rho, nl.start, nl.index, H, rows, np.zeros(n, dtype=np.int64),
                 np.zeros((CHUNKS, n, MOMENT_COUNT)))
    force_rows = np.zeros((n, 3, N_BASIS) if gradient else (0, 3, N_BASIS))
    if gradient:
        gradient_force_rows(mass, rho, rng.normal(scale=1e6, size=(n, 3, 6)), DP * DP / 12.0, rows, force_rows)
    alpha, beta, c0, w_dp = 1.0, 0.5, 30.0, cubic_spline_w(DP, H)
    acc = np.zeros((n, 3))
    weights = np.zeros((nl.pairs, 6))
    prm = solid_bundles.params(H, DP, sound_speed=c0, alpha=alpha, beta=beta, art_exponent=exponent,
                               inv_w_dp=1.0 / w_dp, velocity_gradient="quadratic",
                               nodal_integration="gradient" if gradient else "plain")
    assert driver_variant(prm) == pair_variant(gradient, exponent)
    work = solid_bundles.buffers(n, nl.pairs, CHUNKS, hessian_rows=gradient, sigma_over_rho2=sor2, art_stress=art,
                                 mls_rows=rows, mls_weights=weights, force_rows=force_rows)
    momentum_rate_mls(solid_bundles.state(pos, vel, rho, mass, acc=acc), solid_bundles.neighbours(nl, PERIOD), prm,
                      work, np.zeros(3), driver_variant(prm))
    d = _separations(pos, pos)                                            # r_a - r_b
    r, wk, fk = _kernel_pairs(d)
    inside = (r < 2 * H) & (r > 0.0)
    vol = mass / rho
    p = _basis(-d / H)                                                    # p(u_ab), u_ab = (r_b - r_a) / h
    weight = np.where(inside, wk, 0.0) / H
    g_ab = np.einsum("aik,abk->abi", rows[:, :3], p) * (vol[None, :] * weight)[..., None]
    sigma_v = _full(sor2) * (mass * rho)[:, None, None]                  # V sigma = m rho sigma / rho^2
    phi = np.einsum("aij,abj->abi", sigma_v, g_ab)                       # V_a sigma_a G_ab
    force = phi - phi.transpose(1, 0, 2)
    t = _viscous_and_artificial(d, vel[:, None] - vel[None, :], rho, wk, alpha, beta, c0, art, exponent, w_dp)
    grad_w = np.where(inside, fk, 0.0)[..., None] * d
    force += np.einsum("a,b,abij,abj->abi", mass, mass, t, grad_w)
    if gradient:
        s_ab = vol[None, :] * weight / H                                 # V_b W_ab / h^2
        grad_phi = np.einsum("aik,abk->abi", force_rows, p) * s_ab[..., None]
        force += grad_phi - grad_phi.transpose(1, 0, 2)
    expected = np.where(inside[..., None], force, 0.0).sum(axis=1) / mass[:, None]
    assert np.abs(acc - expected).max() < 1e-11 * np.abs(expected).max()
    a_of = np.repeat(np.arange(n), np.diff(nl.start))
    assert np.abs(weights[:, :3] - g_ab[a_of, nl.index]).max() < 1e-12 * np.abs(g_ab).max()
    assert np.abs(weights[:, 3:] - g_ab[nl.index, a_of]).max() < 1e-12 * np.abs(g_ab).max()


def test_integer_power_covers_every_allowed_exponent():
    """Gray's f_ab^n by squaring: n products in a row to the bit for n <= 4 (Gray's 4 as (x x)(x x)), to an ulp or
    two above, for every n the schema allows."""
    assert MAX_ART_EXPONENT < 16
    for x in (0.0, 0.37, 0.999, 1.0):
        assert integer_power(x, 4) == (x * x) * (x * x)
        for n in range(MAX_ART_EXPONENT + 1):
            product = 1.0
            for _ in range(n):
                product *= x
            if n <= 4:
                assert integer_power(x, n) == product
            else:
                assert integer_power(x, n) == pytest.approx(product, rel=4e-16 * n, abs=0.0)
