"""Incompressible fluid by iterative density correction (Okaji 2002, as used by Satake et al. sec. 2.2): the passes.

Each function is one pass over the fluid particles (targets) and their neighbours: fluid neighbours from a half
list (each pair once, b > a, the particle's own pair not listed), evaluated once per pair and added to both
particles through per-chunk buffers `buf` (chunks, N, 3) (no write races under prange; a second loop sums the
chunks), and wall neighbours from a second, full list whose sources are the fixed wall particles. What calls
them in order: fluid/stepper.py (the correction loop) and fluid/solver.py (the step). Their `xz_periodic` argument
(numerics.periodic.xz_periodic_marker) says whether the pair loops take the minimum image along y only or along
every axis; along y only, a target whose `crossing` flag is off (numerics.neighbours.NeighbourList.crossing: its
pairs stay within half a period of each other as stored) skips it too, which gives the same bits. Each such pass
is a wrapper that hands neighbours.xz_periodic to its parallel loop (_summation_density ...) as an argument of
its own: Numba drops an `if xz_periodic is not None` branch that cannot be taken only where xz_periodic is an
argument, not a field read from a bundle, and the three inlined copies of a pass's rows compiled in 1.5x the time
of the two a run takes (the dam break, an empty cache: 17.2 s against 11.0 s for the density pass).

Choices where the paper is open (docs/method.md, "Fluid"):

- Free surface: summation density (1) is short of rho0 wherever the kernel is cut by the surface, so eq. (7)'s
  pressure is clamped at p >= 0 (no tension) and the density error that the loop drives down is the compression
  (rho - rho0)_+ / rho0 only. Uncompressed particles are left where they are.
- Walls: wall particles sit on the fluid's lattice (spacing dp, mass rho0 dp^3), in at least three layers so a
  fluid particle's kernel never reaches past them; they enter the density sum (1) with their mass at their fixed
  positions, so a fluid particle pressing against a wall is compressed and gets a pressure. In the pressure term
  of (2) a wall particle carries the Shepard average of its fluid neighbours' pressures,
  p_w = sum_f p_f W_wf / sum_f W_wf (Adami, Hu & Adams 2012 without their acceleration term: the iteration
  pressure is a compression, not a hydrostatic field), with density rho0. Mirroring the fluid particle's own
  pressure instead (p_w = p_a) was tried first: next to a vertical wall it halves the vertical pressure gradient
  (the wall half of the kernel sees a constant), the wall-side water sinks and stirs the tank. Both terms of a
  wall pair are >= 0, so a wall only ever pushes. Walls take no part in the viscous term (free slip; see
  `viscous_velocity`).
- Pressure output: one correction moves particles by -dt^2 grad(p)/rho, so the correction of a whole step is that
  of the sum of the iterations' pressures; that sum (`pressure` here) is the pressure that held the fluid
  incompressible over the step, the one to compare with rho g depth.
"""
import math

from numba import njit, prange

from ..numerics.kernels import kernel_sigma, kernel_wf
from ..numerics.neighbours import chunk_first_target, unsigned
from ..numerics.periodic import minimum_image_if
from ..numerics.pair_blocks import BLOCK, FAR_IN_H, STRIDE, kernel_block, pad_block, padded


@njit(cache=True, fastmath=False, error_model="numpy", inline="always")
def _pair_to_both(out, b, mb, ma, tx, ty, tz, sx, sy, sz):
    """A half-list pair's term t_ab given to both particles: returns a's running sums plus m_b t and subtracts
    m_a t from b's chunk buffer row (t_ba = -t_ab, so the pair conserves momentum)."""
    out[b, 0] -= ma * tx
    out[b, 1] -= ma * ty
    out[b, 2] -= ma * tz
    return sx + mb * tx, sy + mb * ty, sz + mb * tz


# block columns of the density pass (pair_blocks.py)
_R2, _W, _F = 0, 1, 2
DENSITY_BLOCK_COLUMNS = 3


