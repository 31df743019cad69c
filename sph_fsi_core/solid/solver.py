"""The elastic solid's solver: its settings, neighbour list, quadratic fit, stable step and sub-steps.

`SolidSolver` is the solid's twin of fluid.solver.FluidSolver. It owns what the compiled drivers of stepper.py need
between calls (the half neighbour list, SolidWork's scratch and pair cache, the scheme's SolidParams) and the loop
that calls them: `advance(n, dt, ext_acc)` takes n leapfrog steps, rebuilding the list when a particle may cross half
its skin and remaking (or, with solid.fit_refresh = rotate, turning) the quadratic fit's rows when the drivers ask.
simulation.Simulation decides how many steps of which size and what external push they hold (the fluid's, or a
prescribed load); this module only advances the body.

Settings that must fit together (the implicit pressure and the strain gradient need the quadratic fit, ...) are
checked where they are declared (schema.check_combinations); here only what depends on the state: a forced
solid.time_step against the stable step at the current velocities.
"""
import math
from typing import NamedTuple

import numpy as np

from ..numerics.kernels import SUPPORT_RADIUS_IN_H
from ..numerics.neighbours import NeighbourList, pair_kernel_values
from ..errors import SceneError
from .fitted_gradient import MOMENT_COUNT, mls_fit_rows, mls_pair_weights
from .gradient_integration import gradient_strain_energy
from .gray2001 import material_constants, strain_energy
from .implicit_pressure import IMPULSE_ROW as PRESSURE_IMPULSE, deviatoric_wave_speed
from .stepper import (SolidArrays, SolidNeighbours, SolidWork, driver_variant, make_params,
                      mirror_clamp_velocities, solid_acceleration, solid_drivers)

NO_EXTERNAL = np.zeros((0, 3))
NO_MIRROR = np.zeros(0, dtype=np.int64)
# the strain gradient's volumetric part (solid.volumetric_gradient) stepped explicitly stiffens the lattice's shortest
# modes as a wave of speed^2 kappa K / rho would: the default scheme's linear stability limit on the paper's beam
# (validation/linear_modes.default_scheme_stable_cfl and its volumetric twin) falls from cfl 0.433 to 0.417 / 0.392 /
# 0.341 / 0.179 at nu = 0.3 / 0.4 / 0.45 / 0.49, kappa = 0.05-0.13; the largest, so the step keeps its margin
VOLUMETRIC_GRADIENT_WAVE = 0.13


class SolidSettings(NamedTuple):
    """A scene's solid settings as the solver uses them (solid_settings)."""
    bulk_modulus: float    # Pa, K = E / (3 (1 - 2 nu))
    shear_modulus: float   # Pa, G = E / (2 (1 + nu))
    sound_speed: float     # m/s, c0 = sqrt(K / rho0)
    wave_speed: float      # m/s, the wave that sets the step (step_wave_speed)
    params: object         # stepper.SolidParams


def step_wave_speed(pressure, c0, shear, density, gradient_bulk_modulus=0.0):
    """The wave speed that sets the solid's step: c0, or with the implicit pressure the deviatoric stress's fastest
    wave (solid/implicit_pressure.py); with the strain gradient's volumetric part (stepped explicitly)
    sqrt(c^2 + VOLUMETRIC_GRADIENT_WAVE K / rho) (its stiffness at the lattice's scale)."""
    c = deviatoric_wave_speed(shear, density) if pressure == "implicit" else c0
    if gradient_bulk_modulus > 0.0:
        return math.sqrt(c * c + VOLUMETRIC_GRADIENT_WAVE * gradient_bulk_modulus / density)
    return c


def solid_settings(values, h, spacing):
    """Material constants and the passes' parameters from a scene's values (scene.SceneSpec.values)."""
    v = values
    bulk, shear, c0 = material_constants(v["solid.young_modulus"], v["solid.poisson_ratio"], v["solid.density"])
    params = make_params(
        h=h, spacing=spacing, density=v["solid.density"], c0=c0, shear_modulus=shear,
        xsph_eps=v["solid.xsph_epsilon"], alpha=v["solid.artificial_viscosity_alpha"],
        beta=v["solid.artificial_viscosity_beta"], art_eps=v["solid.artificial_stress_epsilon"],
        art_exponent=v["solid.artificial_stress_exponent"], gravity=v["scene.gravity"],
        skin=v["numerics.neighbour_skin"] * h,
        velocity_gradient=v["solid.velocity_gradient"], nodal_integration=v["solid.nodal_integration"],
        fit_refresh_turn=v["solid.fit_refresh_turn"], pressure=v["solid.pressure"],
        pressure_tolerance=v["solid.pressure_tolerance"],
        pressure_max_iterations=v["solid.pressure_max_iterations"], fit_refresh=v["solid.fit_refresh"],
        fit_refresh_strain=v["solid.fit_refresh_strain"], volumetric_gradient=v["solid.volumetric_gradient"])
    wave = step_wave_speed(v["solid.pressure"], c0, shear, v["solid.density"], params.gradient_bulk_modulus)
    return SolidSettings(bulk, shear, c0, wave, params)


