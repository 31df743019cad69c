"""Strain-gradient nodal integration for the quadratic-fit solid (`solid.nodal_integration: gradient`).

Not in the paper. The particle scheme integrates the strain energy at the nodes: sum_a V_a sigma_a : eps_a / 2,
each particle's strain taken at its centre. In bending the strain varies linearly across every particle's cell,
and the centre value misses the cell's own second moment: on the paper's beam (4 layers at +-0.5 and +-1.5 dp)
sum z^2 = 5 dp^2 against H^3 / 12 = 5.33 dp^2, so EI comes out 6 % short and the frequency 3.2 %
(docs/method.md, "Strain-gradient nodal integration"). A Taylor expansion of the strain over the cell (a cube of
side dp: second moment m = dp^2 / 12 in each direction) adds

    sum_a V_a m sum_k (d_k S_a : d_k eps_a) / 2,

which makes the (deviatoric) energy exact for strain linear across each cell (the gradient terms of naturally
stabilized nodal integration, Hillman & Chen 2016, IJNME 107). Only the deviatoric stress S gets the term: in
bending it carries all but 1 % of the energy at nu = 0.49 (87 % at nu = 0.3), while the volumetric one, with
K = 50 G at nu = 0.49, penalised the fit's volumetric strain gradient so hard that the paper's beam came out 5 %
stiff with its first mode trading energy away within a period (docs/method.md, "Strain-gradient nodal integration").

The quadratic fit of solid/fitted_gradient.py already determines the velocity's second derivatives: with rows 3..8
of M_a^-1,
    d_j d_k v_a = sum_b (v_b - v_a) Gh_ab[jk],   Gh_ab = V_b W_ab (rows 3..8 of M_a^-1) p(u_ab) / h^2
(six entries xx, yy, zz, xy, xz, yz; the passes apply the rows once per particle instead of storing Gh per
pair). The stress gradient T_a[k] = d_k S_a (three traceless symmetric tensors) is state:
    dT[k]/dt = 2 G dev(e_k) + spin and convection terms (stress_gradient_rate),   e_k = d_k of the strain rate,
and its force is the one whose power is sum_a V_a m sum_k T_a[k] : d_k L_a (as F_ab of solid/fitted_gradient.py):
    F_ab,i = Phi_ab,i - Phi_ba,i,   Phi_ab,i = V_a m sum_jk T_a[k]_ij Gh_ab[jk],   +F on a, -F on b,
so momentum is conserved to round-off and the energy stored is the work done. Particles whose fit fell back to
linear (fewer than three layers) have zero Hessian rows and no correction.
"""
import numpy as np
from numba import njit, prange

from ..numerics.neighbours import chunk_first_target, unsigned
from ..numerics.periodic import pair_separation
from ..numerics.tensors import XX, XY, XZ, YY, YZ, ZZ

HESSIAN_ROWS = 6
_CHUNKS = 64


@njit(cache=True, fastmath=False, error_model="numpy", inline="always")
def quadratic_monomials(ux, uy, uz):
    """The quadratic part of the fit's basis p(u): (ux^2/2, uy^2/2, uz^2/2, ux uy, ux uz, uy uz)."""
    return 0.5 * ux * ux, 0.5 * uy * uy, 0.5 * uz * uz, ux * uy, ux * uz, uy * uz


@njit(cache=True, fastmath=False, error_model="numpy", inline="always")
def _sym(i, j):
    """Index of component (i, j) of a symmetric tensor stored as XX, YY, ZZ, XY, XZ, YZ (tensors.py); the Hessian
    entries d_j d_k are stored in the same order."""
    return i if i == j else i + j + 2


@njit(cache=True, fastmath=False, error_model="numpy", inline="always")
def basis_dot(v, ux, uy, uz):
    """v . p(u) for the quadratic basis p of solid/fitted_gradient.py. With v = A_a[i] (gradient_force_rows) and the
    pair's s_ab = V_b W_ab / h^2, s_ab basis_dot(A_a[i], u_ab) is Phi_ab,i of the module doc;
    fitted_gradient.momentum_rate_mls adds the pair's F_ab = Phi_ab - Phi_ba, where u and W_ab are at hand."""
    return ((v[0] * ux + v[1] * uy + v[2] * uz)
            + 0.5 * (v[3] * ux * ux + v[4] * uy * uy + v[5] * uz * uz)
            + (v[6] * ux * uy + v[7] * ux * uz + v[8] * uy * uz))


@njit(cache=True, fastmath=False, error_model="numpy", parallel=True, nogil=True)
def gradient_force_rows(mass, rho, stress_gradient, cell_moment, rows, force_rows):
    """force_rows[a, i] = A_a[i] = sum_jk V_a m T_a[k]_ij R_a^(3 + q(j, k)), nine numbers per i (N x 3 x 9), so
    that the pair term of the stress gradient's force is Phi_ab,i = s_ab A_a[i] . p(u) (basis_dot)."""
    for a in prange(mass.shape[0]):
        scale = mass[a] / rho[a] * cell_moment
        for i in range(3):
            for r in range(9):
                force_rows[a, i, r] = 0.0
            for j in range(3):
                for k in range(3):
                    t = scale * stress_gradient[a, k, _sym(i, j)]
                    q = 3 + _sym(j, k)
                    for r in range(9):
                        force_rows[a, i, r] += t * rows[a, q, r]


