"""A particle solid's small-strain stiffness assembled as a matrix, its modes and its static answers: the accuracy
of a solid scheme's discretisation, and its explicit step's stability limit, without time stepping.

A nodal-integrated particle solid whose displacement gradient at particle a is a weighted sum over its neighbours,

    grad u_a = sum_b (u_b - u_a) (x) G_ab,

and whose force is the one whose power is the stress power (variationally consistent: the project's quadratic fit,
solid/fitted_gradient.py, and total-Lagrangian SPH) stores E = 1/2 sum_a V_a eps_a : C : eps_a at small strain,
eps_a = sym(grad u_a), C isotropic (E, nu). Its stiffness K = B^T (V C) B and lumped mass M = diag(m) give the free
vibration's frequencies from one generalised eigenproblem K phi = omega^2 M phi over the movable particles (a fixed
clamp's particles keep u = 0 but their strain, which the body's motion sets, stores energy as they do in the
time-stepped schemes). This is the frequency a scheme's time stepping converges to as the amplitude and the step go
to zero (checked against the time-stepped beams and plate in test/test_linear_modes.py); K u = f its settled answer
under a static load.

Operators (`weights`):
- 'corrected_kernel': total-Lagrangian SPH (O'Connor & Rogers 2021, as in TrixiParticles, SPHinXsys and
  DualSPHysics' flexstruc): the kernel gradient on the reference configuration corrected to be exact for linear
  fields, G_ab = V_b M_a^-T grad_a W_ab with M_a = sum_b V_b (X_b - X_a) (x) grad_a W_ab. With `hourglass_alpha`
  > 0, Ganzenmueller 2015's hourglass penalty (TrixiParticles' PenaltyForceGanzenmueller), linearised: the pair
  force alpha/2 V_a V_b W_ab / r^2 E delta n, delta = ((grad u_a + grad u_b) X_ab - 2 u_ab) . n, which is not the
  gradient of an energy, so K is then not symmetric.
- 'quadratic_fit': the quadratic fit's gradient rows (solid/fitted_gradient.py's G_ab = V_b W_ab R_a p(u) / h), the
  plain nodal sum: the project's `quadratic_plain` scheme at small strain; with `nodal_integration` 'gradient' the
  strain-gradient term from the fit's Hessian rows (solid/gradient_integration.py) and the mirrored clamp's ghosts
  as a map from the body's displacements: the default scheme, `quadratic_gradient`.
"""
import math

import numpy as np

from ..numerics.kernels import SUPPORT_RADIUS_IN_H
from ..schema import solid_smoothing_ratio
from ..solid.gray2001 import material_constants
from ..solid.implicit_pressure import deviatoric_wave_speed

WEIGHTS = ("corrected_kernel", "quadratic_fit")


def _kernel_w_f(r, h):
    """W and F = (dW/dr) / r of the M4 cubic spline (numerics/kernels.py), vectorised."""
    q = r / h
    t2 = np.maximum(2.0 - q, 0.0)
    t1 = np.maximum(1.0 - q, 0.0)
    sigma = 1.0 / (math.pi * h ** 3)
    w = sigma * (0.25 * t2 ** 3 - t1 ** 3)
    f = sigma / h * (-0.75 * t2 ** 2 + 3.0 * t1 ** 2) / np.maximum(r, 1e-300)
    return w, f


def pairs(pos, h, period=None):
    """(a, b, d): every ordered pair within the kernel's support 2h (a != b), d = X_b - X_a (the minimum image
    along the axes where `period` > 0: a periodic slab)."""
    from scipy.spatial import cKDTree
    cutoff = SUPPORT_RADIUS_IN_H * h * (1.0 - 1e-12)
    period = np.zeros(3) if period is None else np.asarray(period, dtype=float)
    lo = pos.min(axis=0)
    box = np.where(period > 0.0, period, pos.max(axis=0) - lo + 4.0 * cutoff)
    shifted = np.mod(pos - lo, box)
    ij = cKDTree(shifted, boxsize=box).query_pairs(cutoff, output_type="ndarray")
    a = np.concatenate([ij[:, 0], ij[:, 1]])
    b = np.concatenate([ij[:, 1], ij[:, 0]])
    d = pos[b] - pos[a]
    wrap = period > 0.0
    d[:, wrap] -= period[wrap] * np.round(d[:, wrap] / period[wrap])
    return a, b, d