@njit(cache=True, fastmath=False, error_model="numpy", inline="always")
def _density_row(s, xa, ya, za, src_pos, src_mass, index, k0, k1, period, half_period, h, inv_h, sigma, kernel,
                 block, f_cache, scatter_mass, out, on_x, on_y, on_z):
    """Eq. (1)'s sum over one neighbour row (index[k0:k1] into src_pos), in blocks: returns s + sum_b m_b W_ab
    (added in the row's order) and leaves F_ab in f_cache[k0:k1]; with scatter_mass > 0 (a half list of the fluid)
    also adds scatter_mass W_ab to out[b]. Pairs in the list's skin give W = F = 0 and change no sum. on_x, on_y,
    on_z: the axes to take the minimum image on (constants, periodic.minimum_image_if)."""
    for lo in range(k0, k1, BLOCK):
        m = min(BLOCK, k1 - lo)
        for j in range(m):
            b = index[unsigned(lo + j)]
            dx = minimum_image_if(xa - src_pos[b, 0], period[0], half_period[0], on_x)
            dy = minimum_image_if(ya - src_pos[b, 1], period[1], half_period[1], on_y)
            dz = minimum_image_if(za - src_pos[b, 2], period[2], half_period[2], on_z)
            block[_R2 * STRIDE + j] = dx * dx + dy * dy + dz * dz
        pad_block(block, m, _R2, (FAR_IN_H * h) ** 2, 0, 0, 0.0)
        kernel_block(block, _R2, _W, _F, padded(m), inv_h, sigma, kernel)
        for j in range(m):
            b = index[unsigned(lo + j)]
            w = block[_W * STRIDE + j]
            s += src_mass[b] * w
            if scatter_mass > 0.0:
                out[b] += scatter_mass * w
            f_cache[unsigned(lo + j)] = block[_F * STRIDE + j]
    return s


@njit(cache=True, fastmath=False, error_model="numpy", inline="always")
def _density_target(a, pos, mass, fstart, findex, wall_pos, wall_mass, wstart, windex, period, half_period, h, inv_h,
                    sigma, kernel, block, f_fluid, f_wall, out, on_x, on_y, on_z):
    """Target a's density sum: its own pair (W(0) = sigma), its fluid row (scattered to b as well) and its wall
    row."""
    xa, ya, za = pos[a, 0], pos[a, 1], pos[a, 2]
    ma = mass[a]
    s = ma * sigma
    s = _density_row(s, xa, ya, za, pos, mass, findex, fstart[a], fstart[a + 1], period, half_period, h, inv_h,
                     sigma, kernel, block, f_fluid, ma, out, on_x, on_y, on_z)
    return _density_row(s, xa, ya, za, wall_pos, wall_mass, windex, wstart[a], wstart[a + 1], period, half_period,
                        h, inv_h, sigma, kernel, block, f_wall, 0.0, out, on_x, on_y, on_z)


@njit(cache=True, fastmath=False, error_model="numpy", nogil=True)
def summation_density(fluid, walls, neighbours, prm, work):
    """Eq. (1): rho_a = sum_b m_b W_ab over fluid and wall neighbours at the current positions (own pair included,
    W(0) = 1 / (pi h^3)), into fluid.rho; then, per particle, eq. (7) with p0 = 0 and no tension,
    p_a = c^2 max(rho_a - rho0, 0) (work.p), and p_a / rho_a^2 for eq. (2) (work.p_over_rho2).

    Also caches F_ab = (dW/dr)/r per pair (work.f_fluid, work.f_wall, aligned with the lists' `index`), for the
    pressure-gradient and viscous passes at the same positions. (Eq. (7) rides along because it needs only the
    particle's own density: one parallel region less per iteration.) The kernel is evaluated in blocks of pairs
    (pair_blocks.py; work.blocks: per-chunk scratch of DENSITY_BLOCK_COLUMNS columns); work.density_buf (chunks, N)
    holds the per-chunk sums (a column of the passes' (chunks, N, 3) buffer measured 1.08x slower: a third of each
    cache line used). `fluid`: fluid.stepper.FluidArrays, `walls`: FluidWalls, `neighbours`: FluidNeighbours,
    `prm`: CorrectionParams (h, rho0, c2, kernel), `work`: FluidBuffers. The arrays are taken out of the bundles
    here, once, and the per-target functions take them as arrays: taking the bundles (and tuples of arrays) they cost
    the tank and the dam break 0.91-0.92x per step.
    """
    _summation_density(fluid, walls, neighbours, prm, work, neighbours.xz_periodic)


