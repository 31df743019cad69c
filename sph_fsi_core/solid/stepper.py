"""Time integration of the elastic solid: kick-drift-kick leapfrog, compiled so many steps run per call.

One step of size dt, with a^n the acceleration at r^n (from the previous step):

    v^{n+1/2} = v^n + dt/2 a^n                                   (kick)
    vhat, L    from v^{n+1/2} on the pair cache at r^n          (eq. (4), velocity gradient)
    rho^{n+1} = rho^n + dt drho/dt,  S^{n+1} = S^n + dt dS/dt    (eq. (3), Jaumann Hooke)
    r^{n+1}   = r^n + dt vhat                                     (drift; Gray moves particles with vhat)
    a^{n+1} from eq. (5), refreshing the pair cache at r^{n+1} in the same pass
    v^{n+1}   = v^{n+1/2} + dt/2 a^{n+1}                          (kick)

Second order, three passes over the pairs per step (four with solid.nodal_integration = gradient, whose stress
gradient advances with S: solid/gradient_integration.py). With solid.pressure = implicit the kicks carry the
deviatoric stress only, and after the first one the velocity takes the pressure's impulse over the whole step
from the implicit solve (solid/implicit_pressure.py: backward Euler, a step set by the shear waves); rho still
advances by eq. (3). With solid.fit_refresh = rotate the quadratic fit's rows turn with each particle between
remakes (solid/fit_rotation.py). The artificial viscosity in a^{n+1} uses v^{n+1/2} (the
velocity at n+1 is not known yet).

Clamp particles (movable False) keep r fixed. With solid.clamp = fixed they keep v = 0 but update rho and S (clamp
material whose particles are held). With solid.clamp = mirrored (`clamp_mirror` not empty) those behind the body are
its ghosts: v_g = -v_m and displacement u_g = -u_m of their mirror image m across the clamp face, so velocity and
displacement vanish on the face; they carry no stress (the wall does no work), and the forces the body's stress puts
on a ghost move to its image with the opposite sign: the force whose power is the body's stress power with the
ghosts' velocities substituted, so the scheme stays conservative.

The loop returns early when the neighbour list may go stale within the next step, so the caller can rebuild it (a
rebuild is never needed mid-step).
"""
import math
from typing import NamedTuple

import numba
import numpy as np
from numba import njit

from ..numerics.kernels import cubic_spline_w
from ..numerics.neighbours import max_displacement
from ..numerics.pair_blocks import block_scratch
from .gray2001 import MOMENTUM_BLOCK_COLUMNS as GRAY_BLOCK_COLUMNS
from .gray2001 import (continuity_rate, jaumann_stress_rate, momentum_rate, stress_terms,
                             xsph_velocity_and_gradient)
from .gradient_integration import gradient_force_rows, stress_gradient_rate, velocity_hessian
from .implicit_pressure import deviatoric_over_rho2, implicit_pressure_step
from .fit_rotation import follow_spin, rotate_fit_rows
from .fitted_gradient import MOMENTUM_BLOCK_COLUMNS as MLS_BLOCK_COLUMNS
from .fitted_gradient import (N_BASIS, momentum_rate_mls, pair_variant, velocity_divergence_rate,
                              xsph_velocity_and_mls_gradient)

# solid.fit_refresh_turn = 0 with solid.nodal_integration = gradient: the fitted curvature needs fresh rows
# (docs/method.md, "Strain-gradient nodal integration": with rows kept from one list build to the next, 46 % of the
# paper's beam's energy ended up locked in self-balanced stress within 7 periods)
GRADIENT_FIT_REFRESH_TURN = 1e-4

# solid.velocity_gradient -> SolidParams.gradient_order
GRADIENT_ORDERS = {"sph": 0, "linear": 1, "quadratic": 2}


