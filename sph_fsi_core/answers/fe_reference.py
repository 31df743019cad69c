"""Finite-element references (optional: scikit-fem + scipy): the 3D frequencies of a clamped-free cantilever, and
the static deflection of a plane-strain strip clamped at both ends (the hydrostatic-plate benchmark) or at one
(a gate held static under its water's hydrostatic pressure).

This is how reference_data/cantilever_frequencies.csv's `fe3d_*` columns are computed: a beam L x W x H
(x along the length, y the width, z the thickness = vertical), clamped on its whole x = 0 face, meshed with
triquadratic (27-node) hexahedra, small-strain isotropic elasticity, consistent mass, and the generalized
eigenproblem K u = omega^2 M u solved by shift-invert Lanczos. The core never needs this module: skfem and
scipy are imported inside the functions that use them (requirements-dev.txt pins them).
"""
import math
import time

_REQUIREMENT = ("sph_fsi_core.fe_reference needs scikit-fem and scipy (optional validation dependencies, "
                "pinned in requirements-dev.txt): pip install -r requirements-dev.txt")


def _import_fe():
    try:
        import scipy.sparse.linalg as spla
        import skfem
        from skfem.helpers import dot
        from skfem.models.elasticity import lame_parameters, linear_elasticity
    except ImportError as exc:
        raise ImportError(f"{_REQUIREMENT} ({exc})") from exc
    return spla, skfem, dot, lame_parameters, linear_elasticity


def euler_bernoulli_frequency(length, thickness, young_modulus, density):
    """First clamped-free bending frequency of an Euler-Bernoulli beam bending across `thickness` (Hz)."""
    return 1.8751040687 ** 2 / (2.0 * math.pi * length ** 2) * thickness * math.sqrt(
        young_modulus / (12.0 * density))


def _classify(u, doflocs, component_dofs):
    """Mode type from an eigenvector: 'vertical' (z bending), 'sideways' (y bending), 'axial', 'torsion'.

    The dominant displacement component (largest mean |u_i| over the nodes) gives the direction; a bending
    mode moves each cross-section coherently (one sign of the dominant component per x station), a torsion
    mode does not (u_y, u_z change sign across the section), which coherence = sum_x |sum u| / sum |u| tells.
    """
    import numpy as np
    comps = [u[idx] for idx in component_dofs]
    means = [float(np.mean(np.abs(c))) for c in comps]
    dominant = int(np.argmax(means))
    if dominant == 0:
        return "axial", means, 1.0
    c = comps[dominant]
    x = np.round(doflocs[0, component_dofs[dominant]], 12)
    _, station = np.unique(x, return_inverse=True)
    net = np.abs(np.bincount(station, weights=c))
    total = np.bincount(station, weights=np.abs(c))
    coherence = float(net.sum() / total.sum()) if total.sum() > 0 else 0.0
    if coherence < 0.5:
        return "torsion", means, coherence
    return ("sideways" if dominant == 1 else "vertical"), means, coherence


def _assemble_uniform(skfem, np, full, intorder, forms):
    """Global matrices of `forms` on a mesh of congruent, identically oriented elements (init_tensor).

    skfem.asm evaluates each form once per pair of the 81 local basis functions, in Python: ~30 s per matrix
    for the 1 mm mesh at L = 40 mm. Here the element matrices are assembled by skfem on element 0 only and
    scattered to every element, which is exact when each element is a translate of element 0 with the same
    local vertex order (checked; otherwise this falls back to skfem.asm on the whole mesh).
    """
    import scipy.sparse as sp
    mesh = full.mesh
    offsets = mesh.p[:, mesh.t] - mesh.p[:, mesh.t[:1]]           # (dim, vertices per element, elements)
    scale = float(np.max(np.abs(offsets[..., 0])))
    if not np.allclose(offsets, offsets[..., :1], rtol=0.0, atol=1e-9 * scale):
        return tuple(skfem.asm(form, full) for form in forms)
    first = skfem.Basis(mesh, full.elem, intorder=intorder, elements=np.array([0]))
    local = full.element_dofs[:, 0]
    dofs = full.element_dofs.astype(np.int64)                     # (local dofs, elements)
    n_local, n_elem = dofs.shape
    rows = np.broadcast_to(dofs[:, None, :], (n_local, n_local, n_elem)).ravel()
    cols = np.broadcast_to(dofs[None, :, :], (n_local, n_local, n_elem)).ravel()
    matrices = []
    for form in forms:
        ke = skfem.asm(form, first).tocsr()[local][:, local].toarray()
        values = np.broadcast_to(ke[:, :, None], (n_local, n_local, n_elem)).ravel()
        matrices.append(sp.coo_matrix((values, (rows, cols)), shape=(full.N, full.N)).tocsr())
    return tuple(matrices)