@njit(cache=True, fastmath=False, error_model="numpy", parallel=True, nogil=True)
def _summation_density(fluid, walls, neighbours, prm, work, xz_periodic):
    """summation_density with neighbours.xz_periodic as an argument of its own (module docstring)."""
    pos = fluid.pos
    mass = fluid.mass
    rho = fluid.rho
    wall_pos = walls.pos
    wall_mass = walls.mass
    fstart = neighbours.fluid_start
    findex = neighbours.fluid_index
    wstart = neighbours.wall_start
    windex = neighbours.wall_index
    period = neighbours.period
    crossing = neighbours.crossing
    h = prm.h
    rho0 = prm.rho0
    c2 = prm.c2
    p = work.p
    p_over_rho2 = work.p_over_rho2
    f_fluid = work.f_fluid
    f_wall = work.f_wall
    density_buf = work.density_buf
    blocks = work.blocks
    n = pos.shape[0]
    chunks = density_buf.shape[0]
    kernel = prm.kernel
    inv_h = 1.0 / h
    sigma = kernel_sigma(h, kernel)
    half_period = 0.5 * period
    for c in prange(chunks):
        out = density_buf[c]
        block = blocks[c]
        for a in range(n):
            out[a] = 0.0
        for a in range(chunk_first_target(fstart, c, chunks), chunk_first_target(fstart, c + 1, chunks)):
            if xz_periodic is not None:
                s = _density_target(a, pos, mass, fstart, findex, wall_pos, wall_mass, wstart, windex, period,
                                    half_period, h, inv_h, sigma, kernel, block, f_fluid, f_wall, out, True, True,
                                    True)
            elif crossing[a]:
                s = _density_target(a, pos, mass, fstart, findex, wall_pos, wall_mass, wstart, windex, period,
                                    half_period, h, inv_h, sigma, kernel, block, f_fluid, f_wall, out, False, True,
                                    False)
            else:
                s = _density_target(a, pos, mass, fstart, findex, wall_pos, wall_mass, wstart, windex, period,
                                    half_period, h, inv_h, sigma, kernel, block, f_fluid, f_wall, out, False, False,
                                    False)
            out[a] += s
    for a in prange(n):
        s = 0.0
        for c in range(chunks):
            s += density_buf[c, a]
        rho[a] = s
        pa = c2 * max(s - rho0, 0.0)
        p[a] = pa
        p_over_rho2[a] = pa / (s * s)


@njit(cache=True, fastmath=False, error_model="numpy", nogil=True)
def compression_error(rho, rho0):
    """(max, mean) over fluid particles of the compression (rho_a - rho0)_+ / rho0, the loop's density error.

    One-sided: a density below rho0 is the free surface's truncated kernel, not a compression (module docstring).
    """
    n = rho.shape[0]
    largest = 0.0
    total = 0.0
    for a in range(n):
        e = (rho[a] - rho0) / rho0
        if e > 0.0:
            total += e
            if e > largest:
                largest = e
    return largest, (total / n if n > 0 else 0.0)


@njit(cache=True, fastmath=False, error_model="numpy", inline="always")
def shepard_sums(w, i, wall_pos, pos, p, wfstart, wfindex, period, half_period, inv_h, sigma, kernel, on_x, on_y,
                 on_z):
    """(sum_f p_f W_wf, sum_f W_wf) over row i of the wall->fluid list, that of wall particle w: the two sums of
    the wall's Shepard pressure (module docstring; also the coupling's solid particles, coupling/forces.py). A pair
    in the list's skin adds W = 0 to both."""
    num = 0.0
    den = 0.0
    for k in range(wfstart[i], wfstart[i + 1]):
        f = wfindex[k]
        dx = minimum_image_if(wall_pos[w, 0] - pos[f, 0], period[0], half_period[0], on_x)
        dy = minimum_image_if(wall_pos[w, 1] - pos[f, 1], period[1], half_period[1], on_y)
        dz = minimum_image_if(wall_pos[w, 2] - pos[f, 2], period[2], half_period[2], on_z)
        kern, _ = kernel_wf(math.sqrt(dx * dx + dy * dy + dz * dz), inv_h, sigma, kernel)
        num += p[f] * kern
        den += kern
    return num, den


