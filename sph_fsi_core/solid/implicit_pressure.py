"""The solid's pressure taken implicitly (`solid.pressure: implicit`): a time step set by the shear waves.

Not in the paper. Eq. (5)'s stress is sigma = -p I + S with p = c0^2 (rho - rho0) and c0 = sqrt(K / rho0) the bulk
sound speed; stepped explicitly, the step is dt <= cfl h / c0. At nu = 0.49 K is 50 G, so c0 is six times the
speed of the fastest wave the deviatoric stress carries (sqrt(4 G / 3 rho0)), and nine in ten of the paper's gate's
solid steps only keep the pressure waves stable: bending, what the gate does, is a shear-wave motion.

Here the pressure advances by backward Euler within each step, so its waves are stable at any step and the step is
set by the deviatoric stress alone (dt <= cfl h / (sqrt(4 G / 3 rho0) + |v|max)). With the quadratic fit's pair
weights G_ab at the step's positions (solid/fitted_gradient.py), the fitted divergence and the force paired with it
(their power balances: sum_a V_a p_a theta_a = sum_a f_a . v_a) are

    theta_a(v) = sum_b (v_b - v_a) . G_ab,     f(p) = D^T V p:  F_ab = -V_a p_a G_ab + V_b p_b G_ba  (+F on a, -F on b).

The half-kicked velocity v (deviatoric stress, viscosity, body and external forces only) takes the pressure impulse
of the new pressure, which follows from the new velocity:

    v' = v + dt M^-1 P^T f(p'),     p' = p - K dt theta(P v'),      K_a = c0^2 rho_a,

P the clamp's map (a mirrored clamp's ghosts move as -v of their image; P^T folds their forces back). Eliminating v':

    A p' = V p / K - dt V theta(P v),    A = V / K + dt^2 (V D P) M^-1 (V D P)^T,

symmetric positive definite, solved by conjugate gradients with the diagonal as preconditioner, from the previous
step's pressure plus its last change. For one pressure wave of frequency w the step damps it by
1 / sqrt(1 + w^2 dt^2) (a bending mode of the gate, w dt < 0.01, by less than 1e-4 per step): stable at any step,
first order in the volumetric part. The solution only gives the impulse: rho still advances by eq. (3) with the new
velocity's gradient (whose trace is theta), and p = c0^2 (rho - rho0) as before, so the density follows the motion
whatever the solve's tolerance.
"""
import math

from numba import njit, prange

from ..numerics.neighbours import chunk_first_target, unsigned

# rows of the (6, N) scalar scratch and the (2, N, 3) vector scratch of the solve (SolidWork.pressure_scalars /
# pressure_vectors)
_X, _R, _Z, _D, _Q, _DIAG = range(6)
_U_X, _U_D = range(2)
# the row of SolidWork.pressure_vectors that holds, after a step, the velocity change its pressure gave (dt P M^-1
# P^T D^T V p'): at rest it cancels the deviatoric and external half kicks (simulation.Simulation._relax)
IMPULSE_ROW = _U_X
# SolidWork.pressure_stats: steps solved, iterations summed, most iterations in one step, steps that hit the cap
STEPS, ITERATIONS, MOST, CAPPED = range(4)


@njit(cache=True, fastmath=False, error_model="numpy", inline="always")
def _unknown(a, movable, ghost_clamp):
    """Whether particle a's pressure is solved for: its density advances (solid.stepper._advance_state's rule)."""
    return movable[a] or not ghost_clamp


@njit(cache=True, fastmath=False, error_model="numpy", inline="always")
def _compliance(a, rho, c0_squared):
    """1 / K_a, K_a = c0^2 rho_a: the pressure's change per volumetric strain (eq. (3) with p = c0^2 (rho - rho0))."""
    return 1.0 / (c0_squared * rho[a])


def deviatoric_wave_speed(shear_modulus, density):
    """sqrt(4 G / 3 rho0): the fastest wave of the deviatoric stress alone (a longitudinal wave with K = 0)."""
    return math.sqrt(4.0 * shear_modulus / (3.0 * density))