class SolidParams(NamedTuple):
    """Numbers the solid passes need, as one Numba-friendly tuple of floats."""
    h: float
    rho0: float
    c0: float
    shear_modulus: float
    xsph_eps: float
    alpha: float
    beta: float
    art_eps: float
    art_exponent: int      # 0 switches the artificial stress term off
    inv_w_dp: float        # 1 / W(dp, h)
    gx: float
    gy: float
    gz: float
    half_skin: float
    gradient_order: int    # 0: Gray's SPH gradient (the paper); 1: kernel-corrected L K^-1; 2: quadratic fit
    cell_moment: float     # m = dp^2 / 12 of the strain-gradient nodal integration (0: off)
    gradient_bulk_modulus: float   # K of the stress gradient's volumetric part (solid.volumetric_gradient; 0: off)
    fit_refresh_turn: float   # refit the quadratic fit once some particle's integral of |L| dt passes this (0: never)
    implicit_pressure: bool   # solid.pressure = implicit (solid/implicit_pressure.py); needs gradient_order 2
    rotate_fit: bool          # solid.fit_refresh = rotate (solid/fit_rotation.py)
    fit_refresh_strain: float   # with it: remake the rows once some neighbourhood's Green strain since passes this
    pressure_tolerance: float       # its conjugate gradients' relative residual
    pressure_max_iterations: int    # and their cap per step


def make_params(h, spacing, density, c0, shear_modulus, xsph_eps, alpha, beta, art_eps, art_exponent, gravity,
                skin, velocity_gradient="sph", nodal_integration="plain", fit_refresh_turn=0.0, pressure="explicit",
                pressure_tolerance=1e-4, pressure_max_iterations=200, fit_refresh="remake", fit_refresh_strain=1e-3,
                volumetric_gradient=False):
    return SolidParams(h=h, rho0=density, c0=c0, shear_modulus=shear_modulus, xsph_eps=xsph_eps, alpha=alpha,
                       beta=beta, art_eps=art_eps, art_exponent=int(art_exponent) if art_eps > 0.0 else 0,
                       inv_w_dp=1.0 / cubic_spline_w(spacing, h), gx=gravity[0], gy=gravity[1], gz=gravity[2],
                       half_skin=0.5 * skin, gradient_order=GRADIENT_ORDERS[velocity_gradient],
                       cell_moment=spacing ** 2 / 12.0 if nodal_integration == "gradient" else 0.0,
                       gradient_bulk_modulus=(c0 * c0 * density if volumetric_gradient
                                              and nodal_integration == "gradient" else 0.0),
                       fit_refresh_turn=0.0 if velocity_gradient != "quadratic" else
                       fit_refresh_turn or (GRADIENT_FIT_REFRESH_TURN if nodal_integration == "gradient" else 0.0),
                       implicit_pressure=pressure == "implicit", rotate_fit=fit_refresh == "rotate",
                       fit_refresh_strain=fit_refresh_strain,
                       pressure_tolerance=pressure_tolerance,
                       pressure_max_iterations=int(pressure_max_iterations))


def driver_variant(prm):
    """The drivers' last argument: the quadratic fit's momentum pass setting as a type (fitted_gradient.pair_variant
    of prm's gradient integration and artificial stress), () for Gray's scheme, whose passes take none. An argument
    of its own, not a field of SolidParams: every pass that takes prm compiled once per setting with it (the
    velocity Hessian's 16-41 s, Gray's passes too), where only the momentum pass's block kernel differs."""
    if prm.gradient_order != 2:
        return ()
    return pair_variant(prm.cell_moment > 0.0, prm.art_exponent)


# The passes take these bundles and read their arrays one per line (`pos = state.pos`), never as a tuple
# (`pos, vel = state.pos, state.vel`): Numba's alias analysis does not follow a tuple built and unpacked, so a
# parallel loop writing an array unpacked that way counts as dead and is dropped (continuity_rate lost its drho so).