@njit(cache=True, fastmath=False, error_model="numpy", nogil=True)
def wall_pressure(walls, pos, p, neighbours, h, rho0, kernel):
    """Wall pressure for eq. (2): p_w = sum_f p_f W_wf / sum_f W_wf over fluid neighbours f of wall particle w
    (0 without any), stored as p_w / rho0^2 in walls.p_over_rho2, for the wall particles within reach of the water
    (neighbours.active_walls; row i of the wall->fluid list belongs to wall particle active_walls[i]). The others
    have no fluid neighbour and keep p_w = 0, at no cost. `walls`: fluid.stepper.FluidWalls; `pos`, `p`: the
    fluid's positions and pressures; `neighbours`: FluidNeighbours; `kernel`: numerics/kernels.py's id."""
    _wall_pressure(walls, pos, p, neighbours, h, rho0, kernel, neighbours.xz_periodic)


@njit(cache=True, fastmath=False, error_model="numpy", parallel=True, nogil=True)
def _wall_pressure(walls, pos, p, neighbours, h, rho0, kernel, xz_periodic):
    """wall_pressure with neighbours.xz_periodic as an argument of its own (module docstring)."""
    wall_pos = walls.pos
    wall_p_over_rho2 = walls.p_over_rho2
    active = neighbours.active_walls
    wfstart = neighbours.wall_fluid_start
    wfindex = neighbours.wall_fluid_index
    period = neighbours.period
    crossing = neighbours.wall_crossing
    inv_h = 1.0 / h
    sigma = kernel_sigma(h, kernel)
    half_period = 0.5 * period
    for i in prange(active.shape[0]):
        w = active[i]
        if xz_periodic is not None:
            num, den = shepard_sums(w, i, wall_pos, pos, p, wfstart, wfindex, period, half_period, inv_h, sigma,
                                    kernel, True, True, True)
        elif crossing[i]:
            num, den = shepard_sums(w, i, wall_pos, pos, p, wfstart, wfindex, period, half_period, inv_h, sigma,
                                    kernel, False, True, False)
        else:
            num, den = shepard_sums(w, i, wall_pos, pos, p, wfstart, wfindex, period, half_period, inv_h, sigma,
                                    kernel, False, False, False)
        wall_p_over_rho2[w] = num / den / (rho0 * rho0) if den > 0.0 else 0.0


@njit(cache=True, fastmath=False, error_model="numpy", inline="always")
def _pressure_target(a, pos, mass, p_over_rho2, fstart, findex, f_fluid, wall_pos, wall_mass, wall_p_over_rho2,
                     wstart, windex, f_wall, period, half_period, out, on_x, on_y, on_z):
    """Target a's sum over its fluid row (each term also given to b in `out`) and its wall row, for eq. (2)."""
    xa, ya, za = pos[a, 0], pos[a, 1], pos[a, 2]
    qa = p_over_rho2[a]
    ma = mass[a]
    px, py, pz = period[0], period[1], period[2]
    hx, hy, hz = half_period[0], half_period[1], half_period[2]
    ax = ay = az = 0.0
    # every pair, also those with no pressure or in the skin (coef = 0 adds zeros): a test per pair measured 1.2x
    # slower, its branch taken at random
    for k in range(unsigned(fstart[a]), unsigned(fstart[a + 1])):
        b = findex[k]
        coef = (qa + p_over_rho2[b]) * f_fluid[k]
        dx = coef * minimum_image_if(xa - pos[b, 0], px, hx, on_x)
        dy = coef * minimum_image_if(ya - pos[b, 1], py, hy, on_y)
        dz = coef * minimum_image_if(za - pos[b, 2], pz, hz, on_z)
        ax, ay, az = _pair_to_both(out, b, mass[b], ma, dx, dy, dz, ax, ay, az)
    for k in range(unsigned(wstart[a]), unsigned(wstart[a + 1])):
        b = windex[k]
        coef = wall_mass[b] * (qa + wall_p_over_rho2[b]) * f_wall[k]
        if coef != 0.0:
            ax += coef * minimum_image_if(xa - wall_pos[b, 0], px, hx, on_x)
            ay += coef * minimum_image_if(ya - wall_pos[b, 1], py, hy, on_y)
            az += coef * minimum_image_if(za - wall_pos[b, 2], pz, hz, on_z)
    return ax, ay, az