class SolidSolver:
    """The solid's work arrays, neighbour list, fit and settings; `advance(n, dt, ext_acc)` takes n steps.

    `solid`: state.SolidState (advanced in place); `clamp_mirror`: the ghost clamp's mirror map (solid.clamp =
    mirrored; empty for the fixed clamp); `values`: the scene's settings. `start()` makes the list, the fit and the
    first forces; `allocated` solvers (precompile.py) skip it."""

    def __init__(self, solid, values, h, spacing, period, box_lo, box_hi, clamp_mirror):
        self.solid = solid
        self.h, self.spacing = float(h), float(spacing)
        self.period = period
        self.clamp_mirror = clamp_mirror
        self.initial_positions = solid.pos.copy()
        self.neighbour_builds = 0
        mirror_clamp_velocities(solid.vel, clamp_mirror)
        gradient_integration = values["solid.nodal_integration"] == "gradient"
        if gradient_integration:
            solid.stress_gradient = np.zeros((solid.count, 3, 6))
        self.work = SolidWork(solid.count, hessian_rows=gradient_integration,
                              implicit_pressure=values["solid.pressure"] == "implicit",
                              rotate_fit=values["solid.fit_refresh"] == "rotate")
        self.neighbours = NeighbourList(SUPPORT_RADIUS_IN_H * self.h, values["numerics.neighbour_skin"] * self.h,
                                        period=period, box_lo=box_lo, box_hi=box_hi, half=True)
        self.configure(values)

    # ---- settings ----------------------------------------------------------------------------------------
    def settings_for(self, values):
        """`values`' settings, without applying them; SceneError if a forced solid.time_step is above the stable
        limit at the current velocities."""
        settings = solid_settings(values, self.h, self.spacing)
        forced = values["solid.time_step"]
        limit = self._stable_dt(values["solid.cfl"], settings.wave_speed)
        if forced > limit:
            raise SceneError(f"solid.time_step = {forced:g} s: above the stable limit {limit:.4g} s "
                             f"(solid.cfl * h / (c + |v|max) with c = {settings.wave_speed:.4g} m/s); "
                             f"allowed: (0, {limit:.4g}] s, or 0 for automatic")
        return settings

    def configure(self, values):
        """Apply `values`' settings (a live change takes effect at the next step)."""
        self.settings = self.settings_for(values)
        self.params = self.settings.params
        self.cfl = values["solid.cfl"]
        self.forced_dt = values["solid.time_step"]

    # ---- neighbour list and fit ----------------------------------------------------------------------------
    def start(self):
        """The list, the quadratic fit and the forces at the built positions: what the first step needs."""
        self.rebuild()
        self.acceleration()

    def rebuild(self):
        s, nb, wk = self.solid, self.neighbours, self.work
        nb.build(s.pos, s.pos)
        wk.resize_pairs(nb.pairs)
        pair_kernel_values(s.pos, s.pos, nb.start, nb.index, self.h, self.period, wk.w, wk.f)
        self.refit()
        self.neighbour_builds += 1

    def refit(self, pair_weights=True):
        """The quadratic fit's moment rows (and, unless pair_weights is False, the pair weights made from them) at
        the current positions. Without them the next step's gradient pass and implicit pressure use the weights the
        last forces were made with, and the next momentum pass makes them with the new rows."""
        s, nb, wk = self.solid, self.neighbours, self.work
        wk.turn[:] = 0.0
        wk.fit_refresh[0] = 0
        if self.params.gradient_order == 2:
            if wk.moment_buf.shape[:2] != (wk.buf.shape[0], s.count):
                wk.moment_buf = np.zeros((wk.buf.shape[0], s.count, MOMENT_COUNT))
            mls_fit_rows(s.pos, self.period, s.mass, s.rho, nb.start, nb.index, self.h, wk.mls_rows, wk.mls_order,
                         wk.moment_buf)
            if self.params.rotate_fit:     # solid/fit_rotation.py turns these from now on
                wk.fit_rows0[:] = wk.mls_rows
                wk.fit_rotation[:] = np.eye(3)
                wk.fit_deformation[:] = np.eye(3)
                wk.spin[:] = 0.0
            if wk.mls_weights.shape[0] != nb.pairs:
                wk.mls_weights = np.zeros((nb.pairs, 6))
                pair_weights = True
            if pair_weights:
                mls_pair_weights(s.pos, self.period, s.mass, s.rho, nb.start, nb.index, self.h, wk.mls_rows,
                                 wk.mls_weights)

    def linear_fit_count(self):
        """Moving particles whose quadratic fit fell back to the linear one (fewer than three layers in some
        direction within their kernel); 0 without the quadratic fit."""
        if self.params.gradient_order != 2:
            return 0
        return int(np.count_nonzero(self.solid.movable & (self.work.mls_order < 2)))

    # ---- time step -----------------------------------------------------------------------------------------
    def _stable_dt(self, cfl, wave_speed):
        vel = self.solid.vel
        vmax = float(np.sqrt((vel ** 2).sum(axis=1).max())) if self.solid.count else 0.0
        return cfl * self.h / (wave_speed + vmax)

    def stable_dt(self):
        """dt = cfl * h / (c + |v|max), the solid's acoustic limit (METHOD sec. 1), c the wave that sets the step."""
        return self._stable_dt(self.cfl, self.settings.wave_speed)

    # ---- steps ---------------------------------------------------------------------------------------------
    def acceleration(self, ext_acc=NO_EXTERNAL):
        """Eq. (5) into solid.acc at the current positions."""
        solid_acceleration(SolidArrays.of(self.solid), SolidNeighbours.of(self.neighbours, self.period),
                           self.params, self.work.buffers(), ext_acc, self.clamp_mirror)

    def leapfrog_arguments(self, n, force_first, dt, ext_acc=NO_EXTERNAL):
        """The arguments of the scheme's driver (solid_drivers(params)[0]) for `n` steps of `dt`, as they are now (a
        rebuild or refit replaces the list's arrays and the pair cache)."""
        return (n, force_first, dt, SolidArrays.of(self.solid), SolidNeighbours.of(self.neighbours, self.period),
                self.params, self.work.buffers(), ext_acc, self.clamp_mirror, driver_variant(self.params))

    def advance(self, n, dt, ext_acc=NO_EXTERNAL):
        """`n` leapfrog steps of `dt` holding the external push `ext_acc` ((N, 3) m/s^2, or NO_EXTERNAL). Returns
        True when a step's implicit pressure reached solid.pressure_max_iterations for the first time in the run."""
        wk = self.work
        leapfrog = solid_drivers(self.params)[0]
        done, force = 0, False
        capped = int(wk.pressure_stats[3])
        while done < n:
            k = leapfrog(*self.leapfrog_arguments(n - done, force, dt, ext_acc))
            done += k
            if wk.fit_refresh[0]:      # the neighbourhoods turned: new fit rows, same list (its skin test stands)
                self.refit(pair_weights=not (self.params.implicit_pressure or self.params.rotate_fit))
                force = False
            elif done < n:
                self.rebuild()
                force = True
        return capped == 0 and wk.pressure_stats[3] > 0

    # ---- read-only views -----------------------------------------------------------------------------------
    def velocity(self):
        """The solid particles' velocity at the end of the step, (N, 3) m/s: what every output reports.

        With the implicit pressure the stored velocity is the leapfrog's without the pressure's last half impulse
        (solid/implicit_pressure.py): v + u/2, u the last step's pressure impulse, is the particles' velocity, as
        the relaxation takes it (relax). Reported as stored, a body at rest under load showed a kinetic energy of
        17 % of its strain energy (Antoci's gate under its water's pressure), and the paper's swinging beam a total
        energy that rose and fell by 4.6 % in every swing where v + u/2 keeps it within 0.2 %. With the explicit
        pressure: the stored array itself, not a copy (read it, do not write it)."""
        impulse = self.work.pressure_vectors[PRESSURE_IMPULSE]
        if len(impulse):
            return self.solid.vel + 0.5 * impulse
        return self.solid.vel

    def strain_energy(self):
        """The body's strain energy, J (the strain gradient's part included where the scheme has it)."""
        s, settings = self.solid, self.settings
        energy = strain_energy(s.mass, s.rho, s.stress, s.pressure, settings.shear_modulus, settings.bulk_modulus)
        if len(s.stress_gradient):
            energy += gradient_strain_energy(s.mass, s.rho, s.stress_gradient, self.params.cell_moment,
                                             settings.shear_modulus, self.params.gradient_bulk_modulus)
        return energy

    def pressure_solve_stats(self):
        """The implicit pressure's solves so far (solid.pressure = implicit): steps, iterations per step, the most in
        one step, steps that hit solid.pressure_max_iterations; None without it."""
        if not self.params.implicit_pressure:
            return None
        steps, iterations, most, capped = (int(k) for k in self.work.pressure_stats)
        return {"steps": steps, "iterations_per_step": iterations / steps if steps else 0.0,
                "iterations_max": most, "capped_steps": capped}

    # ---- the static cases' relaxation ------------------------------------------------------------------------
    def relax(self, keep):
        """Scale the particles' velocity by `keep` (Simulation's relaxation of a static case).

        With the implicit pressure the solid's stored velocity is the leapfrog's without the pressure's last half
        impulse: at rest it is dt/2 of the deviatoric and external acceleration, which the pressure's impulse
        cancels, not zero. The relaxation acts on the velocity the particles have, v + u/2 (u the last step's
        pressure impulse, solid/implicit_pressure.py): scaling v alone held a settled strip off its rest state, by
        more the stronger the relaxation (+11.31 % at 1.0 of critical, +11.68 % at 0.25 against FE, +11.82 % with
        the explicit pressure at either; docs/validation/OPEN.md 6). Scaling every velocity keeps a mirrored
        clamp's ghosts the odd image of the body."""
        impulse = self.work.pressure_vectors[PRESSURE_IMPULSE]
        if len(impulse):
            self.solid.vel += 0.5 * impulse
            self.solid.vel *= keep
            self.solid.vel -= 0.5 * impulse
        else:
            self.solid.vel *= keep


