"""The coupling's pair passes (Satake et al. sec. 2.3; coupling/solver.py runs them): the solid's surface and its
normals, the paper's push (eqs. (10)-(11)), and the 'pressure' model's equal and opposite pair forces. The model
and its choices are described in coupling/solver.py's docstring."""
import math

from numba import njit, prange

from ..numerics.kernels import cubic_spline_wf, kernel_normalisation, support_squared
from ..numerics.neighbours import unsigned
from ..numerics.periodic import minimum_image


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
            dx = minimum_image(pos[a, 0] - pos[b, 0], period[0], half_period[0])
            dy = minimum_image(pos[a, 1] - pos[b, 1], period[1], half_period[1])
            dz = minimum_image(pos[a, 2] - pos[b, 2], period[2], half_period[2])
            r2 = dx * dx + dy * dy + dz * dz
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
def seed_push(solid_pos, normal, surface, movable, sfstart, sfindex, fluid_pos, fluid_mass, fluid_rho, correction,
              inv_dt2, period, h, gamma, acc):
    """Eqs. (10)-(11): acc_a = gamma sum_b (m_b / rho_b) (adot_b . n_a) W_ab (-n_a), adot_b = correction_b / dt^2,
    over the fluid neighbours b of solid surface particle a (solid->fluid list). Zero on interior and clamp
    particles."""
    inv_h = 1.0 / h
    sigma = kernel_normalisation(h)
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
            dx = minimum_image(solid_pos[a, 0] - fluid_pos[b, 0], period[0], half_period[0])
            dy = minimum_image(solid_pos[a, 1] - fluid_pos[b, 1], period[1], half_period[1])
            dz = minimum_image(solid_pos[a, 2] - fluid_pos[b, 2], period[2], half_period[2])
            r2 = dx * dx + dy * dy + dz * dz
            if r2 >= support2:
                continue
            w, _ = cubic_spline_wf(math.sqrt(r2), inv_h, sigma)
            proj = (correction[b, 0] * nx + correction[b, 1] * ny + correction[b, 2] * nz) * inv_dt2
            s += fluid_mass[b] / fluid_rho[b] * proj * w
        acc[a, 0] = -gamma * s * nx
        acc[a, 1] = -gamma * s * ny
        acc[a, 2] = -gamma * s * nz


@njit(cache=True, fastmath=False, error_model="numpy", parallel=True, nogil=True)
def shepard_pressure(solid_pos, sfstart, sfindex, fluid_pos, fluid_p, period, h, out):
    """P_s = sum_f P_f W_sf / sum_f W_sf over the fluid neighbours of solid particle s (0 without any): the
    pressure a solid particle carries as a wall (okaji.wall_pressure's rule, on the step's summed P)."""
    inv_h = 1.0 / h
    sigma = kernel_normalisation(h)
    support2 = support_squared(h)
    half_period = 0.5 * period
    for s in prange(solid_pos.shape[0]):
        num = 0.0
        den = 0.0
        for k in range(unsigned(sfstart[s]), unsigned(sfstart[s + 1])):
            f = sfindex[k]
            dx = minimum_image(solid_pos[s, 0] - fluid_pos[f, 0], period[0], half_period[0])
            dy = minimum_image(solid_pos[s, 1] - fluid_pos[f, 1], period[1], half_period[1])
            dz = minimum_image(solid_pos[s, 2] - fluid_pos[f, 2], period[2], half_period[2])
            r2 = dx * dx + dy * dy + dz * dz
            if r2 >= support2:
                continue
            w, _ = cubic_spline_wf(math.sqrt(r2), inv_h, sigma)
            num += fluid_p[f] * w
            den += w
        out[s] = num / den if den > 0.0 else 0.0


@njit(cache=True, fastmath=False, error_model="numpy", parallel=True, nogil=True)
def pressure_force_on_solid(solid_pos, wall_mass, solid_p, sfstart, sfindex, fluid_pos, fluid_mass, fluid_p, period,
                            h, rho0, force):
    """'pressure' model, the solid's side: F_s = sum_a m_a m'_s (P_a + P_s) / rho0^2 grad_a W_as (a gather over the
    fluid neighbours a of s), grad_a W_as = F_as (r_a - r_s)."""
    inv_h = 1.0 / h
    sigma = kernel_normalisation(h)
    support2 = support_squared(h)
    half_period = 0.5 * period
    inv_rho2 = 1.0 / (rho0 * rho0)
    for s in prange(solid_pos.shape[0]):
        fx = 0.0
        fy = 0.0
        fz = 0.0
        for k in range(unsigned(sfstart[s]), unsigned(sfstart[s + 1])):
            a = sfindex[k]
            dx = minimum_image(fluid_pos[a, 0] - solid_pos[s, 0], period[0], half_period[0])
            dy = minimum_image(fluid_pos[a, 1] - solid_pos[s, 1], period[1], half_period[1])
            dz = minimum_image(fluid_pos[a, 2] - solid_pos[s, 2], period[2], half_period[2])
            r2 = dx * dx + dy * dy + dz * dz
            if r2 >= support2:
                continue
            _, f = cubic_spline_wf(math.sqrt(r2), inv_h, sigma)
            c = fluid_mass[a] * wall_mass[s] * (fluid_p[a] + solid_p[s]) * inv_rho2 * f
            fx += c * dx
            fy += c * dy
            fz += c * dz
        force[s, 0] = fx
        force[s, 1] = fy
        force[s, 2] = fz


@njit(cache=True, fastmath=False, error_model="numpy", parallel=True, nogil=True)
def pressure_force_on_fluid(fluid_pos, fluid_mass, fluid_p, fsstart, fsindex, solid_pos, wall_mass, solid_p, period,
                            h, rho0, force):
    """'pressure' model, the fluid's side of the same pairs: F_a = -sum_s m_a m'_s (P_a + P_s) / rho0^2
    grad_a W_as over the solid neighbours s of fluid particle a (fluid->solid list). Bookkeeping only: the fluid
    already felt it in its correction (eq. (2) with the solid as a wall). Sums to minus the solid's side."""
    inv_h = 1.0 / h
    sigma = kernel_normalisation(h)
    support2 = support_squared(h)
    half_period = 0.5 * period
    inv_rho2 = 1.0 / (rho0 * rho0)
    for a in prange(fluid_pos.shape[0]):
        fx = 0.0
        fy = 0.0
        fz = 0.0
        for k in range(unsigned(fsstart[a]), unsigned(fsstart[a + 1])):
            s = fsindex[k]
            dx = minimum_image(fluid_pos[a, 0] - solid_pos[s, 0], period[0], half_period[0])
            dy = minimum_image(fluid_pos[a, 1] - solid_pos[s, 1], period[1], half_period[1])
            dz = minimum_image(fluid_pos[a, 2] - solid_pos[s, 2], period[2], half_period[2])
            r2 = dx * dx + dy * dy + dz * dz
            if r2 >= support2:
                continue
            _, f = cubic_spline_wf(math.sqrt(r2), inv_h, sigma)
            c = fluid_mass[a] * wall_mass[s] * (fluid_p[a] + solid_p[s]) * inv_rho2 * f
            fx -= c * dx
            fy -= c * dy
            fz -= c * dz
        force[a, 0] = fx
        force[a, 1] = fy
        force[a, 2] = fz


def solid_wall_mass(mass, rho, water_density, lattice_scale):
    """The mass a solid particle counts with in the water's sums (module docstring, item 1): the water's rest density
    times the particle's volume m / rho, times the lattice's scale (scenes/tank.py)."""
    return water_density * (mass / rho) * lattice_scale