@njit(cache=True, fastmath=False, error_model="numpy", nogil=True)
def pressure_displacement(fluid, walls, neighbours, prm, work):
    """Position correction of one iteration: disp_a = dt^2 dv_a/dt with dv_a/dt from eq. (2),

        dv_a/dt = - sum_b m_b (p_a / rho_a^2 + p_b / rho_b^2) grad_a W_ab,    grad_a W_ab = F_ab (r_a - r_b),

    wall neighbours with their extrapolated pressure (module docstring). F_ab from the density pass at the same
    positions; a fluid pair's term is evaluated once and given to both particles (grad_b W_ba = -grad_a W_ab), so
    fluid pairs change no momentum. Writes work.disp only (Jacobi: every particle sees its neighbours where they
    were), and adds this iteration's p_a (work.p) to the step's pressure sum fluid.pressure (the pressure output,
    module docstring); dt^2 is prm.dt2, work.buf the per-chunk sums. Arguments as in summation_density.
    """
    _pressure_displacement(fluid, walls, neighbours, prm, work, neighbours.xz_periodic)


@njit(cache=True, fastmath=False, error_model="numpy", parallel=True, nogil=True)
def _pressure_displacement(fluid, walls, neighbours, prm, work, xz_periodic):
    """pressure_displacement with neighbours.xz_periodic as an argument of its own (module docstring)."""
    pos = fluid.pos
    mass = fluid.mass
    accumulated = fluid.pressure
    wall_pos = walls.pos
    wall_mass = walls.mass
    wall_p_over_rho2 = walls.p_over_rho2
    fstart = neighbours.fluid_start
    findex = neighbours.fluid_index
    wstart = neighbours.wall_start
    windex = neighbours.wall_index
    period = neighbours.period
    crossing = neighbours.crossing
    dt2 = prm.dt2
    p = work.p
    p_over_rho2 = work.p_over_rho2
    f_fluid = work.f_fluid
    f_wall = work.f_wall
    disp = work.disp
    buf = work.buf
    n = pos.shape[0]
    chunks = buf.shape[0]
    half_period = 0.5 * period
    for c in prange(chunks):
        out = buf[c]
        for a in range(n):
            out[a, 0] = 0.0
            out[a, 1] = 0.0
            out[a, 2] = 0.0
        for a in range(chunk_first_target(fstart, c, chunks), chunk_first_target(fstart, c + 1, chunks)):
            if xz_periodic is not None:
                ax, ay, az = _pressure_target(a, pos, mass, p_over_rho2, fstart, findex, f_fluid, wall_pos, wall_mass,
                                              wall_p_over_rho2, wstart, windex, f_wall, period, half_period, out,
                                              True, True, True)
            elif crossing[a]:
                ax, ay, az = _pressure_target(a, pos, mass, p_over_rho2, fstart, findex, f_fluid, wall_pos, wall_mass,
                                              wall_p_over_rho2, wstart, windex, f_wall, period, half_period, out,
                                              False, True, False)
            else:
                ax, ay, az = _pressure_target(a, pos, mass, p_over_rho2, fstart, findex, f_fluid, wall_pos, wall_mass,
                                              wall_p_over_rho2, wstart, windex, f_wall, period, half_period, out,
                                              False, False, False)
            out[a, 0] += ax
            out[a, 1] += ay
            out[a, 2] += az
    for a in prange(n):
        sx = 0.0
        sy = 0.0
        sz = 0.0
        for c in range(chunks):
            sx += buf[c, a, 0]
            sy += buf[c, a, 1]
            sz += buf[c, a, 2]
        disp[a, 0] = -dt2 * sx
        disp[a, 1] = -dt2 * sy
        disp[a, 2] = -dt2 * sz
        accumulated[a] += p[a]


@njit(cache=True, fastmath=False, error_model="numpy", parallel=True, nogil=True)
def apply_displacement(pos, disp, total, pos_at_build, moved2):
    """pos += disp; total += disp (the step's correction displacement r(t+dt) - r*); moved2 = squared distance
    from where the neighbour lists were built (the skin test, in the same pass)."""
    for a in prange(pos.shape[0]):
        d2 = 0.0
        for k in range(3):
            pos[a, k] += disp[a, k]
            total[a, k] += disp[a, k]
            e = pos[a, k] - pos_at_build[a, k]
            d2 += e * e
        moved2[a] = d2