def corrected_kernel_weights(n, a, b, d, volume, h):
    """G_ab (pairs, 3) of total-Lagrangian SPH: V_b M_a^-T grad_a W_ab, exact for linear fields."""
    r = np.linalg.norm(d, axis=1)
    _, f = _kernel_w_f(r, h)
    grad = -f[:, None] * d                      # grad_a W_ab = F (X_a - X_b)
    vg = volume[b][:, None] * grad
    m = np.zeros((n, 3, 3))
    np.add.at(m, a, d[:, :, None] * vg[:, None, :])
    minv_t = np.transpose(np.linalg.inv(m), (0, 2, 1))
    return np.einsum("pij,pj->pi", minv_t[a], vg)


def _quadratic_fit_rows(n, a, b, d, volume, h):
    """(p, V_b W_ab, M_a^-1) of the quadratic fit over the pairs (solid/fitted_gradient.py): the basis p(u_ab),
    u = d / h, and each particle's inverse moment matrix M_a = sum_b V_b W_ab p p^T. Every particle's fit must be
    determined (three layers or more in each direction): ValueError else."""
    u = d / h
    p = np.column_stack([u[:, 0], u[:, 1], u[:, 2], 0.5 * u[:, 0] ** 2, 0.5 * u[:, 1] ** 2, 0.5 * u[:, 2] ** 2,
                         u[:, 0] * u[:, 1], u[:, 0] * u[:, 2], u[:, 1] * u[:, 2]])
    w, _ = _kernel_w_f(np.linalg.norm(d, axis=1), h)
    vw = volume[b] * w
    m = np.zeros((n, 9, 9))
    np.add.at(m, a, vw[:, None, None] * p[:, :, None] * p[:, None, :])
    if np.any(np.linalg.cond(m) > 1e12):
        raise ValueError("a quadratic fit is not determined (fewer than three particle layers in some direction)")
    return p, vw, np.linalg.inv(m)


def quadratic_fit_weights(n, a, b, d, volume, h):
    """G_ab (pairs, 3) of the quadratic fit (solid/fitted_gradient.py): V_b W_ab R_a p(u_ab) / h, R_a the first
    three rows of M_a^-1."""
    p, vw, minv = _quadratic_fit_rows(n, a, b, d, volume, h)
    return vw[:, None] * np.einsum("pij,pj->pi", minv[a, :3, :], p) / h


def quadratic_fit_hessian_weights(n, a, b, d, volume, h):
    """Gh_ab (pairs, 6) of the fitted second derivatives d_j d_k u_a = sum_b (u_b - u_a) Gh_ab[jk], jk in the order
    xx, yy, zz, xy, xz, yz: V_b W_ab (rows 3..8 of M_a^-1) p(u_ab) / h^2 (solid/gradient_integration.py)."""
    p, vw, minv = _quadratic_fit_rows(n, a, b, d, volume, h)
    return vw[:, None] * np.einsum("pij,pj->pi", minv[a, 3:, :], p) / h ** 2


def pair_difference_operator(n, a, b, g):
    """Sparse (3 C n x 3n): sum_b (u_b,i - u_a,i) g_ab[c] for every particle a, displacement component i and weight
    column c of g (pairs, C), row 3 C a + C i + c, from the displacements, column 3 e + i. With the gradient
    weights (C = 3) the displacement gradient d u_i / d X_j; with the Hessian weights (C = 6) d_j d_k u_i."""
    from scipy.sparse import coo_matrix
    width = g.shape[1]
    rows, cols, vals = [], [], []
    for i in range(3):
        for c in range(width):
            rows += [3 * width * a + width * i + c] * 2
            cols += [3 * b + i, 3 * a + i]
            vals += [g[:, c], -g[:, c]]
    return coo_matrix((np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))),
                      shape=(3 * width * n, 3 * n)).tocsr()


def gradient_operator(n, a, b, g):
    """Sparse (9n x 3n): the displacement gradient grad u_a = sum_b (u_b - u_a) (x) G_ab of every particle, row
    9 a + 3 i + j = d u_i / d X_j."""
    return pair_difference_operator(n, a, b, g)