@njit(cache=True, fastmath=False, error_model="numpy", parallel=True, nogil=True)
def pressure_forces(x, volume, start, index, weights, buf, force):
    """force = D^T V x: the pair forces F_ab = -V_a x_a G_ab + V_b x_b G_ba (+F on a, -F on b) of pressures x.

    `weights` (pairs, 6): G_ab then G_ba at the current positions (fitted_gradient.momentum_rate_mls); `buf`
    (chunks, N, 3) per-chunk sums of the half list (a wider buffer would move all its columns through the cache).
    """
    n = x.shape[0]
    chunks = buf.shape[0]
    for c in prange(chunks):
        out = buf[c]
        out[:, 0:3] = 0.0
        for a in range(chunk_first_target(start, c, chunks), chunk_first_target(start, c + 1, chunks)):
            pa = volume[a] * x[a]
            fx = fy = fz = 0.0
            for s in range(unsigned(start[a]), unsigned(start[a + 1])):
                b = index[s]
                pb = volume[b] * x[b]
                gx = pb * weights[s, 3] - pa * weights[s, 0]
                gy = pb * weights[s, 4] - pa * weights[s, 1]
                gz = pb * weights[s, 5] - pa * weights[s, 2]
                fx += gx
                fy += gy
                fz += gz
                out[b, 0] -= gx
                out[b, 1] -= gy
                out[b, 2] -= gz
            out[a, 0] += fx
            out[a, 1] += fy
            out[a, 2] += fz
    for a in prange(n):
        for k in range(3):
            total = 0.0
            for c in range(chunks):
                total += buf[c, a, k]
            force[a, k] = total


@njit(cache=True, fastmath=False, error_model="numpy", parallel=True, nogil=True)
def fitted_divergence(u, start, index, weights, buf, theta):
    """theta_a = sum_b (u_b - u_a) . G_ab over the half list (b sees G_ba and -(u_b - u_a)); `buf` (chunks, N)."""
    n = u.shape[0]
    chunks = buf.shape[0]
    for c in prange(chunks):
        out = buf[c]
        out[:] = 0.0
        for a in range(chunk_first_target(start, c, chunks), chunk_first_target(start, c + 1, chunks)):
            ta = 0.0
            for s in range(unsigned(start[a]), unsigned(start[a + 1])):
                b = index[s]
                dx = u[b, 0] - u[a, 0]
                dy = u[b, 1] - u[a, 1]
                dz = u[b, 2] - u[a, 2]
                ta += dx * weights[s, 0] + dy * weights[s, 1] + dz * weights[s, 2]
                out[b] -= dx * weights[s, 3] + dy * weights[s, 4] + dz * weights[s, 5]
            out[a] += ta
    for a in prange(n):
        total = 0.0
        for c in range(chunks):
            total += buf[c, a]
        theta[a] = total


@njit(cache=True, fastmath=False, error_model="numpy", parallel=True, nogil=True)
def _diagonal(mass, volume, rho, c0_squared, movable, ghost_clamp, start, index, weights, dt, buf, square_buf, diag):
    """diag_a = V_a / K_a + dt^2 V_a^2 (|sum_b G_ab|^2 / m_a + sum_b |G_ab|^2 / m_b): A's diagonal, the clamp's
    folding left out (the preconditioner needs no more); 1 for the particles that are not unknowns. `buf` (chunks,
    N, 3) and `square_buf` (chunks, N) per-chunk sums."""
    n = mass.shape[0]
    chunks = buf.shape[0]
    for c in prange(chunks):
        out = buf[c]
        out_sq = square_buf[c]
        out[:, :] = 0.0
        out_sq[:] = 0.0
        for a in range(chunk_first_target(start, c, chunks), chunk_first_target(start, c + 1, chunks)):
            for s in range(unsigned(start[a]), unsigned(start[a + 1])):
                b = index[s]
                out[a, 0] += weights[s, 0]
                out[a, 1] += weights[s, 1]
                out[a, 2] += weights[s, 2]
                out_sq[a] += (weights[s, 0] ** 2 + weights[s, 1] ** 2 + weights[s, 2] ** 2) / mass[b]
                out[b, 0] += weights[s, 3]
                out[b, 1] += weights[s, 4]
                out[b, 2] += weights[s, 5]
                out_sq[b] += (weights[s, 3] ** 2 + weights[s, 4] ** 2 + weights[s, 5] ** 2) / mass[a]
    for a in prange(n):
        if not _unknown(a, movable, ghost_clamp):
            diag[a] = 1.0
            continue
        sx = sy = sz = sq = 0.0
        for c in range(chunks):
            sx += buf[c, a, 0]
            sy += buf[c, a, 1]
            sz += buf[c, a, 2]
            sq += square_buf[c, a]
        diag[a] = (volume[a] * _compliance(a, rho, c0_squared)
                   + dt * dt * volume[a] * volume[a] * ((sx * sx + sy * sy + sz * sz) / mass[a] + sq))