# 3 x 3 x 3 Gauss points: exact for box elements (Q2 stiffness and mass integrands are of degree <= 4 in each
# coordinate); skfem's default for Hex2 is 7 x 7 x 7, the same matrices at ~13x the cost.
HEX_INTORDER = 4


def _box_basis(skfem, np, extents, element_size):
    """Vector Q2 hexahedra on the box [0, a] x [0, b] x [0, c], round(extent / element_size) (>= 1) per direction:
    (basis, counts)."""
    counts = tuple(max(1, int(round(extent / element_size))) for extent in extents)
    mesh = skfem.MeshHex.init_tensor(*(np.linspace(0.0, extent, n + 1) for extent, n in zip(extents, counts)))
    return skfem.Basis(mesh, skfem.ElementVector(skfem.ElementHex2()), intorder=HEX_INTORDER), counts


def cantilever_fe_frequency(length, thickness, width, young_modulus, poisson_ratio, density,
                            element_size=1e-3, modes=6):
    """Lowest vertical (z) and sideways (y) bending frequencies (Hz) of a clamped-free 3D elastic beam.

    Mesh: [0, length] x [0, width] x [0, thickness] in hexahedra, round(extent / element_size) (>= 1) per
    direction, ElementVector(ElementHex2()); Dirichlet u = 0 on every DOF of the x = 0 face; `modes` lowest
    eigenpairs by scipy eigsh in shift-invert mode. Returns a dict: vertical_hz, sideways_hz (None when not
    among the `modes` computed), frequencies_hz and mode_types of all modes, dofs (free DOFs), total_dofs,
    elements (nx, ny, nz), assembly_time_s, solve_time_s (eigensolve incl. factorization), sigma.
    """
    import numpy as np
    spla, skfem, dot, lame_parameters, linear_elasticity = _import_fe()

    t0 = time.perf_counter()
    basis, counts = _box_basis(skfem, np, (length, width, thickness), element_size)
    intorder = HEX_INTORDER

    @skfem.BilinearForm
    def mass(u, v, _):
        return density * dot(u, v)

    elasticity = linear_elasticity(*lame_parameters(young_modulus, poisson_ratio))
    stiffness, mass_matrix = _assemble_uniform(skfem, np, basis, intorder, (elasticity, mass))
    clamped = basis.get_dofs(lambda p: p[0] <= 1e-9 * length).all()
    free = basis.complement_dofs(clamped)
    k_ff = stiffness[free][:, free].tocsc()
    m_ff = mass_matrix[free][:, free].tocsc()
    t1 = time.perf_counter()

    # Shift below the lowest mode (K is positive definite once clamped): the `modes` eigenvalues nearest
    # sigma are then the lowest ones, and K - sigma M stays well conditioned.
    omega_eb = 2.0 * math.pi * euler_bernoulli_frequency(length, min(thickness, width), young_modulus, density)
    sigma = -0.25 * omega_eb ** 2
    k = min(modes, k_ff.shape[0] - 1)
    eigenvalues, vectors = spla.eigsh(k_ff, k=k, M=m_ff, sigma=sigma, which="LM")
    t2 = time.perf_counter()

    order = np.argsort(eigenvalues)
    eigenvalues, vectors = eigenvalues[order], vectors[:, order]
    component_dofs = basis.split_indices()
    frequencies, types = [], []
    vertical = sideways = None
    for i in range(len(eigenvalues)):
        f = math.sqrt(max(float(eigenvalues[i]), 0.0)) / (2.0 * math.pi)
        u = np.zeros(basis.N)
        u[free] = vectors[:, i]
        kind, _, _ = _classify(u, basis.doflocs, component_dofs)
        frequencies.append(f)
        types.append(kind)
        if kind == "vertical" and vertical is None:
            vertical = f
        elif kind == "sideways" and sideways is None:
            sideways = f
    return {
        "vertical_hz": vertical,
        "sideways_hz": sideways,
        "frequencies_hz": frequencies,
        "mode_types": types,
        "dofs": int(len(free)),
        "total_dofs": int(basis.N),
        "elements": counts,
        "assembly_time_s": t1 - t0,
        "solve_time_s": t2 - t1,
        "sigma": sigma,
    }