@njit(cache=True, fastmath=False, error_model="numpy", parallel=True, nogil=True)
def velocity_from_displacement(pos, pos_old, dt, vel):
    """Eq. (8): v*_a = (r_a(t+dt) - r_a(t)) / dt."""
    inv_dt = 1.0 / dt
    for a in prange(pos.shape[0]):
        for k in range(3):
            vel[a, k] = (pos[a, k] - pos_old[a, k]) * inv_dt


# block columns of the viscous pass (pair_blocks.py): r^2, rho_b, F_ab, then v_a - v_b (overwritten by the term)
_VR2, _VRHO, _VF, _VX = 0, 1, 2, 3
VISCOUS_BLOCK_COLUMNS = 6
FLUID_BLOCK_COLUMNS = max(DENSITY_BLOCK_COLUMNS, VISCOUS_BLOCK_COLUMNS)   # the fluid's per-chunk scratch


@njit(cache=True, fastmath=False, error_model="numpy", nogil=True)
def _viscous_block(block, m, mua, rhoa, nu, eta2):
    """Eq. (9)'s pair terms of a block's m pairs: coef_ab (v_a - v_b) in place of v_a - v_b (columns _VX..),
    coef_ab = (mu_a + mu_b) / (rho_a rho_b) F_ab r^2 / (r^2 + eta^2). A function of its own, as kernel_block: LLVM
    turns the loop into vector code there, not inlined into the row's gather and scatter."""
    for j in range(m):
        r2 = block[_VR2 * STRIDE + j]
        rhob = block[_VRHO * STRIDE + j]
        coef = (mua + rhob * nu) / (rhoa * rhob) * block[_VF * STRIDE + j] * r2 / (r2 + eta2)
        block[_VX * STRIDE + j] = coef * block[_VX * STRIDE + j]
        block[(_VX + 1) * STRIDE + j] = coef * block[(_VX + 1) * STRIDE + j]
        block[(_VX + 2) * STRIDE + j] = coef * block[(_VX + 2) * STRIDE + j]


@njit(cache=True, fastmath=False, error_model="numpy", inline="always")
def _viscous_target(a, pos, vel, mass, rho, fstart, findex, f_fluid, period, half_period, nu, eta2, block, out, on_x,
                    on_y, on_z):
    """Target a's sum of eq. (9) over its fluid row, each term also given to b in `out`, in blocks of pairs
    (pair_blocks.py: the two divisions per pair run in SIMD lanes; each term is the scalar loop's expression, so
    the same bits)."""
    xa, ya, za = pos[a, 0], pos[a, 1], pos[a, 2]
    vxa, vya, vza = vel[a, 0], vel[a, 1], vel[a, 2]
    rhoa = rho[a]
    mua = rhoa * nu
    ma = mass[a]
    px, py, pz = period[0], period[1], period[2]
    hx, hy, hz = half_period[0], half_period[1], half_period[2]
    sx = sy = sz = 0.0
    k0, k1 = fstart[a], fstart[a + 1]
    for lo in range(k0, k1, BLOCK):   # pairs in the skin add zeros
        m = min(BLOCK, k1 - lo)
        for j in range(m):
            k = unsigned(lo + j)
            b = findex[k]
            dx = minimum_image_if(xa - pos[b, 0], px, hx, on_x)
            dy = minimum_image_if(ya - pos[b, 1], py, hy, on_y)
            dz = minimum_image_if(za - pos[b, 2], pz, hz, on_z)
            block[_VR2 * STRIDE + j] = dx * dx + dy * dy + dz * dz
            block[_VRHO * STRIDE + j] = rho[b]
            block[_VF * STRIDE + j] = f_fluid[k]
            block[_VX * STRIDE + j] = vxa - vel[b, 0]
            block[(_VX + 1) * STRIDE + j] = vya - vel[b, 1]
            block[(_VX + 2) * STRIDE + j] = vza - vel[b, 2]
        pad_block(block, m, _VRHO, 1.0, _VF, _VX + 3, 0.0)   # rho_b = 1 (divided by), F = 0, no velocity
        _viscous_block(block, padded(m), mua, rhoa, nu, eta2)
        for j in range(m):
            b = findex[unsigned(lo + j)]
            sx, sy, sz = _pair_to_both(out, b, mass[b], ma, block[_VX * STRIDE + j], block[(_VX + 1) * STRIDE + j],
                                       block[(_VX + 2) * STRIDE + j], sx, sy, sz)
    return sx, sy, sz