class SolidArrays(NamedTuple):
    """The solid's particle state as the compiled drivers take it (state.SolidState's arrays, N particles).

    The drivers advance pos, vel, rho, stress, stress_gradient and acc in place; pressure is written by the
    acceleration pass; mass and movable are read only.
    """
    pos: np.ndarray               # (N, 3) m
    vel: np.ndarray               # (N, 3) m/s
    rho: np.ndarray               # (N,) kg/m^3
    stress: np.ndarray            # (N, 6) Pa, deviatoric S in XX, YY, ZZ, XY, XZ, YZ order
    mass: np.ndarray              # (N,) kg
    movable: np.ndarray           # (N,) bool; False: clamp particle
    pressure: np.ndarray          # (N,) Pa, p = c0^2 (rho - rho0) of eq. (5)'s sigma = -p I + S
    acc: np.ndarray               # (N, 3) m/s^2, eq. (5) at the current positions
    stress_gradient: np.ndarray   # (N, 3, 6) Pa/m, d_k S of solid.nodal_integration = gradient; else (0, 3, 6)

    @classmethod
    def of(cls, solid):
        """The arrays of a state.SolidState (the same arrays, not copies)."""
        return cls(solid.pos, solid.vel, solid.rho, solid.stress, solid.mass, solid.movable, solid.pressure,
                   solid.acc, solid.stress_gradient)


class SolidNeighbours(NamedTuple):
    """The solid's half neighbour list (numerics.neighbours.NeighbourList: each pair once) and the periodic box."""
    start: np.ndarray              # (N + 1,) int64, row a is index[start[a]:start[a + 1]]
    index: np.ndarray              # (pairs,) the neighbours b > a of each row
    crossing: np.ndarray           # (N,) bool, the rows that may need the minimum image
    targets_at_build: np.ndarray   # (N, 3) m, the positions the list was built at (the skin test)
    period: np.ndarray             # (3,) m, the periodic box's lengths (0: not periodic)

    @classmethod
    def of(cls, neighbours, period):
        """The arrays of a built NeighbourList (taken anew after each rebuild, which replaces them)."""
        return cls(neighbours.start, neighbours.index, neighbours.crossing, neighbours.targets_at_build, period)


class SolidBuffers(NamedTuple):
    """SolidWork's arrays as the compiled drivers take them (SolidWork.buffers()); N particles, P pairs of the list,
    C chunks (threads) of the half-list passes. Rates are per second; the pair cache belongs to the list's build."""
    vhat: np.ndarray              # (N, 3) m/s, the XSPH velocity that moves particles
    volume: np.ndarray            # (N,) m^3, m / rho once per step (particle_volumes)
    grad_v: np.ndarray            # (N, 3, 3) 1/s, the velocity gradient L of eq. (4)
    drho: np.ndarray              # (N,) kg/m^3/s, eq. (3)'s continuity rate
    dstress: np.ndarray           # (N, 6) Pa/s, the Jaumann Hooke rate of eq. (3)
    sigma_over_rho2: np.ndarray   # (N, 6) m^2/s^2 (Pa m^6/kg^2), sigma / rho^2 of eq. (5)
    art_stress: np.ndarray        # (N, 6) m^2/s^2, Gray's artificial stress R / rho^2
    eig_work: np.ndarray          # (N, 10, 3) eigen-solver scratch, rows 3..5 the warm-started eigenvectors
    kinv: np.ndarray              # (N, 3, 3) kernel-gradient correction K^-1 (solid.velocity_gradient = linear)
    mls_rows: np.ndarray          # (N, 3 or 9, 9) rows of the quadratic fit's M^-1 (solid/fitted_gradient.py)
    mls_weights: np.ndarray       # (P, 6) pair cache of the quadratic fit (G_ab, G_ba); (0, 6) without it
    w: np.ndarray                 # (P,) 1/m^3, pair cache W_ab
    f: np.ndarray                 # (P,) 1/m^5, pair cache F_ab (grad W_ab = F_ab r_ab)
    buf: np.ndarray               # (C, N, 18) per-chunk sums of the velocity gradient passes
    vector_buf: np.ndarray        # (C, N, 3) per-chunk sums of the momentum passes
    scalar_buf: np.ndarray        # (C, N) per-chunk sums of the continuity pass
    blocks: np.ndarray            # (C, columns) pair-block scratch (numerics/pair_blocks.py)
    hessian: np.ndarray           # (N or 0, 3, 6) 1/(m s), velocity Hessian (solid/gradient_integration.py)
    dstress_gradient: np.ndarray  # (N or 0, 3, 6) Pa/(m s), rate of the stress gradient
    force_rows: np.ndarray        # (N or 0, 3, 9) the stress gradient's force rows
    hessian_moments: np.ndarray   # (C, N or 0, 27) per-chunk sums of the Hessian pass
    turn: np.ndarray              # (N,) integral of |L| dt since the fit rows were made (dimensionless); with
                                  # solid.fit_refresh = rotate the Green strain's norm since then
    fit_refresh: np.ndarray       # (1,) int64, set to 1 by the driver when the fit rows are due
    pressure_scalars: np.ndarray  # (6, N or 0) scratch of the implicit pressure's solve (solid/implicit_pressure.py)
    pressure_vectors: np.ndarray  # (2, N or 0, 3) its velocity changes
    pressure_force: np.ndarray    # (N or 0, 3) its pair forces
    pressure_stats: np.ndarray    # (4,) int64: steps solved, iterations, most in one step, capped steps
    fit_rows0: np.ndarray         # (N or 0, 3 or 9, 9) solid.fit_refresh = rotate: the rows as they were made
    fit_rotation: np.ndarray      # (N or 0, 3, 3) each particle's rotation since then (solid/fit_rotation.py)
    fit_deformation: np.ndarray   # (N or 0, 3, 3) and its deformation gradient since then
    spin: np.ndarray              # (N or 0,) its turn since the rows were last turned