def strain_operator(grad):
    """Sparse (6n x 3n): the Voigt strain (xx, yy, zz, 2xy, 2xz, 2yz) of every particle from gradient_operator's
    displacement gradient."""
    from scipy.sparse import coo_matrix
    n = grad.shape[0] // 9
    voigt = [((0, 0),), ((1, 1),), ((2, 2),), ((0, 1), (1, 0)), ((0, 2), (2, 0)), ((1, 2), (2, 1))]
    rows, cols = [], []
    for k, comps in enumerate(voigt):
        for (i, j) in comps:
            rows.append(6 * np.arange(n) + k)
            cols.append(9 * np.arange(n) + 3 * i + j)
    pick = coo_matrix((np.ones(9 * n), (np.concatenate(rows), np.concatenate(cols))), shape=(6 * n, 9 * n))
    return (pick.tocsr() @ grad).tocsr()


def isotropic_voigt(young, nu, deviatoric=False):
    """C (6 x 6) of isotropic linear elasticity on Voigt strain with engineering shears; `deviatoric`: its
    deviatoric part only, 2 G (I - 1 1^T / 3) on the normal strains (what an implicit pressure leaves explicit)."""
    mu = young / (2.0 * (1.0 + nu))
    lam = -2.0 * mu / 3.0 if deviatoric else young * nu / ((1.0 + nu) * (1.0 - 2.0 * nu))
    c = np.zeros((6, 6))
    c[:3, :3] = lam
    c[np.arange(3), np.arange(3)] += 2.0 * mu
    c[np.arange(3, 6), np.arange(3, 6)] = mu
    return c


def elastic_stiffness(strain, volume, young, nu, deviatoric=False):
    """K = Bv^T diag(V_a C) Bv (3n x 3n, sparse, symmetric)."""
    from scipy.sparse import kron, diags
    return (strain.T @ kron(diags(volume), isotropic_voigt(young, nu, deviatoric), format="csr") @ strain).tocsr()


# (j, k) -> index of d_j d_k in the Hessian's order xx, yy, zz, xy, xz, yz
_HESSIAN_INDEX = ((0, 3, 4), (3, 1, 5), (4, 5, 2))
_TENSOR_PAIRS = ((0, 0), (1, 1), (2, 2), (0, 1), (0, 2), (1, 2))


def strain_gradient_stiffness(n, a, b, gh, energy_volume, shear_modulus, cell_moment, bulk_modulus=0.0):
    """K_g (3n x 3n, sparse, symmetric) of the strain-gradient nodal integration (solid/gradient_integration.py) at
    small strain: the energy sum_a V_a m G sum_k |dev(d_k eps_a)|^2, d_k eps_ij = (d_k d_j u_i + d_k d_i u_j) / 2
    from the fitted Hessian, m = dp^2 / 12: only the deviatoric part, as the scheme; `bulk_modulus` K adds the
    volumetric one, m K / 2 sum_k (tr d_k eps_a)^2 per volume (not the scheme's: measured, docs/method.md)."""
    from scipy.sparse import coo_matrix, kron, diags
    hess = pair_difference_operator(n, a, b, gh)     # rows 18 a + 6 i + jk
    # d_k eps_ij in rows 18 a + 6 k + (ij), tensor components xx, yy, zz, xy, xz, yz
    rows, cols, vals = [], [], []
    for k in range(3):
        for c, (i, j) in enumerate(_TENSOR_PAIRS):
            for (first, second) in ((i, j), (j, i)):
                rows.append(18 * np.arange(n) + 6 * k + c)
                cols.append(18 * np.arange(n) + 6 * first + _HESSIAN_INDEX[k][second])
                vals.append(np.full(n, 0.5))
    pick = coo_matrix((np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))), shape=(18 * n, 18 * n))
    grad_eps = (pick.tocsr() @ hess).tocsr()
    # |dev e|^2 = e : P e on tensor components: the normal part's deviator, shears counted twice
    q = np.zeros((6, 6))
    q[:3, :3] = np.eye(3) - 1.0 / 3.0
    q[3:, 3:] = 2.0 * np.eye(3)
    q[:3, :3] += bulk_modulus / (2.0 * shear_modulus)
    weight = kron(diags(2.0 * shear_modulus * cell_moment * energy_volume), np.kron(np.eye(3), q), format="csr")
    return (grad_eps.T @ weight @ grad_eps).tocsr()