@njit(cache=True, fastmath=False, error_model="numpy", nogil=True)
def _velocity_change(force, mass, movable, clamp_mirror, dt, u):
    """u = dt P M^-1 P^T force: a ghost's force folded onto its image (opposite sign), the body's velocity change,
    the ghosts' the odd image of it, the other clamp particles' zero."""
    for a in range(force.shape[0]):
        m = clamp_mirror[a] if clamp_mirror.shape[0] > 0 else -1
        if m >= 0:
            for k in range(3):
                force[m, k] -= force[a, k]
    for a in range(force.shape[0]):
        if movable[a]:
            for k in range(3):
                u[a, k] = dt * force[a, k] / mass[a]
        else:
            for k in range(3):
                u[a, k] = 0.0
    for a in range(force.shape[0]):
        m = clamp_mirror[a] if clamp_mirror.shape[0] > 0 else -1
        if m >= 0:
            for k in range(3):
                u[a, k] = -u[m, k]


@njit(cache=True, fastmath=False, error_model="numpy", nogil=True)
def _apply(x, state, neighbours, work, c0_squared, clamp_mirror, dt, u, theta, y):
    """y = A x and u = dt P M^-1 P^T D^T V x (the velocity change the pressures x give); arguments as in
    implicit_pressure_step."""
    rho = state.rho
    mass = state.mass
    movable = state.movable
    volume = work.volume
    start = neighbours.start
    index = neighbours.index
    weights = work.mls_weights
    force = work.pressure_force
    pressure_forces(x, volume, start, index, weights, work.vector_buf, force)
    _velocity_change(force, mass, movable, clamp_mirror, dt, u)
    fitted_divergence(u, start, index, weights, work.scalar_buf, theta)
    for a in range(x.shape[0]):
        y[a] = (volume[a] * (x[a] * _compliance(a, rho, c0_squared) + dt * theta[a])
                if _unknown(a, movable, clamp_mirror.shape[0] > 0) else 0.0)


@njit(cache=True, fastmath=False, error_model="numpy", nogil=True)
def _dot(a, b):
    total = 0.0
    for i in range(a.shape[0]):
        total += a[i] * b[i]
    return total


