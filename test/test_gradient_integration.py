"""Strain-gradient nodal integration (solid.nodal_integration = gradient, sph_fsi_core/solid/gradient_integration.py):
the fit's Hessian, the force paired with it, energy, and what it changes on a beam against 3D elasticity.
"""
import numpy as np
import pytest

from sph_fsi_core.numerics.neighbours import NeighbourList, pair_kernel_values
from sph_fsi_core.answers.oscillation import measure_frequency, period_averaged
from sph_fsi_core.run import run_scene
from sph_fsi_core.scene import SceneError, load_scene
from sph_fsi_core.simulation import Simulation
from sph_fsi_core.solid.gradient_integration import gradient_force_rows, gradient_strain_energy, velocity_hessian
from sph_fsi_core.solid.fitted_gradient import MOMENT_COUNT, N_BASIS, mls_fit_rows, momentum_rate_mls, pair_variant
from sph_fsi_core.numerics.tensors import SYM_INDEX
from sph_fsi_core.solid.stepper import driver_variant
import solid_bundles


def _jittered_bar(seed):
    """4 x 6 particles across, 12 long, at 1 mm, jittered by 5 % of the spacing (every particle near a surface)."""
    dp = 1e-3
    xs, ys, zs = ((np.arange(n) + 0.5) * dp for n in (12, 6, 4))
    pos = np.stack(np.meshgrid(xs, ys, zs, indexing="ij"), -1).reshape(-1, 3)
    rng = np.random.default_rng(seed)
    pos = np.ascontiguousarray(pos + rng.normal(scale=0.05 * dp, size=pos.shape))
    h = 1.3 * dp
    n = len(pos)
    mass, rho = np.full(n, 1e-6), np.full(n, 1000.0)
    nl = NeighbourList(2 * h, 0.1 * h, half=True)
    nl.build(pos, pos)
    rows = np.zeros((n, N_BASIS, N_BASIS))
    order = np.zeros(n, dtype=np.int64)
    mls_fit_rows(pos, np.zeros(3), mass, rho, nl.start, nl.index, h, rows, order, np.zeros((2, n, MOMENT_COUNT)))
    assert (order == 2).all()
    w, f = np.zeros(nl.pairs), np.zeros(nl.pairs)
    pair_kernel_values(pos, pos, nl.start, nl.index, h, np.zeros(3), w, f)
    return pos, h, mass, rho, nl, rows, w


def _hessian(pos, h, mass, rho, nl, rows, w, vel):
    n = len(pos)
    work = solid_bundles.buffers(n, nl.pairs, hessian_rows=True, volume=mass / rho, mls_rows=rows, w=w)
    velocity_hessian(solid_bundles.state(pos, vel, rho, mass), solid_bundles.neighbours(nl),
                     solid_bundles.params(h, 1e-3), work)
    return work.hessian


def test_fitted_hessian_is_exact_for_quadratic_velocity_fields_up_to_the_corners():
    pos, h, mass, rho, nl, rows, w = _jittered_bar(seed=5)
    rng = np.random.default_rng(2)
    a = rng.normal(size=(3, 3))
    b = rng.normal(size=(3, 3, 3)) / 0.01
    b = 0.5 * (b + b.transpose(0, 2, 1))      # v_i = a_ij x_j + b_ijk x_j x_k / 2: Hessian of v_i is b_i
    vel = np.ascontiguousarray(pos @ a.T + 0.5 * np.einsum("ijk,nj,nk->ni", b, pos, pos))
    hessian = _hessian(pos, h, mass, rho, nl, rows, w, vel)
    exact = np.array([[b[i, j, k] for j, k in ((0, 0), (1, 1), (2, 2), (0, 1), (0, 2), (1, 2))] for i in range(3)])
    assert np.abs(hessian - exact[None]).max() < 1e-8 * np.abs(b).max()