def hourglass_stiffness(grad, a, b, d, volume, h, young, alpha):
    """K_hg (3n x 3n, sparse, not symmetric): minus the derivative of the linearised Ganzenmueller penalty force,
    each unordered pair once, +f on a and -f on b: f = k delta n, k = alpha/2 V_a V_b W_ab / r^2 E, n the unit
    vector from b to a, delta = ((grad u_a + grad u_b) X_ab - 2 (u_a - u_b)) . n (module docstring)."""
    from scipy.sparse import coo_matrix, diags
    n = grad.shape[0] // 9
    once = a < b
    a, b, d = a[once], b[once], d[once]
    x_ab = -d
    r = np.linalg.norm(x_ab, axis=1)
    nrm = x_ab / r[:, None]
    w, _ = _kernel_w_f(r, h)
    k = 0.5 * alpha * volume[a] * volume[b] * w / r ** 2 * young
    pair = np.arange(len(a))
    rows, cols, vals = [], [], []
    for i in range(3):
        rows += [pair, pair]
        cols += [3 * a + i, 3 * b + i]
        vals += [-2.0 * nrm[:, i], 2.0 * nrm[:, i]]
    delta = coo_matrix((np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))),
                       shape=(len(a), 3 * n)).tocsr()
    for c in (a, b):
        for i in range(3):
            for j in range(3):
                delta = delta + diags(nrm[:, i] * x_ab[:, j]) @ grad[9 * c + 3 * i + j]
    rows, cols, vals = [], [], []
    for i in range(3):
        rows += [3 * a + i, 3 * b + i]
        cols += [pair, pair]
        vals += [k * nrm[:, i], -k * nrm[:, i]]
    spread = coo_matrix((np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))), shape=(3 * n, len(a)))
    return -(spread.tocsr() @ delta).tocsr()


def stiffness(pos, volume, h, young, nu, weights="corrected_kernel", hourglass_alpha=0.0,
              nodal_integration="plain", cell_moment=0.0, stores_energy=None, volumetric_gradient=False,
              deviatoric=False, period=None):
    """The assembled K (3n x 3n, sparse) of the particles at `pos` (their reference configuration). Particles where
    `stores_energy` is False (a mirrored clamp's ghosts) lend their positions to the fits but store no energy.
    `volumetric_gradient`: the strain-gradient term's volumetric part too (solid.volumetric_gradient, stepped
    explicitly); `deviatoric`: without the local volumetric stiffness (what the implicit pressure solves for)."""
    n = len(pos)
    a, b, d = pairs(pos, h, period)
    make = {"corrected_kernel": corrected_kernel_weights, "quadratic_fit": quadratic_fit_weights}[weights]
    grad = gradient_operator(n, a, b, make(n, a, b, d, volume, h))
    energy_volume = volume if stores_energy is None else np.where(stores_energy, volume, 0.0)
    k = elastic_stiffness(strain_operator(grad), energy_volume, young, nu, deviatoric)
    if nodal_integration == "gradient":
        if weights != "quadratic_fit":
            raise ValueError("the strain-gradient integration needs the quadratic fit's Hessian")
        gh = quadratic_fit_hessian_weights(n, a, b, d, volume, h)
        bulk, shear, _ = material_constants(young, nu, 1.0)
        k = k + strain_gradient_stiffness(n, a, b, gh, energy_volume, shear, cell_moment,
                                          bulk if volumetric_gradient else 0.0)
    if hourglass_alpha > 0.0:
        k = k + hourglass_stiffness(grad, a, b, d, energy_volume, h, young, hourglass_alpha)
    return k