@njit(cache=True, fastmath=False, error_model="numpy", nogil=True)
def implicit_pressure_step(dt, state, neighbours, prm, work, clamp_mirror):
    """One step's pressure (module docstring): state.vel (the half-kicked velocity) takes the new pressure's impulse.
    rho and pressure are left to the continuity equation, which the stepper then advances with the velocity gradient
    of the new velocity (tr L_a is theta_a, with the same weights): solved exactly, the two agree; stopped at the
    tolerance, the density still follows the motion itself, so the solve's error cannot build up as a drift of the
    pressure (it did, as a 1 % creep of a gate at rest over 0.2 s, when rho was set from the solution). Unknowns: the
    particles whose density advances (movable ones, and with the fixed clamp its held particles; not a mirrored
    clamp's ghosts, which carry no stress).

    Conjugate gradients with the diagonal preconditioner, stopped when |r| <= prm.pressure_tolerance |b| (2-norms) or
    after prm.pressure_max_iterations; work.pressure_stats (4,) accumulates steps, iterations, the most in one step
    and the capped steps. work.volume (N,): m / rho at the step's start (solid.stepper.particle_volumes).
    work.pressure_scalars (6, N), work.pressure_vectors (2, N, 3), work.pressure_force (N, 3) scratch; scalars[_X]
    keeps the solution's change, the next step's warm start (the old pressure plus it). work.vector_buf (chunks, N,
    3) and work.scalar_buf (chunks, N): the pair passes' per-chunk sums; work.mls_weights the pair weights.
    `state`: solid.stepper.SolidArrays, `neighbours`: SolidNeighbours, `prm`: SolidParams, `work`: SolidBuffers;
    clamp_mirror: the ghost clamp's images (empty without).
    """
    vel = state.vel
    rho = state.rho
    pressure = state.pressure
    mass = state.mass
    movable = state.movable
    volume = work.volume
    weights = work.mls_weights
    scalars = work.pressure_scalars
    vectors = work.pressure_vectors
    start = neighbours.start
    index = neighbours.index
    stats = work.pressure_stats
    c0_squared = prm.c0 * prm.c0
    tolerance = prm.pressure_tolerance
    max_iterations = prm.pressure_max_iterations
    n = vel.shape[0]
    ghost_clamp = clamp_mirror.shape[0] > 0
    x, r, z, d, q, diag = scalars[_X], scalars[_R], scalars[_Z], scalars[_D], scalars[_Q], scalars[_DIAG]
    ux, ud = vectors[_U_X], vectors[_U_D]
    # b = V p / K - dt V theta(P v); v already holds the ghosts' images
    fitted_divergence(vel, start, index, weights, work.scalar_buf, q)
    for a in range(n):
        r[a] = (volume[a] * (pressure[a] * _compliance(a, rho, c0_squared) - dt * q[a])
                if _unknown(a, movable, ghost_clamp) else 0.0)
    b_norm = math.sqrt(_dot(r, r))
    # from the old pressure plus its last step's change (x holds it; checkpoints keep it with the rest of the work)
    for a in range(n):
        x[a] = pressure[a] + x[a] if _unknown(a, movable, ghost_clamp) else 0.0
    _diagonal(mass, volume, rho, c0_squared, movable, ghost_clamp, start, index, weights, dt, work.vector_buf,
              work.scalar_buf, diag)
    _apply(x, state, neighbours, work, c0_squared, clamp_mirror, dt, ux, q, z)
    for a in range(n):
        r[a] -= z[a]
        z[a] = r[a] / diag[a]
        d[a] = z[a]
    rz = _dot(r, z)
    iterations = 0
    while math.sqrt(_dot(r, r)) > tolerance * b_norm and iterations < max_iterations:
        # z is free until the preconditioner refills it: theta's scratch here
        _apply(d, state, neighbours, work, c0_squared, clamp_mirror, dt, ud, z, q)
        dq = _dot(d, q)
        if dq <= 0.0:
            break
        alpha = rz / dq
        for a in range(n):
            x[a] += alpha * d[a]
            r[a] -= alpha * q[a]
            for k in range(3):
                ux[a, k] += alpha * ud[a, k]
        for a in range(n):
            z[a] = r[a] / diag[a]
        rz_new = _dot(r, z)
        beta = rz_new / rz
        rz = rz_new
        for a in range(n):
            d[a] = z[a] + beta * d[a]
        iterations += 1
    for a in range(n):
        for k in range(3):
            vel[a, k] += ux[a, k]
        x[a] = x[a] - pressure[a] if _unknown(a, movable, ghost_clamp) else 0.0      # the next step's warm start
    stats[STEPS] += 1
    stats[ITERATIONS] += iterations
    stats[MOST] = max(stats[MOST], iterations)
    if iterations >= max_iterations:
        stats[CAPPED] += 1


@njit(cache=True, fastmath=False, error_model="numpy", parallel=True, nogil=True)
def deviatoric_over_rho2(stress, rho, sigma_over_rho2):
    """S / rho^2 in place of sigma / rho^2 for the momentum pass: the pressure's force is the implicit solve's."""
    for a in prange(stress.shape[0]):
        inv_r2 = 1.0 / (rho[a] * rho[a])
        for k in range(3):
            sigma_over_rho2[a, k] = stress[a, k] * inv_r2
