"""Particle shifting (fluid.shifting): after each fluid step the water is moved, its velocity kept, down the gradient
of its particles' concentration, so a flow that has stirred its particles into clumps and gaps is spread back towards
an even arrangement (docs/method.md, "Shifting"; docs/validation/OPEN.md 1.5):

    dr_a = -A h U dt grad C_a,     C_a = sum_b V_b W_ab,     grad C_a = sum_b V_b (1 + R (W_ab / W(dp))^n) grad_a W_ab

Fick's law for the concentration C with Lind, Xu, Stansby & Rogers 2012's (J. Comput. Phys. 231, eq. (9), (13))
anti-clumping factor, R = 0.2 and n = 4 as theirs; V_b = m_b / rho0 over water and wall neighbours (a solid in the
water counts with its volume: coupling.forces.solid_wall_mass). U is the water's largest speed (Xu, Stansby &
Laurence 2009, J. Comput. Phys. 228: the shift scaled by the flow, `fluid.shifting_speed: largest`) or each
particle's own (Lind et al. 2012: `own`). Scaled by its own speed a particle near a stagnation point is hardly
shifted, and that is where a jet's pressure noise is (OPEN.md 1.5); scaled by the flow's, water at rest is not
shifted at all and a slow wave little.

A free surface cuts the kernel, C falls to about 0.5 and its gradient would throw the water out: a particle is not
shifted within the surface's band, that is where C < 0.97, h |grad C| > 0.2, or a fluid neighbour within 2h has C
< 0.9 (Lind et al. shift only along the surface there; in a band this thin that is nearly no shift). The band's
numbers are the water-lattice study's (docs/validation/studies/water_lattice/particle_shifting.py), where they kept
a jet's free surfaces in place.

The passes take the fluid's lists as the step left them (fluid/solver.py): built at the step's positions less than
half the skin ago, so every pair within 2h is listed. Their loops follow fluid/okaji.py's (a half list's pair once,
given to both through per-chunk buffers; the minimum image only where `crossing` says so).
"""
import math

from numba import njit, prange

from ..numerics.kernels import kernel_sigma, kernel_w, kernel_wf, support_squared
from ..numerics.neighbours import chunk_first_target, unsigned
from ..numerics.periodic import minimum_image_if

ANTI_CLUMP_R, ANTI_CLUMP_N = 0.2, 4   # Lind et al. 2012, eq. (13)
SURFACE_CONCENTRATION = 0.9           # a particle with less is on the free surface
BAND_CONCENTRATION, BAND_GRADIENT = 0.97, 0.2


@njit(cache=True, fastmath=False, error_model="numpy", inline="always")
def _offset(xa, ya, za, src_pos, b, period, half_period, on_x, on_y, on_z):
    """r_a - r_b for source b of src_pos, through the minimum image on the axes on_x, on_y, on_z say (constants)."""
    return (minimum_image_if(xa - src_pos[b, 0], period[0], half_period[0], on_x),
            minimum_image_if(ya - src_pos[b, 1], period[1], half_period[1], on_y),
            minimum_image_if(za - src_pos[b, 2], period[2], half_period[2], on_z))


@njit(cache=True, fastmath=False, error_model="numpy", inline="always")
def _concentration_target(a, pos, mass, inv_rho0, fstart, findex, wall_pos, wall_mass, wstart, windex, period,
                          half_period, inv_h, sigma, inv_w_dp, kernel, conc_out, grad_out, on_x, on_y, on_z):
    """Target a's sums over its fluid row (each pair's terms also given to b) and its wall row: returns
    (sum_b V_b W_ab, sum_b V_b (1 + R (W_ab / W(dp))^n) grad_a W_ab) without its own W(0)."""
    xa, ya, za = pos[a, 0], pos[a, 1], pos[a, 2]
    va = mass[a] * inv_rho0
    c = gx = gy = gz = 0.0
    for k in range(unsigned(fstart[a]), unsigned(fstart[a + 1])):
        b = findex[k]
        dx, dy, dz = _offset(xa, ya, za, pos, b, period, half_period, on_x, on_y, on_z)
        w, f = kernel_wf(math.sqrt(dx * dx + dy * dy + dz * dz), inv_h, sigma, kernel)
        vb = mass[b] * inv_rho0
        g = f * (1.0 + ANTI_CLUMP_R * (w * inv_w_dp) ** ANTI_CLUMP_N)
        c += vb * w
        gx += vb * g * dx
        gy += vb * g * dy
        gz += vb * g * dz
        conc_out[b] += va * w
        grad_out[b, 0] -= va * g * dx
        grad_out[b, 1] -= va * g * dy
        grad_out[b, 2] -= va * g * dz
    for k in range(unsigned(wstart[a]), unsigned(wstart[a + 1])):
        b = windex[k]
        dx, dy, dz = _offset(xa, ya, za, wall_pos, b, period, half_period, on_x, on_y, on_z)
        w, f = kernel_wf(math.sqrt(dx * dx + dy * dy + dz * dz), inv_h, sigma, kernel)
        vg = wall_mass[b] * inv_rho0 * f * (1.0 + ANTI_CLUMP_R * (w * inv_w_dp) ** ANTI_CLUMP_N)
        c += wall_mass[b] * inv_rho0 * w
        gx += vg * dx
        gy += vg * dy
        gz += vg * dz
    return c, gx, gy, gz