def test_gradient_force_conserves_momentum_and_pairs_with_the_gradient_stress_power():
    """sum m a = 0, and sum_a F_a . v_a = -sum_a V_a m sum_k T_a[k] : d_k L_a for any T and v."""
    pos, h, mass, rho, nl, rows, w = _jittered_bar(seed=9)
    n = len(pos)
    rng = np.random.default_rng(4)
    vel = np.ascontiguousarray(rng.normal(scale=0.01, size=(n, 3)))
    t = rng.normal(scale=1e6, size=(n, 3, 6))
    cell_moment = 1e-6 / 12.0
    acc = np.zeros((n, 3))
    force_rows = np.zeros((n, 3, 9))
    gradient_force_rows(mass, rho, t, cell_moment, rows, force_rows)
    # the momentum pass with no stress and no viscosity: the stress gradient's force alone
    prm = solid_bundles.params(h, 1e-3, sound_speed=1.0, alpha=0.0, beta=0.0, inv_w_dp=1.0,
                               velocity_gradient="quadratic", nodal_integration="gradient")
    assert driver_variant(prm) == pair_variant(True, 0)
    momentum_rate_mls(solid_bundles.state(pos, vel, rho, mass, acc=acc), solid_bundles.neighbours(nl), prm,
                      solid_bundles.buffers(n, nl.pairs, hessian_rows=True, mls_rows=rows, w=w,
                                            force_rows=force_rows), np.zeros(3), driver_variant(prm))
    force = mass[:, None] * acc
    assert np.abs(force.sum(axis=0)).max() < 1e-12 * np.abs(force).sum()
    hessian = _hessian(pos, h, mass, rho, nl, rows, w, vel)
    full = np.zeros((n, 3, 3, 3))   # T[k] as full symmetric tensors
    for c, (i, j) in enumerate(((0, 0), (1, 1), (2, 2), (0, 1), (0, 2), (1, 2))):
        full[:, :, i, j] = full[:, :, j, i] = t[:, :, c]
    dl = np.zeros((n, 3, 3, 3))     # d_k L_ij = d_k d_j v_i
    for i in range(3):
        for j in range(3):
            for k in range(3):
                dl[:, k, i, j] = hessian[:, i, SYM_INDEX[j, k]]
    power = (mass / rho * cell_moment * np.einsum("nkij,nkij->n", full, dl)).sum()
    assert abs((force * vel).sum() + power) < 1e-10 * abs(power)


def test_momentum_pass_refuses_a_pair_variant_that_does_not_match_its_force_rows():
    """The block kernel's loop is chosen by pair_variant's type: a variant without the gradient integration and
    force rows that carry it would leave the gradient force out of the block and read stale columns; refused."""
    pos, h, mass, rho, nl, rows, w = _jittered_bar(seed=9)
    n = len(pos)
    prm = solid_bundles.params(h, 1e-3, sound_speed=1.0, alpha=0.0, beta=0.0, inv_w_dp=1.0,
                               velocity_gradient="quadratic")
    work = solid_bundles.buffers(n, nl.pairs, hessian_rows=True, mls_rows=rows, w=w)
    assert work.force_rows.shape == (n, 3, 9)
    assert pair_variant(True, 0) == () and pair_variant(True, 4) == (0,) and pair_variant(False, 3) == (0,) * 5
    with pytest.raises(ValueError, match="pair variant"):
        momentum_rate_mls(solid_bundles.state(pos, np.zeros((n, 3)), rho, mass), solid_bundles.neighbours(nl), prm,
                          work, np.zeros(3), pair_variant(False, 0))


def test_gradient_energy_of_a_bent_lattice_beam_makes_up_the_missing_second_moment():
    """Pure bending sigma_xx = E k z on 4 layers (nu = 0.5, where all of it is deviatoric): plain nodal integration
    gives sum z^2 = 5 dp^2 where the continuum has H^3 / 12 = 16 / 3 dp^2; the cell term adds dp^2 / 12 per layer,
    the missing 1 / 3."""
    dp, e_mod, kappa = 1e-3, 2e6, 3.0
    z = (np.arange(4) - 1.5) * dp
    n = len(z)
    mass, rho = np.full(n, 1000.0 * dp ** 3), np.full(n, 1000.0)
    t = np.zeros((n, 3, 6))
    t[:, 2, :3] = e_mod * kappa * np.array([2.0, -1.0, -1.0]) / 3.0   # d_z S, the deviator of d_z sigma_xx
    shear = e_mod / 3.0                                               # nu = 0.5: uniaxial energy s^2 / (2E)
    plain = (mass / rho * (e_mod * kappa * z) ** 2 / (2 * e_mod)).sum()
    gradient = gradient_strain_energy(mass, rho, t, dp ** 2 / 12.0, shear)
    continuum = e_mod * kappa ** 2 / 2 * (4 * dp) ** 3 / 12 * dp ** 2   # per dp x dp of beam
    assert plain == pytest.approx(continuum * 5 / (16 / 3), rel=1e-12)
    assert plain + gradient == pytest.approx(continuum, rel=1e-9)


