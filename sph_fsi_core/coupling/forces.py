"""The coupling's pair passes (Satake et al. sec. 2.3; coupling/solver.py runs them): the solid's surface and its
normals, the paper's push (eqs. (10)-(11)), and the 'pressure' model's equal and opposite pair forces. The model
and its choices are described in coupling/solver.py's docstring."""
import math

from numba import njit, prange

from ..fluid.okaji import shepard_sums
from ..numerics.kernels import cubic_spline_wf, kernel_normalisation, kernel_sigma, kernel_wf, support_squared
from ..numerics.neighbours import unsigned
from ..numerics.periodic import minimum_image


@njit(cache=True, fastmath=False, error_model="numpy", inline="always")
def _separation(pos_a, a, pos_b, b, period, half_period):
    """r_a - r_b by the minimum image, and its square."""
    dx = minimum_image(pos_a[a, 0] - pos_b[b, 0], period[0], half_period[0])
    dy = minimum_image(pos_a[a, 1] - pos_b[b, 1], period[1], half_period[1])
    dz = minimum_image(pos_a[a, 2] - pos_b[b, 2], period[2], half_period[2])
    return dx, dy, dz, dx * dx + dy * dy + dz * dz


@njit(cache=True, fastmath=False, error_model="numpy", parallel=True, nogil=True)
def surface_gradient(pos, volume, start, index, period, h, out):
    """g_a = -sum_b V_b grad_a W_ab over the solid's own particles (full list): zero in the bulk, outward at a
    surface (module docstring). grad_a W_ab = F_ab (r_a - r_b)."""
    inv_h = 1.0 / h
    sigma = kernel_normalisation(h)
    support2 = support_squared(h)
    half_period = 0.5 * period
    for a in prange(pos.shape[0]):
        gx = 0.0
        gy = 0.0
        gz = 0.0
        for k in range(unsigned(start[a]), unsigned(start[a + 1])):
            b = index[k]
            if b == a:
                continue
            dx, dy, dz, r2 = _separation(pos, a, pos, b, period, half_period)
            if r2 >= support2:
                continue
            _, f = cubic_spline_wf(math.sqrt(r2), inv_h, sigma)
            c = volume[b] * f
            gx -= c * dx
            gy -= c * dy
            gz -= c * dz
        out[a, 0] = gx
        out[a, 1] = gy
        out[a, 2] = gz


@njit(cache=True, fastmath=False, error_model="numpy", nogil=True)
def surface_normals(gradient, surface, normal):
    """n_a = g_a / |g_a| on surface particles, 0 elsewhere."""
    for a in range(gradient.shape[0]):
        norm = math.sqrt(gradient[a, 0] ** 2 + gradient[a, 1] ** 2 + gradient[a, 2] ** 2)
        for k in range(3):
            normal[a, k] = gradient[a, k] / norm if (surface[a] and norm > 0.0) else 0.0


@njit(cache=True, fastmath=False, error_model="numpy", parallel=True, nogil=True)
def seed_push(solid_pos, normal, surface, movable, sfstart, sfindex, fluid, inv_dt2, period, h, kernel, gamma, acc):
    """Eqs. (10)-(11): acc_a = gamma sum_b (m_b / rho_b) (adot_b . n_a) W_ab (-n_a), adot_b = correction_b / dt^2,
    over the fluid neighbours b of solid surface particle a (solid->fluid list). Zero on interior and clamp
    particles. `fluid`: fluid.stepper.FluidArrays (positions, masses, densities and the step's correction
    displacements); W the water's kernel (`kernel`: numerics/kernels.py's id)."""
    fluid_pos = fluid.pos
    fluid_mass = fluid.mass
    fluid_rho = fluid.rho
    correction = fluid.correction_displacement
    inv_h = 1.0 / h
    sigma = kernel_sigma(h, kernel)
    support2 = support_squared(h)
    half_period = 0.5 * period
    for a in prange(solid_pos.shape[0]):
        acc[a, 0] = 0.0
        acc[a, 1] = 0.0
        acc[a, 2] = 0.0
        if not surface[a] or not movable[a]:
            continue
        nx, ny, nz = normal[a, 0], normal[a, 1], normal[a, 2]
        s = 0.0
        for k in range(unsigned(sfstart[a]), unsigned(sfstart[a + 1])):
            b = sfindex[k]
            _, _, _, r2 = _separation(solid_pos, a, fluid_pos, b, period, half_period)
            if r2 >= support2:
                continue
            w, _ = kernel_wf(math.sqrt(r2), inv_h, sigma, kernel)
            proj = (correction[b, 0] * nx + correction[b, 1] * ny + correction[b, 2] * nz) * inv_dt2
            s += fluid_mass[b] / fluid_rho[b] * proj * w
        acc[a, 0] = -gamma * s * nx
        acc[a, 1] = -gamma * s * ny
        acc[a, 2] = -gamma * s * nz