# The on-demand 3D reference's meshes: H/2, H/4 and H/6 elements (for the paper's 4 mm beam the 2, 1 and 0.67 mm
# meshes of reference_data/cantilever_frequencies.csv), extrapolated to zero size (order ~1.4: the clamp's corners).
CANTILEVER_FE_DIVISIONS = (2, 4, 6)


def cantilever_fe_nondimensional(length_over_thickness, width_over_thickness, poisson_ratio,
                                 divisions=CANTILEVER_FE_DIVISIONS):
    """The clamped-free beam's first vertical bending frequency as f H / sqrt(E / rho), extrapolated to zero mesh.

    A linear elastic body's frequencies scale exactly as sqrt(E / rho) / H at fixed shape and nu, so one number per
    (L/H, W/H, nu) serves every size and material. Solved on the unit beam (H = 1, E = rho = 1) by
    cantilever_fe_frequency at element sizes 1 / n for n in `divisions`, then extrapolated_frequency. Returns a dict:
    frequency (the extrapolated f H / sqrt(E / rho)), order, mesh_frequencies (one per division), divisions,
    time_s.
    """
    t0 = time.perf_counter()
    sizes, freqs = [], []
    for n in divisions:
        result = cantilever_fe_frequency(length_over_thickness, 1.0, width_over_thickness, 1.0, poisson_ratio, 1.0,
                                         element_size=1.0 / n)
        if result["vertical_hz"] is None:
            raise ValueError(f"no vertical bending mode among the lowest modes of the {n}-per-thickness mesh")
        sizes.append(1.0 / n)
        freqs.append(result["vertical_hz"])
    f0, order = extrapolated_frequency(sizes, freqs)
    return {"frequency": f0, "order": order, "mesh_frequencies": freqs, "divisions": tuple(divisions),
            "time_s": time.perf_counter() - t0}


def extrapolated_frequency(sizes, freqs):
    """Richardson extrapolation to zero element size from three meshes, assuming f(s) = f0 + C s^p.

    Solves (f1 - f2) / (f2 - f3) = (s1^p - s2^p) / (s2^p - s3^p) for p by bisection (the right-hand side
    grows monotonically with p for s1 > s2 > s3 > 0), then C and f0. Returns (f0, p). Sizes need not be in a
    constant ratio; raises ValueError when the data are not monotone in s (no such p exists).
    """
    if len(sizes) != 3 or len(freqs) != 3:
        raise ValueError("need exactly three (size, frequency) pairs")
    (s1, f1), (s2, f2), (s3, f3) = sorted(zip(sizes, freqs), key=lambda sf: -sf[0])
    if not s1 > s2 > s3 > 0.0:
        raise ValueError("element sizes must be positive and distinct")
    d12, d23 = f1 - f2, f2 - f3
    if d12 == 0.0 or d23 == 0.0 or (d12 > 0) != (d23 > 0):
        raise ValueError("frequencies are not monotone in the element size: no f0 + C s^p fit")
    target = math.log(d12 / d23)

    def log_ratio(p):  # log((s1^p - s2^p) / (s2^p - s3^p)), written to stay finite for large p
        a, b = p * math.log(s2 / s1), p * math.log(s3 / s2)
        return p * math.log(s1 / s2) + math.log(-math.expm1(a)) - math.log(-math.expm1(b))

    lo, hi = 1e-6, 1.0
    while log_ratio(hi) < target:
        hi *= 2.0
        if hi > 1e3:
            raise ValueError("order of convergence above 1000: data not of the form f0 + C s^p")
    if log_ratio(lo) > target:
        raise ValueError("order of convergence below 1e-6: data not of the form f0 + C s^p")
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        if log_ratio(mid) < target:
            lo = mid
        else:
            hi = mid
        if hi - lo <= 1e-15 * hi:
            break
    p = 0.5 * (lo + hi)
    c = d12 / (s1 ** p - s2 ** p)
    return f1 - c * s1 ** p, p