# the largest solid.cfl run with the quadratic fit: 0.35 held on the paper's beam (0.3 in its gate), 0.4 diverged
QUADRATIC_FIT_TESTED_CFL = 0.35


def artificial_stress_warning(values):
    """Gray's artificial stress suits the paper's SPH gradient and harms the quadratic fit (docs/method.md): the
    warning for `values`, or None."""
    eps, gradient = values["solid.artificial_stress_epsilon"], values["solid.velocity_gradient"]
    if gradient == "sph" and eps == 0.0:
        return ("solid.velocity_gradient = sph without artificial stress (solid.artificial_stress_epsilon = "
                "0): particles under tension may pair up (the tensile instability); 0.15 is the tested value "
                "(solid.scheme = gray2001 sets it)")
    if gradient == "quadratic" and eps > 0.0 and values["solid.poisson_ratio"] >= 0.45:
        return (f"solid.artificial_stress_epsilon = {eps:g} with the quadratic fit and solid.poisson_ratio = "
                f"{values['solid.poisson_ratio']:g}: the artificial stress is not paired with the strain rate, and "
                f"in a nearly incompressible body it feeds a spurious mode that grows at fine spacings (the "
                f"paper's beam diverged at H/dp = 8); the quadratic fit needs none: set it to 0 (as "
                f"solid.scheme = quadratic_gradient and quadratic_plain do)")
    return None


def cfl_warning(values):
    """The quadratic fit's stable solid.cfl is lower than Gray's gradient's (docs/method.md, the solid's step
    factor): the warning for `values`, or None."""
    if values["solid.velocity_gradient"] == "quadratic" and values["solid.cfl"] > QUADRATIC_FIT_TESTED_CFL:
        return (f"solid.cfl = {values['solid.cfl']:g} with the quadratic fit: its stable limit lay between 0.35 and "
                f"0.4 on the paper's beam (Gray's gradient ran stably to 1.0 in the paper's gate, hence "
                f"gray2001's 0.5); {QUADRATIC_FIT_TESTED_CFL:g} or less is tested (a quadratic solid.scheme "
                f"sets 0.25)")
    return None