@njit(cache=True, fastmath=False, error_model="numpy", nogil=True)
def concentration(pos, mass, wall_pos, wall_mass, neighbours, h, rho0, dp, kernel, conc_buf, grad_buf, conc, grad):
    """C_a and the anti-clumping grad C_a of the module docstring over the step's lists into `conc` (N,) and `grad`
    (N, 3); conc_buf (C, N) and grad_buf (C, N, 3) are the per-chunk sums (FluidSolver's density_buf and buf, free
    after the step). `neighbours`: fluid.stepper.FluidNeighbours; `kernel`: numerics/kernels.py's id."""
    _concentration(pos, mass, wall_pos, wall_mass, neighbours, h, rho0, dp, kernel, conc_buf, grad_buf, conc, grad,
                   neighbours.xz_periodic)


@njit(cache=True, fastmath=False, error_model="numpy", parallel=True, nogil=True)
def _concentration(pos, mass, wall_pos, wall_mass, neighbours, h, rho0, dp, kernel, conc_buf, grad_buf, conc, grad,
                   xz_periodic):
    """concentration with neighbours.xz_periodic as an argument of its own (fluid/okaji.py's docstring)."""
    fstart = neighbours.fluid_start
    findex = neighbours.fluid_index
    wstart = neighbours.wall_start
    windex = neighbours.wall_index
    period = neighbours.period
    crossing = neighbours.crossing
    n = pos.shape[0]
    chunks = conc_buf.shape[0]
    inv_h = 1.0 / h
    inv_rho0 = 1.0 / rho0
    sigma = kernel_sigma(h, kernel)
    inv_w_dp = 1.0 / kernel_w(dp, h, kernel)
    half_period = 0.5 * period
    for ch in prange(chunks):
        conc_out = conc_buf[ch]
        grad_out = grad_buf[ch]
        for a in range(n):
            conc_out[a] = 0.0
            grad_out[a, 0] = 0.0
            grad_out[a, 1] = 0.0
            grad_out[a, 2] = 0.0
        for a in range(chunk_first_target(fstart, ch, chunks), chunk_first_target(fstart, ch + 1, chunks)):
            if xz_periodic is not None:
                c, gx, gy, gz = _concentration_target(a, pos, mass, inv_rho0, fstart, findex, wall_pos, wall_mass,
                                                      wstart, windex, period, half_period, inv_h, sigma, inv_w_dp,
                                                      kernel, conc_out, grad_out, True, True, True)
            elif crossing[a]:
                c, gx, gy, gz = _concentration_target(a, pos, mass, inv_rho0, fstart, findex, wall_pos, wall_mass,
                                                      wstart, windex, period, half_period, inv_h, sigma, inv_w_dp,
                                                      kernel, conc_out, grad_out, False, True, False)
            else:
                c, gx, gy, gz = _concentration_target(a, pos, mass, inv_rho0, fstart, findex, wall_pos, wall_mass,
                                                      wstart, windex, period, half_period, inv_h, sigma, inv_w_dp,
                                                      kernel, conc_out, grad_out, False, False, False)
            conc_out[a] += c
            grad_out[a, 0] += gx
            grad_out[a, 1] += gy
            grad_out[a, 2] += gz
    for a in prange(n):
        c = mass[a] * inv_rho0 * sigma   # its own W(0)
        gx = gy = gz = 0.0
        for ch in range(chunks):
            c += conc_buf[ch, a]
            gx += grad_buf[ch, a, 0]
            gy += grad_buf[ch, a, 1]
            gz += grad_buf[ch, a, 2]
        conc[a] = c
        grad[a, 0] = gx
        grad[a, 1] = gy
        grad[a, 2] = gz