@njit(cache=True, fastmath=False, error_model="numpy", parallel=True, nogil=True)
def shepard_pressure(solid_pos, sfstart, sfindex, fluid_pos, fluid_p, period, h, kernel, out):
    """P_s = sum_f P_f W_sf / sum_f W_sf over the fluid neighbours of solid particle s (0 without any): the
    pressure a solid particle carries as a wall (the fluid's own rule, kernel and sums, okaji.shepard_sums, on the
    step's summed P, the image on every axis)."""
    inv_h = 1.0 / h
    sigma = kernel_sigma(h, kernel)
    half_period = 0.5 * period
    for s in prange(solid_pos.shape[0]):
        num, den = shepard_sums(s, s, solid_pos, fluid_pos, fluid_p, sfstart, sfindex, period, half_period, inv_h,
                                sigma, kernel, True, True, True)
        out[s] = num / den if den > 0.0 else 0.0


@njit(cache=True, fastmath=False, error_model="numpy", parallel=True, nogil=True)
def pressure_pair_forces(pos, mass, p, start, index, other_pos, other_mass, other_p, period, h, kernel, rho0,
                         force):
    """'pressure' model: the force on each target t from its neighbours u in the other phase (a gather over one
    list), F_t = sum_u m_t m_u (P_t + P_u) / rho0^2 grad_u W_ut,  grad_u W_ut = F_tu (r_u - r_t).

    One pass for both sides of the same pairs: with the solid as targets (solid->fluid list; `mass` m'_s, the
    solid particle's mass as the water's wall) the push on the solid, F_s = sum_a m_a m'_s (P_a + P_s) / rho0^2
    grad_a W_as; with the water as targets (fluid->solid list) the reaction, bookkeeping only (the fluid already
    felt it in its correction, eq. (2) with the solid as a wall), which sums to minus the solid's side. The pair's
    coefficient reads the same either way (IEEE products and sums commute exactly) and r_u - r_t = -(r_t - r_u)
    exactly, so each side has the bits of a pass of its own. grad W of the water's kernel (`kernel`: its id)."""
    inv_h = 1.0 / h
    sigma = kernel_sigma(h, kernel)
    support2 = support_squared(h)
    inv_rho2 = 1.0 / (rho0 * rho0)
    half_period = 0.5 * period
    for t in prange(pos.shape[0]):
        fx = 0.0
        fy = 0.0
        fz = 0.0
        for k in range(unsigned(start[t]), unsigned(start[t + 1])):
            u = index[k]
            dx, dy, dz, r2 = _separation(other_pos, u, pos, t, period, half_period)
            if r2 >= support2:
                continue
            _, f = kernel_wf(math.sqrt(r2), inv_h, sigma, kernel)
            c = mass[t] * other_mass[u] * (p[t] + other_p[u]) * inv_rho2 * f
            fx += c * dx
            fy += c * dy
            fz += c * dz
        force[t, 0] = fx
        force[t, 1] = fy
        force[t, 2] = fz


def solid_wall_mass(mass, rho, water_density, lattice_scale):
    """The mass a solid particle counts with in the water's sums (module docstring, item 1): the water's rest density
    times the particle's volume m / rho, times the lattice's scale (scenes/tank.py)."""
    return water_density * (mass / rho) * lattice_scale