class SolidWork:
    """Scratch arrays of the solid passes, allocated once per build.

    Per-chunk accumulators of the half-list passes, one chunk per thread: `buf` (chunks, N, 18) for the velocity
    gradient passes, `vector_buf` (chunks, N, 3) for the momentum passes and the implicit pressure's, and
    `scalar_buf` (chunks, N) for the continuity pass and the implicit pressure's (each pass zeroes and sums only its
    own numbers: three columns of the wide buffer moved all of it through the cache); `blocks`: their pair blocks
    (pair_blocks.py). The pair cache (w, f, mls_weights) and moment_buf are replaced when the list is rebuilt: take
    `buffers()` after that, for each driver call.
    """

    def __init__(self, n, hessian_rows=False, implicit_pressure=False, rotate_fit=False):
        self.buf = np.zeros((max(numba.get_num_threads(), 1), n, 18))
        self.vector_buf = np.zeros(self.buf.shape[:2] + (3,))
        self.scalar_buf = np.zeros(self.buf.shape[:2])
        self.blocks = block_scratch(self.buf.shape[0], max(GRAY_BLOCK_COLUMNS, MLS_BLOCK_COLUMNS))
        self.vhat = np.zeros((n, 3))
        self.volume = np.zeros(n)           # m / rho, once per step (particle_volumes)
        self.grad_v = np.zeros((n, 3, 3))
        self.drho = np.zeros(n)
        self.dstress = np.zeros((n, 6))
        self.sigma_over_rho2 = np.zeros((n, 6))
        self.art_stress = np.zeros((n, 6))
        self.eig_work = np.zeros((n, 10, 3))
        self.eig_work[:, 3:6] = np.eye(3)   # eigenvector guesses, warm-started from step to step
        self.kinv = np.zeros((n, 3, 3))
        self.kinv[:] = np.eye(3)            # kernel-gradient correction K^-1 (identity until first computed)
        # quadratic fit: rows 0..2 of M^-1 (solid/fitted_gradient.py), 0..8 with the strain-gradient integration
        self.mls_rows = np.zeros((n, N_BASIS if hessian_rows else 3, N_BASIS))
        m = n if hessian_rows else 0   # solid/gradient_integration.py's arrays, empty when it is off
        self.hessian = np.zeros((m, 3, 6))
        self.dstress_gradient = np.zeros((m, 3, 6))
        self.force_rows = np.zeros((m, 3, N_BASIS))
        self.hessian_moments = np.zeros((self.buf.shape[0], m, 3 * N_BASIS))
        self.mls_order = np.zeros(n, dtype=np.int64)
        self.turn = np.zeros(n)                      # integral of |L| dt since the fit rows were made
        self.fit_refresh = np.zeros(1, dtype=np.int64)   # set by the stepper: the rows are due
        self.moment_buf = np.zeros((0, 0, 0))       # allocated on first use (chunks, N, 45)
        self.mls_weights = np.zeros((0, 6))          # pair cache (G_ab, G_ba), allocated on first use
        k = n if implicit_pressure else 0            # solid/implicit_pressure.py's scratch, empty when it is off
        self.pressure_scalars = np.zeros((6, k))
        self.pressure_vectors = np.zeros((2, k, 3))
        self.pressure_force = np.zeros((k, 3))
        self.pressure_stats = np.zeros(4, dtype=np.int64)
        r = n if rotate_fit else 0                   # solid/fit_rotation.py's arrays, empty when it is off
        self.fit_rows0 = np.zeros((r,) + self.mls_rows.shape[1:])
        self.fit_rotation = np.zeros((r, 3, 3))
        self.fit_rotation[:] = np.eye(3)
        self.fit_deformation = self.fit_rotation.copy()
        self.spin = np.zeros(r)
        self.w = np.zeros(0)
        self.f = np.zeros(0)

    def resize_pairs(self, npairs):
        if len(self.w) != npairs:
            self.w = np.zeros(npairs)
            self.f = np.zeros(npairs)

    def buffers(self):
        """The arrays the drivers use, as they are now (after any reallocation)."""
        return SolidBuffers(self.vhat, self.volume, self.grad_v, self.drho, self.dstress, self.sigma_over_rho2,
                            self.art_stress, self.eig_work, self.kinv, self.mls_rows, self.mls_weights, self.w,
                            self.f, self.buf, self.vector_buf, self.scalar_buf, self.blocks, self.hessian,
                            self.dstress_gradient, self.force_rows, self.hessian_moments, self.turn,
                            self.fit_refresh, self.pressure_scalars, self.pressure_vectors, self.pressure_force,
                            self.pressure_stats, self.fit_rows0, self.fit_rotation, self.fit_deformation,
                            self.spin)