def mirrored_clamp_map(mirror, movable):
    """P (3n x 3m, sparse): every particle's displacement from the m movable ones', a mirrored clamp's ghost the
    negative of its image's (u_g = -u_m, solid/stepper.py), other fixed particles none."""
    from scipy.sparse import coo_matrix
    n = len(movable)
    body = np.flatnonzero(movable)
    column = np.full(n, -1)
    column[body] = np.arange(len(body))
    ghosts = np.flatnonzero(mirror >= 0)
    rows, cols, vals = [], [], []
    for i in range(3):
        rows += [3 * body + i, 3 * ghosts + i]
        cols += [3 * column[body] + i, 3 * column[mirror[ghosts]] + i]
        vals += [np.ones(len(body)), -np.ones(len(ghosts))]
    return coo_matrix((np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))),
                      shape=(3 * n, 3 * len(body))).tocsr()


def lowest_modes(k, mass, movable, count=12, shift=0.0, clamp_map=None):
    """The `count` lowest free-vibration modes over the movable particles: (frequencies in Hz, ascending, and the
    mode shapes (count, n, 3): with `clamp_map` (mirrored_clamp_map) the ghosts follow their images, else the fixed
    particles stay at rest). K need not be symmetric (then the real parts)."""
    from scipy.sparse import diags
    from scipy.sparse.linalg import eigs, eigsh
    n = len(mass)
    if clamp_map is None:
        clamp_map = _movable_map(movable)
    kk = clamp_map.T @ k @ clamp_map
    m = np.repeat(mass[movable], 3)
    scale = diags(1.0 / np.sqrt(m))
    a = (scale @ kk @ scale).tocsc()
    symmetric = abs(a - a.T).max() <= 1e-10 * abs(a).max()
    if symmetric:
        lam, vec = eigsh(a, k=count, sigma=shift, which="LM")
    else:
        lam, vec = eigs(a, k=count, sigma=shift, which="LM")
        lam, vec = lam.real, vec.real
    order = np.argsort(lam)
    lam, vec = lam[order], vec[:, order] / np.sqrt(m)[:, None]
    shapes = (clamp_map @ vec).T.reshape(count, n, 3)
    return np.sqrt(np.maximum(lam, 0.0)) / (2.0 * math.pi), shapes


def first_bending_mode(freqs, shapes, mass, axis=2, fraction=0.3):
    """(index, frequency) of the lowest mode whose effective mass along `axis` is at least `fraction` of the
    body's (a beam's first bending mode: about 0.61); the modes below it are spurious (zero-energy) ones."""
    total = mass.sum()
    for i, shape in enumerate(shapes):
        u = shape[:, axis]
        participation = (mass @ u) ** 2 / (mass @ (shape ** 2).sum(axis=1)) / total
        if participation >= fraction:
            return i, float(freqs[i])
    raise ValueError(f"no mode among the lowest {len(freqs)} moves the body along axis {axis}")


def _built(scene, overrides, clamp):
    """(values, built) of a scene with solid.clamp = `clamp`."""
    from ..scene import load_scene
    from ..scenes import BUILDERS
    spec = load_scene(scene, [f"solid.clamp={clamp}", *overrides])
    return spec.values, BUILDERS[spec.builder].build(spec.values)


def _built_stiffness(values, built, clamp, **kw):
    """(K, clamp_map) of a built scene's solid (its periodic slab's pairs across the period); mirrored: the ghosts
    store no energy and follow their images, fixed: the clamp's particles stay at rest."""
    solid = built.solid
    dp = values["numerics.spacing"]
    mirrored = clamp == "mirrored"
    k = stiffness(solid.pos, solid.mass / solid.rho, solid_smoothing_ratio(values) * dp,
                  values["solid.young_modulus"], values["solid.poisson_ratio"], cell_moment=dp * dp / 12.0,
                  stores_energy=solid.movable if mirrored else None, period=built.period, **kw)
    return k, (mirrored_clamp_map(built.clamp_mirror, solid.movable) if mirrored else _movable_map(solid.movable))