def clamped_plate_beam_deflection(span, thickness, young_modulus, poisson_ratio, load, shear=True):
    """Mid-span deflection (m, positive along the load) of a plane-strain strip clamped at both ends under a
    uniform load `load` (Pa, force per area of plate): w = q L^4 / (384 D) with D = E t^3 / (12 (1 - nu^2))
    (Euler-Bernoulli), plus the shear deflection q L^2 / (8 kappa G t) with kappa = 5/6 when `shear`
    (Timoshenko). The beam values that ../shared/reference/hydrostatic_plate_fourey2017.csv quotes."""
    rigidity = young_modulus * thickness ** 3 / (12.0 * (1.0 - poisson_ratio ** 2))
    w = load * span ** 4 / (384.0 * rigidity)
    if shear:
        w += load * span ** 2 / (8.0 * (5.0 / 6.0) * young_modulus / (2.0 * (1.0 + poisson_ratio)) * thickness)
    return w


def cantilever_beam_deflection(length, rigidity, line_load, x):
    """Euler-Bernoulli deflection (m, along the load) at x from the clamp of a clamped-free beam of bending
    rigidity `rigidity` (N m^2; D per width for a strip) under a uniform line load `line_load` (N/m; per width for a
    strip: Pa): q x^2 (6 L^2 - 4 L x + x^2) / (24 EI)."""
    return line_load * x ** 2 * (6.0 * length ** 2 - 4.0 * length * x + x * x) / (24.0 * rigidity)


def strip_static(length, thickness, young_modulus, poisson_ratio, face_pressure, body_force, clamp_both,
                  element_size):
    """Static plane-strain displacement of a strip [0, length] x [0, thickness] (x along it, z across) clamped on
    its x = 0 face (and its x = length face when `clamp_both`), under a pressure `face_pressure(x)` (Pa) on its
    z = thickness face pushing towards -z and a body force `body_force` = (f_x, f_z) (N/m^3) throughout.

    Small-strain isotropic elasticity in plane strain (the 3D Lame constants on the x-z plane: a periodic slab
    across y), biquadratic (9-node) quadrilaterals, round(extent / element_size) per direction (default:
    thickness / 8), a sparse direct solve. Returns (u, basis, stiffness, rhs, clamped dofs, counts, seconds)."""
    import numpy as np
    spla, skfem, dot, lame_parameters, linear_elasticity = _import_fe()

    t0 = time.perf_counter()
    size = element_size or thickness / 8.0
    counts = tuple(max(1, int(round(extent / size))) for extent in (length, thickness))
    mesh = skfem.MeshQuad.init_tensor(np.linspace(0.0, length, counts[0] + 1),
                                      np.linspace(0.0, thickness, counts[1] + 1))
    element = skfem.ElementVector(skfem.ElementQuad2())
    basis = skfem.Basis(mesh, element, intorder=4)
    stiffness = skfem.asm(linear_elasticity(*lame_parameters(young_modulus, poisson_ratio)), basis)
    fx, fz = body_force

    @skfem.LinearForm
    def body(v, _):
        return fx * v[0] + fz * v[1]

    face = skfem.FacetBasis(mesh, element, intorder=6,
                            facets=mesh.facets_satisfying(lambda p: p[1] >= thickness * (1 - 1e-9)))

    @skfem.LinearForm
    def traction(v, w):
        return -face_pressure(w.x[0]) * v[1]     # the pressure pushes the face in: traction -p n_z, n_z = +1

    rhs = skfem.asm(body, basis) + skfem.asm(traction, face)
    if clamp_both:
        clamped = basis.get_dofs(lambda p: (p[0] <= 1e-9 * length) | (p[0] >= length * (1 - 1e-9))).all()
    else:
        clamped = basis.get_dofs(lambda p: p[0] <= 1e-9 * length).all()
    u = skfem.solve(*skfem.condense(stiffness, rhs, D=clamped))
    return u, basis, stiffness, rhs, clamped, counts, time.perf_counter() - t0