@njit(cache=True, fastmath=False, error_model="numpy", nogil=True)
def mirror_clamp_velocities(vel, clamp_mirror):
    """Ghost clamp (solid.clamp = mirrored): v_g = -v_m, the odd image of the body's velocity across the face."""
    for g in range(clamp_mirror.shape[0]):
        m = clamp_mirror[g]
        if m >= 0:
            for k in range(3):
                vel[g, k] = -vel[m, k]


@njit(cache=True, fastmath=False, error_model="numpy", nogil=True)
def fold_clamp_forces(acc, mass, body, clamp_mirror):
    """Ghost clamp: the pair forces on ghost g act on its image m with the opposite sign (v_g = -v_m).

    The power of a force F_g on the ghost is F_g . v_g = -F_g . v_m, so -F_g is the force on m that does the same
    work; `acc` of the ghost holds the body force too, which is not a pair force and is left out.
    """
    for g in range(clamp_mirror.shape[0]):
        m = clamp_mirror[g]
        if m >= 0:
            ratio = mass[g] / mass[m]
            for k in range(3):
                acc[m, k] -= (acc[g, k] - body[k]) * ratio


@njit(cache=True, fastmath=False, error_model="numpy", nogil=True)
def _finish_acceleration(acc, mass, movable, body, ext_acc, clamp_mirror):
    """After a momentum pass: a ghost clamp's forces folded onto the body, the clamp held (zero acceleration), and
    the external push `ext_acc` (N, 3) added to movable particles ((0, 3): none)."""
    fold_clamp_forces(acc, mass, body, clamp_mirror)
    has_ext = ext_acc.shape[0] == acc.shape[0]
    for a in range(acc.shape[0]):
        if not movable[a]:
            acc[a, 0] = 0.0
            acc[a, 1] = 0.0
            acc[a, 2] = 0.0
        elif has_ext:
            acc[a, 0] += ext_acc[a, 0]
            acc[a, 1] += ext_acc[a, 1]
            acc[a, 2] += ext_acc[a, 2]