@njit(cache=True, fastmath=False, error_model="numpy", inline="always")
def _add_scaled(m, k, p0, p1, p2, p3, p4, p5, p6, p7, p8):
    """m + k p for nine moments held as a tuple (kept in registers, unlike an array the compiler must assume
    aliased with the chunk buffer)."""
    return (m[0] + k * p0, m[1] + k * p1, m[2] + k * p2, m[3] + k * p3, m[4] + k * p4, m[5] + k * p5,
            m[6] + k * p6, m[7] + k * p7, m[8] + k * p8)


@njit(cache=True, fastmath=False, error_model="numpy", inline="always")
def _scatter_moments(out, b, col, k, p0, p1, p2, p3, p4, p5, p6, p7, p8):
    """b's share of a pair: b sees -u (the linear entries change sign) and the velocity difference -dv."""
    out[b, col] += k * p0
    out[b, col + 1] += k * p1
    out[b, col + 2] += k * p2
    out[b, col + 3] -= k * p3
    out[b, col + 4] -= k * p4
    out[b, col + 5] -= k * p5
    out[b, col + 6] -= k * p6
    out[b, col + 7] -= k * p7
    out[b, col + 8] -= k * p8


@njit(cache=True, fastmath=False, error_model="numpy", parallel=True, nogil=True)
def velocity_hessian(state, neighbours, prm, work):
    """work.hessian (N, 3, 6): d_j d_k v_i of the quadratic fit, entry [i, q(j, k)]; work.w holds W_ab at state.pos.

    H_a[i, q] = R_a^(3+q) . sum_b (v_b - v_a)_i s_ab p(u_ab), s_ab = V_b W_ab / h^2: the pairs only sum the 27
    moments (per-chunk work.hessian_moments, chunks x N x 27), the rows (work.mls_rows) are applied once per
    particle. work.volume: V = m / rho per particle (solid.stepper.particle_volumes). neighbours.crossing: the rows
    that may need the minimum image (numerics.neighbours.NeighbourList.crossing; the others take plain differences,
    the same bits). `state`: solid.stepper.SolidArrays, `neighbours`: SolidNeighbours, `prm`: SolidParams, `work`:
    SolidBuffers.
    """
    pos = state.pos
    vel = state.vel
    volume = work.volume
    rows = work.mls_rows
    w = work.w
    hessian = work.hessian
    moments = work.hessian_moments
    start = neighbours.start
    index = neighbours.index
    crossing = neighbours.crossing
    period = neighbours.period
    h = prm.h
    half_period = 0.5 * period
    n = pos.shape[0]
    inv_h = 1.0 / h
    chunks = moments.shape[0]
    for c in prange(chunks):
        out = moments[c]
        out[:, :] = 0.0
        for a in range(chunk_first_target(start, c, chunks), chunk_first_target(start, c + 1, chunks)):
            va = volume[a]
            wrap = crossing[a]
            zero = (0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0)
            mx = my = mz = zero    # particle a's moments, one 9-tuple per velocity component
            for s in range(unsigned(start[a]), unsigned(start[a + 1])):
                if w[s] == 0.0:
                    continue
                b = index[s]
                rx, ry, rz = pair_separation(pos, a, b, period, half_period, wrap)
                ux = -rx * inv_h
                uy = -ry * inv_h
                uz = -rz * inv_h
                qxx, qyy, qzz, qxy, qxz, qyz = quadratic_monomials(ux, uy, uz)
                sab = volume[b] * w[s] * inv_h * inv_h
                sba = va * w[s] * inv_h * inv_h
                dvx = vel[b, 0] - vel[a, 0]
                dvy = vel[b, 1] - vel[a, 1]
                dvz = vel[b, 2] - vel[a, 2]
                mx = _add_scaled(mx, dvx * sab, ux, uy, uz, qxx, qyy, qzz, qxy, qxz, qyz)
                my = _add_scaled(my, dvy * sab, ux, uy, uz, qxx, qyy, qzz, qxy, qxz, qyz)
                mz = _add_scaled(mz, dvz * sab, ux, uy, uz, qxx, qyy, qzz, qxy, qxz, qyz)
                _scatter_moments(out, b, 0, dvx * sba, ux, uy, uz, qxx, qyy, qzz, qxy, qxz, qyz)
                _scatter_moments(out, b, 9, dvy * sba, ux, uy, uz, qxx, qyy, qzz, qxy, qxz, qyz)
                _scatter_moments(out, b, 18, dvz * sba, ux, uy, uz, qxx, qyy, qzz, qxy, qxz, qyz)
            for r in range(9):
                out[a, r] += mx[r]
                out[a, 9 + r] += my[r]
                out[a, 18 + r] += mz[r]
    for a in prange(n):
        for c in range(1, chunks):
            for r in range(27):
                moments[0, a, r] += moments[c, a, r]
        for i in range(3):
            for q in range(HESSIAN_ROWS):
                total = 0.0
                for r in range(9):
                    total += rows[a, 3 + q, r] * moments[0, a, 9 * i + r]
                hessian[a, i, q] = total