def _as_function(pressure):
    return pressure if callable(pressure) else (lambda x, value=float(pressure): value + 0.0 * x)


def displacement_at(u, basis, x, z):
    """(u_x, u_z) at the degree of freedom nearest (x, z)."""
    import numpy as np
    ux_dofs, uz_dofs = basis.split_indices()
    locs = basis.doflocs[:, uz_dofs]
    nearest = np.argmin((locs[0] - x) ** 2 + (locs[1] - z) ** 2)
    return float(u[ux_dofs[nearest]]), float(u[uz_dofs[nearest]])


def clamped_plate_fe_deflection(span, thickness, young_modulus, poisson_ratio, top_pressure, body_force_z=0.0,
                                element_size=None):
    """Static plane-strain deflection of a strip [0, span] x [0, thickness] (x along the span, z up) clamped on
    both end faces (u = 0 on x = 0 and x = span), under a pressure `top_pressure` (Pa, pushing down; a number or
    a function of x) on its top face and a body force `body_force_z` (N/m^3, e.g. -rho_s g) throughout.

    Small-strain isotropic elasticity in plane strain (the 3D Lame constants on the x-z plane: a periodic slab
    across y), biquadratic (9-node) quadrilaterals, round(extent / element_size) per direction (default:
    thickness / 8), 3 x 3 Gauss points, a sparse direct solve. Returns a dict: midspan_deflection_m (u_z at
    mid-span, mid-thickness; negative downwards), top_midspan_deflection_m, bottom_midspan_deflection_m, the
    vertical reaction at the clamps (N per m of width: equals the applied load), elements (nx, nz), dofs,
    solve_time_s.
    """
    u, basis, stiffness, rhs, clamped, counts, seconds = strip_static(
        span, thickness, young_modulus, poisson_ratio, _as_function(top_pressure), (0.0, body_force_z), True,
        element_size)
    uz_dofs = basis.split_indices()[1]
    import numpy as np
    reaction = stiffness @ u - rhs
    return {
        "midspan_deflection_m": displacement_at(u, basis, 0.5 * span, 0.5 * thickness)[1],
        "top_midspan_deflection_m": displacement_at(u, basis, 0.5 * span, thickness)[1],
        "bottom_midspan_deflection_m": displacement_at(u, basis, 0.5 * span, 0.0)[1],
        "clamp_reaction_z_n_per_m": float(reaction[np.intersect1d(clamped, uz_dofs)].sum()),
        "elements": counts,
        "dofs": int(basis.N),
        "solve_time_s": seconds,
    }