def test_gradient_energy_of_a_pressure_gradient_is_its_volumetric_energy():
    """solid.volumetric_gradient: T[k] with an isotropic part -q I (the gradient of a pressure) stores V m q^2 / (2K)
    per direction, the cell's energy of a pressure varying by q per metre across it; the deviator's part unchanged."""
    dp, bulk, shear, q = 1e-3, 5e7, 1e6, 3e5
    mass, rho = np.full(2, 1000.0 * dp ** 3), np.full(2, 1000.0)
    t = np.zeros((2, 3, 6))
    t[:, 1, :3] = -q
    m = dp ** 2 / 12.0
    assert gradient_strain_energy(mass, rho, t, m, shear, bulk) == pytest.approx(2 * dp ** 3 * m * q ** 2 / (2 * bulk),
                                                                               rel=1e-12)
    assert gradient_strain_energy(mass, rho, t, m, shear) == pytest.approx(0.0, abs=1e-30)


# The pressure explicit and the fit remade, as these were measured: they watch the energy, which the implicit
# pressure (the default scheme's) does not keep: it damps the pressure waves (test_implicit_pressure.py)
SMALL_BEAM = ["geometry.length=0.012", "geometry.width=0.003", "geometry.clamp_margin=2",
              "output.snapshot_interval=0", "output.timeseries_interval=5e-5", "scene.end_time=0.03",
              "solid.artificial_viscosity_alpha=0", "solid.pressure=explicit", "solid.fit_refresh=remake"]


@pytest.fixture(scope="module")
def small_beam():
    out = {}
    for mode in ("plain", "gradient"):
        rows = []
        spec = load_scene("cantilever", SMALL_BEAM + [f"solid.nodal_integration={mode}"])
        summary = run_scene(spec, None, progress=False, on_sample=lambda sim, row: rows.append(row))
        t = np.array([r["time"] for r in rows])
        z = np.array([r["tip_dz"] for r in rows])
        energy = np.array([r["kinetic_energy"] + r["strain_energy"] for r in rows])
        out[mode] = summary, t, z, energy
    return out


@pytest.mark.slow
def test_inviscid_beam_keeps_its_energy_with_the_gradient_term(small_beam):
    """Measured: last over first period-mean 0.99999 (plain: 0.9999999)."""
    _, t, z, energy = small_beam["gradient"]
    _, means = period_averaged(t, energy, measure_frequency(t, z).frequency)
    assert len(means) >= 4
    assert abs(means[-1] / means[0] - 1.0) < 1e-4


@pytest.mark.slow
def test_gradient_integration_brings_the_short_beam_towards_3d_elasticity(small_beam):
    """12 x 3 x 4 mm at H/dp = 4. 3D elasticity (fe_reference, quadratic hexahedra): 186.80 Hz with 1 mm elements,
    184.41 Hz with 0.5 mm, converging from above. Measured: plain 165.0 Hz (-10.5 % against 184.4), gradient
    172.9 Hz (-6.2 %; this stubby beam, L/H = 3, shears as much as it bends, and the term corrects bending)."""
    from sph_fsi_core.answers.fe_reference import cantilever_fe_frequency
    fe = cantilever_fe_frequency(0.012, thickness=0.004, width=0.003, young_modulus=1.859e6, poisson_ratio=0.49,
                                 density=1000.0, element_size=1e-3)["vertical_hz"]
    plain, gradient = (small_beam[m][0]["frequency_hz"] for m in ("plain", "gradient"))
    assert plain * 1.03 < gradient < fe


def test_gradient_integration_needs_the_quadratic_fit():
    with pytest.raises(SceneError, match="solid.nodal_integration"):
        Simulation(load_scene("cantilever", ["solid.nodal_integration=gradient", "solid.velocity_gradient=sph",
                                             "solid.pressure=explicit"]))