@njit(cache=True, fastmath=False, error_model="numpy", nogil=True)
def fitted_acceleration(state, neighbours, prm, work, ext_acc, clamp_mirror, variant):
    """Eq. (5) (Satake et al.; Gray, Monaghan & Swift 2001) into state.acc (zero for clamp particles) with the
    quadratic fit's pair weights (solid.velocity_gradient = quadratic, solid/fitted_gradient.py), refreshing the pair
    cache at the current positions.

    `state`: SolidArrays, `neighbours`: SolidNeighbours, `prm`: SolidParams, `work`: SolidBuffers; `ext_acc`
    (N, 3) m/s^2 added to movable particles (the fluid's push), or (0, 3) for none; `clamp_mirror` (N,) int64,
    the ghost clamp's mirror images (solid.clamp = mirrored), or empty; `variant`: driver_variant(prm).
    """
    rho, stress, mass, movable = state.rho, state.stress, state.mass, state.movable
    sigma_over_rho2 = work.sigma_over_rho2
    stress_terms(stress, rho, prm.rho0, prm.c0 * prm.c0, prm.art_eps, state.pressure, sigma_over_rho2,
                 work.art_stress, work.eig_work)
    if prm.implicit_pressure:   # the pressure's force comes from the step's implicit solve
        deviatoric_over_rho2(stress, rho, sigma_over_rho2)
    body = np.array([prm.gx, prm.gy, prm.gz])
    if prm.cell_moment > 0.0:
        gradient_force_rows(mass, rho, state.stress_gradient, prm.cell_moment, work.mls_rows, work.force_rows)
    momentum_rate_mls(state, neighbours, prm, work, body, variant)
    _finish_acceleration(state.acc, mass, movable, body, ext_acc, clamp_mirror)


@njit(cache=True, fastmath=False, error_model="numpy", nogil=True)
def sph_acceleration(state, neighbours, prm, work, ext_acc, clamp_mirror, variant):
    """Eq. (5) as fitted_acceleration, with Gray's SPH gradient (solid.velocity_gradient = sph, the paper's) or its
    kernel-corrected form (linear): solid/gray2001.py; `variant` () (driver_variant)."""
    stress_terms(state.stress, state.rho, prm.rho0, prm.c0 * prm.c0, prm.art_eps, state.pressure,
                 work.sigma_over_rho2, work.art_stress, work.eig_work)
    body = np.array([prm.gx, prm.gy, prm.gz])
    momentum_rate(state, neighbours, prm, work, body)
    _finish_acceleration(state.acc, state.mass, state.movable, body, ext_acc, clamp_mirror)


def solid_acceleration(state, neighbours, prm, work, ext_acc, clamp_mirror):
    """Eq. (5) into state.acc with the scheme's momentum pass (the driver of `solid_drivers`)."""
    solid_drivers(prm)[1](state, neighbours, prm, work, ext_acc, clamp_mirror, driver_variant(prm))


@njit(cache=True, fastmath=False, error_model="numpy", nogil=True)
def particle_volumes(mass, rho, volume):
    """V_a = m_a / rho_a, once per step for the pair passes that weight each neighbour by its volume."""
    for a in range(mass.shape[0]):
        volume[a] = mass[a] / rho[a]


@njit(cache=True, fastmath=False, error_model="numpy", nogil=True)
def _max_norm(v):
    m = 0.0
    for a in range(v.shape[0]):
        s = v[a, 0] * v[a, 0] + v[a, 1] * v[a, 1] + v[a, 2] * v[a, 2]
        if s > m:
            m = s
    return math.sqrt(m)


@njit(cache=True, fastmath=False, error_model="numpy", nogil=True)
def _skin_may_be_crossed(step, force_first, dt, pos, pos_at_build, vel, acc, prm):
    """Whether the next step could carry a particle past half the list's skin (the caller returns for a rebuild);
    never for the first step after a rebuild when `force_first`."""
    # XSPH speed is at most (1 + 2 eps) times the largest neighbour speed; stop before the skin can be crossed.
    reach = dt * (1.0 + 2.0 * prm.xsph_eps) * (_max_norm(vel) + 0.5 * dt * _max_norm(acc))
    return (step > 0 or not force_first) and max_displacement(pos, pos_at_build) + reach > prm.half_skin