def cantilever_frequency(overrides=(), weights="corrected_kernel", hourglass_alpha=0.0, count=12,
                         nodal_integration="plain", clamp="fixed", volumetric_gradient=False):
    """The first bending frequency of the cantilever scene's beam as built, assembled by this module, against the
    beam's 3D FE reference: a dict. `clamp` fixed (its particles at rest, storing energy; the scene's
    geometry.clamp_margin) or mirrored (the ghosts following their images, storing none); `nodal_integration`
    gradient adds the strain-gradient term (with the quadratic fit): the default scheme, quadratic_gradient."""
    from ..answers.references import cantilever_references
    v, built = _built("cantilever", overrides, clamp)
    solid = built.solid
    k, clamp_map = _built_stiffness(v, built, clamp, weights=weights, hourglass_alpha=hourglass_alpha,
                                         nodal_integration=nodal_integration,
                                         volumetric_gradient=volumetric_gradient)
    refs = cantilever_references(v["geometry.length"], v["geometry.thickness"], v["geometry.width"],
                                 v["solid.young_modulus"], v["solid.poisson_ratio"], v["solid.density"])
    ref = refs["reference_hz"]
    freqs, shapes = lowest_modes(k, solid.mass, solid.movable, count=count, shift=-(0.05 * 2 * math.pi * ref) ** 2,
                                 clamp_map=clamp_map)
    index, f = first_bending_mode(freqs, shapes, solid.mass * solid.movable)
    return {"frequency_hz": f, "reference_hz": ref, "reference": refs["judged_against"],
            "error": f / ref - 1.0, "spurious_modes_below": index, "lowest_hz": freqs.tolist()}


def highest_frequency(k, mass, movable, clamp_map=None):
    """omega_max (rad/s) of K phi = omega^2 M phi over the movable particles: leapfrog is stable for dt < 2 /
    omega_max."""
    from scipy.sparse import diags
    from scipy.sparse.linalg import eigsh
    if clamp_map is None:
        clamp_map = _movable_map(movable)
    scale = diags(1.0 / np.sqrt(np.repeat(mass[movable], 3)))
    a = (scale @ (clamp_map.T @ k @ clamp_map) @ scale).tocsc()
    return float(math.sqrt(eigsh(a, k=1, which="LA", return_eigenvectors=False)[0]))


def default_scheme_stable_cfl(overrides=(), volumetric_gradient=False):
    """The largest solid.cfl at which the default scheme's explicit part (the deviatoric stress and its gradient;
    the pressure is implicit) is linearly stable on the cantilever scene's beam at rest: the step dt = cfl h / c_dev
    (simulation.py, c_dev = sqrt(4 G / 3 rho)) against leapfrog's 2 / omega_max. `volumetric_gradient`: with the
    strain gradient's volumetric part too, which is stepped explicitly (solid.volumetric_gradient)."""
    v, built = _built("cantilever", overrides, "mirrored")
    k, clamp_map = _built_stiffness(v, built, "mirrored", weights="quadratic_fit", nodal_integration="gradient",
                                    deviatoric=True, volumetric_gradient=volumetric_gradient)
    omega = highest_frequency(k, built.solid.mass, built.solid.movable, clamp_map)
    return 2.0 / omega * _deviatoric_wave(v) / (solid_smoothing_ratio(v) * v["numerics.spacing"])


def _deviatoric_wave(values):
    """c_dev = sqrt(4 G / 3 rho), the wave speed the default scheme's step is set by (simulation.py)."""
    _, shear, _ = material_constants(values["solid.young_modulus"], values["solid.poisson_ratio"], 1.0)
    return deviatoric_wave_speed(shear, values["solid.density"])


def static_displacement(scene, overrides=(), volumetric_gradient=False, weights="quadratic_fit",
                        nodal_integration="gradient", clamp="mirrored"):
    """(u (n, 3), built, values): a solid-only scene's static answer assembled and solved, K u = f, f its
    `solid_load` and its own weight on the movable particles (a periodic slab's pairs across its period). The
    default: the default scheme (the quadratic fit, the strain-gradient term, the mirrored clamp)."""
    from scipy.sparse.linalg import spsolve
    v, built = _built(scene, overrides, clamp)
    solid = built.solid
    k, clamp_map = _built_stiffness(v, built, clamp, weights=weights, nodal_integration=nodal_integration,
                                    volumetric_gradient=volumetric_gradient)
    force = built.solid_load + solid.mass[:, None] * np.asarray(v["scene.gravity"])[None, :]
    force[~solid.movable] = 0.0
    u = clamp_map @ spsolve((clamp_map.T @ k @ clamp_map).tocsc(), clamp_map.T @ force.ravel())
    return u.reshape(len(solid.pos), 3), built, v