def test_volumetric_gradient_needs_the_gradient_integration():
    with pytest.raises(SceneError, match="solid.volumetric_gradient"):
        Simulation(load_scene("cantilever", ["solid.scheme=quadratic_plain", "solid.volumetric_gradient=true"]))


def _locked_fraction(extra):
    """Strain energy's share of the total at each zero crossing of the free end (a clean mode has ~0 there)."""
    rows = []
    spec = load_scene("cantilever", SMALL_BEAM + ["geometry.tip_velocity=0.3", "output.timeseries_interval=2e-5",
                                                  "solid.nodal_integration=gradient"] + extra)
    run_scene(spec, None, progress=False, on_sample=lambda sim, row: rows.append(row))
    z = np.array([r["tip_dz"] for r in rows])
    se = np.array([r["strain_energy"] for r in rows])
    ke = np.array([r["kinetic_energy"] for r in rows])
    crossings = [i for i in range(1, len(z)) if z[i - 1] * z[i] < 0]
    return se[crossings] / (se[crossings] + ke[crossings])


@pytest.mark.slow
@pytest.mark.parametrize("refresh", ["remake", "rotate"])
def test_the_fit_refreshed_as_the_beam_turns_locks_no_energy_in_self_balanced_stress(refresh):
    """12 mm beam swinging at 0.3 m/s, ten zero crossings. With the fit's rows remade only at neighbour-list builds
    (a refresh turn of 1 and a strain of 1, never reached) the stale rows leak rotation into the fitted curvature and
    the strain energy left at the crossings grows, measured 1 % -> 28 % of the total; with the default refresh (1e-4
    with the gradient integration: rows remade, or turned with the particle and remade at 1e-3 of strain) it stays at
    the 1-2 % of the higher modes the initial shape excites."""
    stale = _locked_fraction([f"solid.fit_refresh={refresh}", "solid.fit_refresh_turn=1.0",
                              "solid.fit_refresh_strain=1.0"])
    fresh = _locked_fraction([f"solid.fit_refresh={refresh}"])
    assert len(fresh) >= 9
    assert stale[-1] > 0.15 and stale[-1] > 5 * stale[0]
    assert fresh.max() < 0.04


@pytest.mark.slow
def test_the_volumetric_gradient_locks_no_energy_either():
    """solid.volumetric_gradient on the same swinging beam with the default refresh: its first version, made
    before the fit was refreshed, locked half of the tip's amplitude within 0.1 s (docs/method.md); with fresh rows
    the strain energy at the crossings stays at the higher modes' 1-2 %, as without it."""
    assert _locked_fraction(["solid.volumetric_gradient=true"]).max() < 0.04


def test_two_layer_beam_keeps_the_linear_fit_as_it_bends_and_the_fit_is_remade():
    """At 2 mm the paper's beam is two particles thick: its z direction cannot determine a quadratic (u_z and
    u_z^2 / 2 are collinear over the neighbours, Cholesky pivot 1e-16 of the diagonal) and the fit falls back to
    linear. Bending lifts that pivot with the square of the distortion; with a pivot tolerance of 1e-6 the refits
    (remade every ~100 steps as the beam turns) flipped such particles to ill-determined quadratic fits and the run
    blew up at 2.75 ms. Measured now: no particle changes its fit order over 20 ms (its rows remade or turned as it
    moves), and the run is stable."""
    sim = Simulation(load_scene("cantilever", ["numerics.spacing=0.002", "output.snapshot_interval=0"]))
    order = sim.solid_phase.solver.work.mls_order.copy()
    moving = sim.solid.movable
    # every moving particle linear (the root's 12 had quadratic fits while the mirrored clamp kept the fixed clamp's
    # margin above and below the root: config/cantilever.yaml)
    assert (order[moving] == 1).sum() == 120
    while sim.time < 0.02:
        sim.step()
        assert (sim.solid_phase.solver.work.mls_order == order).all()
    assert sim.solid_phase.steps > 900      # 20 ms in steps of the deviatoric waves (the implicit pressure)
    assert np.isfinite(sim.solid.vel).all() and np.abs(sim.solid.vel).max() < 0.02