@njit(cache=True, fastmath=False, error_model="numpy", nogil=True)
def _half_kick(dt, vel, acc, movable, clamp_mirror):
    """v += dt / 2 a for movable particles; a ghost clamp's velocities follow their images."""
    for a in range(vel.shape[0]):
        if movable[a]:
            for k in range(3):
                vel[a, k] += 0.5 * dt * acc[a, k]
    mirror_clamp_velocities(vel, clamp_mirror)


@njit(cache=True, fastmath=False, error_model="numpy", nogil=True)
def _advance_state(dt, state, work, prm, clamp_mirror):
    """rho, S (and the stress gradient) by their rates (eq. (3)); r by vhat, a ghost's by its image's reversed."""
    pos, rho, stress, movable = state.pos, state.rho, state.stress, state.movable
    stress_gradient = state.stress_gradient
    vhat, drho, dstress, dstress_gradient = work.vhat, work.drho, work.dstress, work.dstress_gradient
    ghost_clamp = clamp_mirror.shape[0] > 0
    for a in range(pos.shape[0]):
        if movable[a] or not ghost_clamp:
            rho[a] += dt * drho[a]
            for k in range(6):
                stress[a, k] += dt * dstress[a, k]
            if prm.cell_moment > 0.0:
                for k in range(3):
                    for c in range(6):
                        stress_gradient[a, k, c] += dt * dstress_gradient[a, k, c]
        if movable[a]:
            for k in range(3):
                pos[a, k] += dt * vhat[a, k]
        elif ghost_clamp and clamp_mirror[a] >= 0:
            # the ghost's displacement is its image's, reversed, as its velocity is
            for k in range(3):
                pos[a, k] -= dt * vhat[clamp_mirror[a], k]


@njit(cache=True, fastmath=False, error_model="numpy", nogil=True)
def _fit_refresh_due(dt, prm, work):
    """After a step: whether the quadratic fit's rows are due to be remade (some neighbourhood turned or strained by
    prm.fit_refresh_turn since they were made); with solid.fit_refresh = rotate, turns the rows that are due to be
    turned (solid/fit_rotation.py) and asks for a remake only past prm.fit_refresh_strain."""
    grad_v, turn = work.grad_v, work.turn
    if prm.fit_refresh_turn > 0.0 and prm.rotate_fit:
        strained, turned = follow_spin(grad_v, dt, work.fit_rotation, work.fit_deformation, turn, work.spin)
        if strained > prm.fit_refresh_strain:
            return True
        if turned > prm.fit_refresh_turn:
            rotate_fit_rows(work.fit_rows0, work.fit_rotation, work.spin, prm.fit_refresh_turn, work.mls_rows)
    elif prm.fit_refresh_turn > 0.0:
        worst = 0.0
        for a in range(grad_v.shape[0]):
            g = grad_v[a]
            turn[a] += dt * math.sqrt(g[0, 0] ** 2 + g[0, 1] ** 2 + g[0, 2] ** 2 + g[1, 0] ** 2 + g[1, 1] ** 2
                                      + g[1, 2] ** 2 + g[2, 0] ** 2 + g[2, 1] ** 2 + g[2, 2] ** 2)
            worst = max(worst, turn[a])
        if worst > prm.fit_refresh_turn:
            return True
    return False