@njit(cache=True, fastmath=False, error_model="numpy", parallel=True, nogil=True)
def stress_gradient_rate(hessian, grad_v, stress, stress_gradient, shear_modulus, bulk_modulus, rate):
    """dT[k]/dt for T[k] = d_k S following the particle: the gradient of the Jaumann-Hooke rate of S, less the
    convection of a spatial gradient by the flow (d/dt d_k = d_k d/dt - L_lk d_l):

        dT[k]/dt = 2G dev(e_k) + K tr(e_k) I + (d_k W) S - S (d_k W) + W T[k] - T[k] W - L_lk T[l],

    e_k and d_k W the symmetric and antisymmetric parts of d_k L (the fit's Hessian, d_k L_im = d_m d_k v_i), W
    the spin. A rigidly rotating bent body keeps its stress gradient, turned with it. K tr(e_k) I is the
    volumetric part (solid.volumetric_gradient; bulk_modulus 0: the deviatoric part only, T traceless): the
    gradient of -p, whose spin terms vanish (an isotropic tensor commutes with W).
    """
    g2 = 2.0 * shear_modulus
    n = hessian.shape[0]
    chunks = min(n, _CHUNKS)    # each chunk keeps its 3 x 3 scratch tensors
    for c in prange(chunks):
        dl = np.empty((3, 3))      # d_k L for one k
        sd = np.empty((3, 3))      # S
        sp = np.empty((3, 3))      # W
        tk = np.empty((3, 3, 3))   # T[k]
        m = np.empty((3, 3))       # the rate of T[k], full
        for a in range(c * n // chunks, (c + 1) * n // chunks):
            for i in range(3):
                for j in range(3):
                    sd[i, j] = stress[a, _sym(i, j)]
                    sp[i, j] = 0.5 * (grad_v[a, i, j] - grad_v[a, j, i])
                    for k in range(3):
                        tk[k, i, j] = stress_gradient[a, k, _sym(i, j)]
            for k in range(3):
                for i in range(3):
                    for j in range(3):
                        dl[i, j] = hessian[a, i, _sym(j, k)]
                trace = dl[0, 0] + dl[1, 1] + dl[2, 2]
                for i in range(3):
                    for j in range(i, 3):
                        value = 0.5 * g2 * (dl[i, j] + dl[j, i])
                        for q in range(3):
                            dw_iq = 0.5 * (dl[i, q] - dl[q, i])
                            dw_jq = 0.5 * (dl[j, q] - dl[q, j])
                            value += (dw_iq * sd[q, j] + dw_jq * sd[i, q]
                                      + sp[i, q] * tk[k, q, j] + sp[j, q] * tk[k, i, q]
                                      - grad_v[a, q, k] * tk[q, i, j])
                        m[i, j] = value
                m[0, 0] += (bulk_modulus - g2 / 3.0) * trace
                m[1, 1] += (bulk_modulus - g2 / 3.0) * trace
                m[2, 2] += (bulk_modulus - g2 / 3.0) * trace
                rate[a, k, XX] = m[0, 0]
                rate[a, k, YY] = m[1, 1]
                rate[a, k, ZZ] = m[2, 2]
                rate[a, k, XY] = m[0, 1]
                rate[a, k, XZ] = m[0, 2]
                rate[a, k, YZ] = m[1, 2]


@njit(cache=True, fastmath=False, error_model="numpy", nogil=True)
def gradient_strain_energy(mass, rho, stress_gradient, cell_moment, shear_modulus, bulk_modulus=0.0):
    """sum_a V_a m sum_k (dev T[k] : dev T[k] / (4G) + tr(T[k])^2 / (18 K)), the energy of the stress gradient
    (T traceless without its volumetric part, bulk_modulus 0)."""
    total = 0.0
    for a in range(mass.shape[0]):
        for k in range(3):
            t = stress_gradient[a, k]
            trace = t[XX] + t[YY] + t[ZZ]
            tt = (t[XX] ** 2 + t[YY] ** 2 + t[ZZ] ** 2 - trace * trace / 3.0
                  + 2.0 * (t[XY] ** 2 + t[XZ] ** 2 + t[YZ] ** 2))
            e = tt / (4.0 * shear_modulus)
            if bulk_modulus > 0.0:
                e += trace * trace / (18.0 * bulk_modulus)
            total += mass[a] / rho[a] * cell_moment * e
    return total