def cantilever_strip_fe_deflection(length, thickness, young_modulus, poisson_ratio, face_pressure,
                                   body_force_along=0.0, element_size=None, probe_x=None, body_force_across=0.0):
    """Static plane-strain deflection of a cantilever strip [0, length] x [0, thickness] clamped on its x = 0
    face and free at x = length, under a pressure `face_pressure` (Pa; a number or a function of the distance x
    from the clamp) on one face, pushing across the strip, and a body force `body_force_along` (N/m^3) along it
    (a hanging gate's own weight) and `body_force_across` (N/m^3) across it, + along the pressed face's outward
    normal (a horizontal strip pressed on its top: its own weight is -rho g). Same elements as
    clamped_plate_fe_deflection. Read at mid-thickness, at x = `probe_x` from the clamp (default: the free end),
    which must be a node (a multiple of element_size / 2).
    Returns a dict: tip_deflection_m (across the strip, along the pressure: positive, at probe_x), tip_axial_m
    (along the strip, + away from the clamp, at probe_x), free_end_deflection_m (at the free end, mid-thickness),
    probe_x_m, elements, dofs, solve_time_s."""
    import numpy as np
    u, basis, _, _, _, counts, seconds = strip_static(
        length, thickness, young_modulus, poisson_ratio, _as_function(face_pressure),
        (body_force_along, body_force_across), False, element_size)
    x = length if probe_x is None else probe_x
    locs = basis.doflocs[:, basis.split_indices()[1]]
    if np.min(np.hypot(locs[0] - x, locs[1] - 0.5 * thickness)) > 1e-9 * length:
        raise ValueError(f"probe_x = {x:g} m at mid-thickness is not a node of the mesh; allowed: a multiple of "
                         f"element_size / 2")
    ux, uz = displacement_at(u, basis, x, 0.5 * thickness)
    return {"tip_deflection_m": -uz, "tip_axial_m": ux,
            "free_end_deflection_m": -displacement_at(u, basis, length, 0.5 * thickness)[1], "probe_x_m": x,
            "elements": counts, "dofs": int(basis.N), "solve_time_s": seconds}


def cantilever_fe_static_deflection(length, thickness, width, young_modulus, poisson_ratio, body_force_z, points,
                                    element_size):
    """Static 3D deflection of the clamped-free beam of cantilever_fe_frequency (the same elements and clamp: u = 0
    on the x = 0 face) under a uniform body force `body_force_z` (N/m^3, a dead load like
    config/cantilever_loaded.yaml's distributed one). The load and the beam are symmetric about y = width / 2, so
    only the half y <= width / 2 is meshed, with u_y = 0 on the plane of symmetry (half the unknowns: a direct
    solve of the long beams fits in memory). Returns u_z (m) at each of `points` ((n, 3) in [0, L] x [0, W] x
    [0, H], which must be nodes of the mesh: multiples of element_size / 2; a point beyond the middle is read at
    its mirror image) and their mean, with the mesh's counts, dofs and solve time."""
    import numpy as np
    spla, skfem, dot, lame_parameters, linear_elasticity = _import_fe()
    t0 = time.perf_counter()
    half = 0.5 * width
    basis, counts = _box_basis(skfem, np, (length, half, thickness), element_size)
    (stiffness,) = _assemble_uniform(skfem, np, basis, HEX_INTORDER,
                                     (linear_elasticity(*lame_parameters(young_modulus, poisson_ratio)),))

    @skfem.LinearForm
    def body(v, _):
        return body_force_z * v[2]

    rhs = skfem.asm(body, basis)
    clamped = basis.get_dofs(lambda p: p[0] <= 1e-9 * length).all()
    ux_dofs, uy_dofs, uz_dofs = basis.split_indices()
    on_middle = np.flatnonzero(np.abs(basis.doflocs[1, uy_dofs] - half) <= 1e-9 * width)
    fixed = np.union1d(clamped, uy_dofs[on_middle])
    u = skfem.solve(*skfem.condense(stiffness, rhs, D=fixed))
    locs = basis.doflocs[:, uz_dofs]
    values = []
    for p in np.asarray(points, dtype=float):
        q = np.array([p[0], min(p[1], width - p[1]), p[2]])
        distance = np.sqrt(((locs - q[:, None]) ** 2).sum(axis=0))
        nearest = int(np.argmin(distance))
        if distance[nearest] > 1e-6 * length:
            raise ValueError(f"point {p} is not a node of the mesh; allowed: multiples of element_size / 2")
        values.append(float(u[uz_dofs[nearest]]))
    return {"uz_m": values, "mean_uz_m": float(np.mean(values)), "elements": counts, "dofs": int(basis.N),
            "solve_time_s": time.perf_counter() - t0}