@njit(cache=True, fastmath=False, error_model="numpy", inline="always")
def _surface_neighbours_target(a, pos, conc, fstart, findex, period, half_period, reach2, out, on_x, on_y, on_z):
    """How many of target a's fluid neighbours within 2h are on the free surface (its half row; the pair's other
    side counted in out[b])."""
    count = 0.0
    surface_a = conc[a] < SURFACE_CONCENTRATION
    for k in range(unsigned(fstart[a]), unsigned(fstart[a + 1])):
        b = findex[k]
        dx, dy, dz = _offset(pos[a, 0], pos[a, 1], pos[a, 2], pos, b, period, half_period, on_x, on_y, on_z)
        if dx * dx + dy * dy + dz * dz < reach2:
            if conc[b] < SURFACE_CONCENTRATION:
                count += 1.0
            if surface_a:
                out[b] += 1.0
    return count


@njit(cache=True, fastmath=False, error_model="numpy", nogil=True)
def surface_neighbours(pos, conc, neighbours, h, count_buf, count):
    """count[a]: how many of a's fluid neighbours within 2h have C < SURFACE_CONCENTRATION (the band's last test,
    module docstring); count_buf (C, N) the per-chunk sums."""
    _surface_neighbours(pos, conc, neighbours, h, count_buf, count, neighbours.xz_periodic)


@njit(cache=True, fastmath=False, error_model="numpy", parallel=True, nogil=True)
def _surface_neighbours(pos, conc, neighbours, h, count_buf, count, xz_periodic):
    """surface_neighbours with neighbours.xz_periodic as an argument of its own."""
    fstart = neighbours.fluid_start
    findex = neighbours.fluid_index
    period = neighbours.period
    crossing = neighbours.crossing
    n = pos.shape[0]
    chunks = count_buf.shape[0]
    reach2 = support_squared(h)
    half_period = 0.5 * period
    for ch in prange(chunks):
        out = count_buf[ch]
        for a in range(n):
            out[a] = 0.0
        for a in range(chunk_first_target(fstart, ch, chunks), chunk_first_target(fstart, ch + 1, chunks)):
            if xz_periodic is not None:
                s = _surface_neighbours_target(a, pos, conc, fstart, findex, period, half_period, reach2, out,
                                               True, True, True)
            elif crossing[a]:
                s = _surface_neighbours_target(a, pos, conc, fstart, findex, period, half_period, reach2, out,
                                               False, True, False)
            else:
                s = _surface_neighbours_target(a, pos, conc, fstart, findex, period, half_period, reach2, out,
                                               False, False, False)
            out[a] += s
    for a in prange(n):
        s = 0.0
        for ch in range(chunks):
            s += count_buf[ch, a]
        count[a] = s


@njit(cache=True, fastmath=False, error_model="numpy", parallel=True, nogil=True)
def shift_positions(pos, vel, conc, grad, surface_count, coefficient, h, dt, own_speed, moved2):
    """The module docstring's dr_a = -A h U dt grad C_a, added to pos, except in the free surface's band (conc,
    grad: concentration's; surface_count: surface_neighbours'); U the largest |v| of the water or, with
    `own_speed`, the particle's own. Returns the largest |dr_a| (m); moved2 (N,) is its scratch, |dr_a|^2."""
    n = pos.shape[0]
    largest_speed2 = 0.0
    if not own_speed:
        for a in range(n):
            s2 = vel[a, 0] * vel[a, 0] + vel[a, 1] * vel[a, 1] + vel[a, 2] * vel[a, 2]
            if s2 > largest_speed2:
                largest_speed2 = s2
    scale = coefficient * h * dt
    largest_speed = math.sqrt(largest_speed2)
    for a in prange(n):
        moved2[a] = 0.0
        gx, gy, gz = grad[a, 0], grad[a, 1], grad[a, 2]
        g2 = gx * gx + gy * gy + gz * gz
        # SURFACE_CONCENTRATION < BAND_CONCENTRATION: a surface particle is in its own band
        if conc[a] < BAND_CONCENTRATION or surface_count[a] > 0.0 or h * h * g2 > BAND_GRADIENT * BAND_GRADIENT:
            continue
        u = largest_speed
        if own_speed:
            u = math.sqrt(vel[a, 0] * vel[a, 0] + vel[a, 1] * vel[a, 1] + vel[a, 2] * vel[a, 2])
        f = -scale * u
        pos[a, 0] += f * gx
        pos[a, 1] += f * gy
        pos[a, 2] += f * gz
        moved2[a] = f * f * g2
    return math.sqrt(moved2.max()) if n else 0.0