@njit(cache=True, fastmath=False, error_model="numpy", nogil=True)
def fitted_leapfrog(n_steps, force_first, dt, state, neighbours, prm, work, ext_acc, clamp_mirror, variant):
    """Advance up to `n_steps` leapfrog steps of the module docstring (Satake et al. eqs. (3)-(5), the solid of
    Gray, Monaghan & Swift 2001) with the quadratic fit's velocity gradient (solid.velocity_gradient = quadratic);
    returns the number done (fewer: the neighbour list needs a rebuild, or the fit's rows a remake).

    `state`: SolidArrays, advanced in place; `neighbours`: SolidNeighbours; `prm`: SolidParams; `work`:
    SolidBuffers; `ext_acc`, `clamp_mirror`, `variant`: as fitted_acceleration's. `force_first`: take the first step
    even if the skin test fails (used right after a rebuild, when a particle faster than half the skin per step
    would otherwise stall the run; the watchdog's speed limit catches those). Also returns early, with
    work.fit_refresh[0] = 1, once some particle's neighbourhood has turned or strained by prm.fit_refresh_turn
    (the integral of |L| dt) since the quadratic fit's rows were made: the rows belong to the positions they were
    made at, and a stale fit leaks the linear part of the motion into the fitted curvature.
    """
    pos, vel, rho, stress, mass, movable = state.pos, state.vel, state.rho, state.stress, state.mass, state.movable
    acc = state.acc
    grad_v = work.grad_v
    for step in range(n_steps):
        if _skin_may_be_crossed(step, force_first, dt, pos, neighbours.targets_at_build, vel, acc, prm):
            return step
        _half_kick(dt, vel, acc, movable, clamp_mirror)
        if prm.cell_moment > 0.0 or prm.implicit_pressure:
            particle_volumes(mass, rho, work.volume)     # rho is the step's start's until the update below
        if prm.implicit_pressure:
            implicit_pressure_step(dt, state, neighbours, prm, work, clamp_mirror)
        xsph_velocity_and_mls_gradient(state, neighbours, prm, work)
        # the fitted gradient's own divergence, so pressure and deviatoric stress see one strain rate
        velocity_divergence_rate(rho, grad_v, work.drho)
        jaumann_stress_rate(grad_v, stress, prm.shear_modulus, work.dstress)
        if prm.cell_moment > 0.0:
            velocity_hessian(state, neighbours, prm, work)
            stress_gradient_rate(work.hessian, grad_v, stress, state.stress_gradient, prm.shear_modulus,
                                 prm.gradient_bulk_modulus, work.dstress_gradient)
        _advance_state(dt, state, work, prm, clamp_mirror)
        fitted_acceleration(state, neighbours, prm, work, ext_acc, clamp_mirror, variant)
        _half_kick(dt, vel, acc, movable, clamp_mirror)
        if _fit_refresh_due(dt, prm, work):
            work.fit_refresh[0] = 1
            return step + 1
    return n_steps


@njit(cache=True, fastmath=False, error_model="numpy", nogil=True)
def sph_leapfrog(n_steps, force_first, dt, state, neighbours, prm, work, ext_acc, clamp_mirror, variant):
    """fitted_leapfrog's steps with Gray's SPH velocity gradient (solid.velocity_gradient = sph, the paper's) or its
    kernel-corrected form (linear): solid/gray2001.py. Returns the number of steps done; `variant` is () (its passes
    take none: driver_variant)."""
    pos, vel, rho, stress, mass, movable = state.pos, state.vel, state.rho, state.stress, state.mass, state.movable
    acc = state.acc
    grad_v = work.grad_v
    for step in range(n_steps):
        if _skin_may_be_crossed(step, force_first, dt, pos, neighbours.targets_at_build, vel, acc, prm):
            return step
        _half_kick(dt, vel, acc, movable, clamp_mirror)
        particle_volumes(mass, rho, work.volume)     # rho is the step's start's until the update below
        xsph_velocity_and_gradient(state, neighbours, prm, work)
        if prm.gradient_order == 0:
            continuity_rate(state, neighbours, work)
        else:
            # the corrected gradient's own divergence, so pressure and deviatoric stress see one strain rate
            velocity_divergence_rate(rho, grad_v, work.drho)
        jaumann_stress_rate(grad_v, stress, prm.shear_modulus, work.dstress)
        _advance_state(dt, state, work, prm, clamp_mirror)
        sph_acceleration(state, neighbours, prm, work, ext_acc, clamp_mirror, variant)
        _half_kick(dt, vel, acc, movable, clamp_mirror)
    return n_steps


def solid_drivers(prm):
    """(leapfrog, acceleration) of the scheme in prm: each compiles only its own passes, so a run compiles what its
    scheme uses (Gray's scheme leaves the quadratic fit out, the fit leaves Gray's passes out)."""
    return (fitted_leapfrog, fitted_acceleration) if prm.gradient_order == 2 else (sph_leapfrog, sph_acceleration)