def clamped_plate_deflection(overrides=(), **kw):
    """The clamped_plate scene's deflection assembled (static_displacement) against its plane-strain FE reference,
    as the scene judges it: mid-span clamped at both ends, the free end's probe (x = L - dp / 2) with
    geometry.supports = clamped_free: a dict."""
    from ..scenes.cases import clamped_plate
    from ..answers.fe_reference import cantilever_strip_fe_deflection, clamped_plate_fe_deflection
    u, built, v = static_displacement("clamped_plate", overrides, **kw)
    deflection = float(u[built.probes[0].indices, 2].mean())
    span, thickness, dp = v["geometry.span"], v["geometry.thickness"], v["numerics.spacing"]
    e, nu, weight = v["solid.young_modulus"], v["solid.poisson_ratio"], v["solid.density"] * v["scene.gravity"][2]
    pressure = lambda x: clamped_plate.pressure_at(v, x)     # noqa: E731
    if v["geometry.supports"] == "clamped_free":
        element = dp / max(1, math.ceil(8.0 * dp / thickness - 1e-9))     # the probe on a node (scene's evaluate)
        reference = -cantilever_strip_fe_deflection(span, thickness, e, nu, pressure, element_size=element,
                                                    probe_x=span - 0.5 * dp,
                                                    body_force_across=weight)["tip_deflection_m"]
    else:
        reference = clamped_plate_fe_deflection(span, thickness, e, nu, pressure, weight)["midspan_deflection_m"]
    return {"deflection_m": deflection, "reference_m": reference, "error": deflection / reference - 1.0}


def gate_loaded_deflection(overrides=(), **kw):
    """The antoci_gate_loaded scene's free-end deflection along the water's push, assembled, against its
    plane-strain FE reference (scenes/cases/gate.py, static_tip_reference): a dict."""
    from ..scenes.cases import antoci_gate_loaded, gate
    u, built, v = static_displacement("antoci_gate_loaded", overrides, **kw)
    push = 1.0 if v["geometry.mirror"] else -1.0
    deflection = float(push * u[built.probes[0].indices, 0].mean())
    reference = gate.static_tip_reference(antoci_gate_loaded.layout_values(v), v["geometry.water_density"],
                                          abs(v["scene.gravity"][2]))["fe_tip_deflection_m"]
    return {"deflection_m": deflection, "reference_m": reference, "error": deflection / reference - 1.0}


def _movable_map(movable):
    """P (3n x 3m): the movable particles' displacements placed, the fixed ones' zero."""
    from scipy.sparse import diags
    return diags(np.repeat(movable.astype(float), 3), format="csr")[:, np.repeat(movable, 3)]


def implicit_step_iterations(step_ratios, overrides=(), tolerance=1e-4, seed=0):
    """{ratio: iterations}: Jacobi-preconditioned conjugate gradients to `tolerance` (relative residual, from
    zero) for one step of an implicit solid, (M + dt^2 / 4 K_dev) x = b (Newmark's average acceleration), at
    `ratio` times the default scheme's explicit step (cfl 0.25 on c_dev), on the cantilever scene's beam with the
    default scheme's deviatoric stiffness (the pressure has its own implicit solve): what a step as long as the
    fluid's would cost in stiffness applications, against `ratio` explicit steps of one each."""
    from scipy.sparse import diags
    from scipy.sparse.linalg import cg
    v, built = _built("cantilever", overrides, "mirrored")
    solid = built.solid
    k, clamp_map = _built_stiffness(v, built, "mirrored", weights="quadratic_fit", nodal_integration="gradient",
                                         deviatoric=True)
    kk = (clamp_map.T @ k @ clamp_map).tocsr()
    m = np.repeat(solid.mass[solid.movable], 3)
    dt0 = 0.25 * solid_smoothing_ratio(v) * v["numerics.spacing"] / _deviatoric_wave(v)
    x = np.random.default_rng(seed).normal(size=len(m))
    out = {}
    for ratio in step_ratios:
        a = (diags(m) + (ratio * dt0) ** 2 / 4.0 * kk).tocsr()
        count = [0]
        cg(a, a @ x, rtol=tolerance, M=diags(1.0 / a.diagonal()), callback=lambda _: count.__setitem__(0, count[0] + 1),
           maxiter=10000)
        out[ratio] = count[0]
    return out