@njit(cache=True, fastmath=False, error_model="numpy", nogil=True)
def viscous_velocity(pos, vel, mass, rho, neighbours, work, h, nu, dt, vel_out):
    """Eq. (9) in the laminar form of Morris, Fox & Zhu 1997 (the paper's typesetting of (9) is damaged):

        v_a = v*_a + dt sum_b m_b (mu_a + mu_b) / (rho_a rho_b) (r_ab . grad_a W_ab) / (r_ab^2 + 0.01 h^2) v_ab,

    mu = rho nu, v_ab = v*_a - v*_b; r_ab . grad_a W_ab = F_ab r_ab^2 < 0, so the sum diffuses momentum and
    conserves it pair by pair (each pair evaluated once, given to both). Fluid neighbours only: the walls are
    free-slip, because the real boundary layer, sqrt(nu t) ~ 0.4 mm at t = 0.2 s, is thinner than any particle
    spacing used here and a no-slip wall would spread it over 2h. Writes `vel_out` (Jacobi). `neighbours`:
    fluid.stepper.FluidNeighbours (the half list); `work`: FluidBuffers (F_ab in f_fluid from the density pass,
    buf the per-chunk sums, blocks per-chunk pair-block scratch of VISCOUS_BLOCK_COLUMNS columns at least).
    """
    _viscous_velocity(pos, vel, mass, rho, neighbours, work, h, nu, dt, vel_out, neighbours.xz_periodic)


@njit(cache=True, fastmath=False, error_model="numpy", parallel=True, nogil=True)
def _viscous_velocity(pos, vel, mass, rho, neighbours, work, h, nu, dt, vel_out, xz_periodic):
    """viscous_velocity with neighbours.xz_periodic as an argument of its own (module docstring)."""
    fstart = neighbours.fluid_start
    findex = neighbours.fluid_index
    period = neighbours.period
    crossing = neighbours.crossing
    f_fluid = work.f_fluid
    buf = work.buf
    blocks = work.blocks
    n = pos.shape[0]
    chunks = buf.shape[0]
    eta2 = 0.01 * h * h
    half_period = 0.5 * period
    for c in prange(chunks):
        out = buf[c]
        block = blocks[c]
        for a in range(n):
            out[a, 0] = 0.0
            out[a, 1] = 0.0
            out[a, 2] = 0.0
        for a in range(chunk_first_target(fstart, c, chunks), chunk_first_target(fstart, c + 1, chunks)):
            if xz_periodic is not None:
                sx, sy, sz = _viscous_target(a, pos, vel, mass, rho, fstart, findex, f_fluid, period, half_period, nu,
                                             eta2, block, out, True, True, True)
            elif crossing[a]:
                sx, sy, sz = _viscous_target(a, pos, vel, mass, rho, fstart, findex, f_fluid, period, half_period, nu,
                                             eta2, block, out, False, True, False)
            else:
                sx, sy, sz = _viscous_target(a, pos, vel, mass, rho, fstart, findex, f_fluid, period, half_period, nu,
                                             eta2, block, out, False, False, False)
            out[a, 0] += sx
            out[a, 1] += sy
            out[a, 2] += sz
    for a in prange(n):
        for k in range(3):
            s = 0.0
            for c in range(chunks):
                s += buf[c, a, k]
            vel_out[a, k] = vel[a, k] + dt * s


@njit(cache=True, fastmath=False, error_model="numpy", parallel=True, nogil=True)
def gravity_and_predictor(pos, vel, dt, gx, gy, gz, pos_old):
    """Step 1-2 of the fluid step: v_a += g dt (body force), then eq. (6), r*_a = r_a + v_a dt; keeps r_a(t)."""
    for a in prange(pos.shape[0]):
        vel[a, 0] += gx * dt
        vel[a, 1] += gy * dt
        vel[a, 2] += gz * dt
        for k in range(3):
            pos_old[a, k] = pos[a, k]
            pos[a, k] += vel[a, k] * dt


@njit(cache=True, fastmath=False, error_model="numpy", nogil=True)
def wrap_periodic(pos, period, lo):
    """Put positions back into the periodic box [lo, lo + period) on periodic axes (after a step's velocity)."""
    for k in range(3):
        if period[k] > 0.0:
            for a in range(pos.shape[0]):
                pos[a, k] = lo[k] + (pos[a, k] - lo[k]) % period[k]
