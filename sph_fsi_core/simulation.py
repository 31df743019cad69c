"""The one time loop. `Simulation` builds a scene's phases and advances them; everything else only reads state.

`step()` advances one outer step, one time-series interval. The solid takes it as an integer number of solid steps
no larger than the stable step; the loop over solid steps runs compiled (solid.stepper.fitted_leapfrog or
sph_leapfrog, the scheme's). The fluid takes it as whole fluid steps (fluid.solver.FluidSolver.step), each no
larger than its stable step, the last ones shortened evenly so the interval ends on a step. After every outer step
the watchdog checks the state, so a run that goes wrong stops within one outer step with a diagnosis and nothing
non-finite ever leaves the simulator. Phases a scene does not have are None and cost nothing: no arrays, lists or
passes.
"""
import math
import time as _time

import numpy as np

from .coupling.solver import Coupling
from .diagnostics import Diverged, Watchdog, kinetic_energy
from .probes import ProbeSet, probe_columns
from .fluid.lost_water import LostWater
from .fluid.solver import FluidSolver
from .scene import SceneError, SceneSpec
from .state import WallState
from .scenes import BUILDERS, build_scene
from .solid.solver import NO_EXTERNAL, NO_MIRROR, SolidSolver, artificial_stress_warning, cfl_warning
from .jit_cache import start_parallel_runtime
from .numerics.kernels import lattice_density_scale

__all__ = ["Simulation", "Diverged"]

# the settling phase's velocity relaxation, rate = SETTLE_RELAXATION / fluid.settle_time: a velocity's memory falls
# to e^-10 over the phase, and the column still sinks into its compression (at g / rate, 0.1 m/s for 0.1 s)
SETTLE_RELAXATION = 10.0
# and its step, in units of h / c_b (_settle_water): about 2 correction iterations per step at 2
SETTLE_STEP_IN_H = 2.0


class Simulation:
    """A scene's particles and the loop that advances them. Construct from a validated SceneSpec."""

    def __init__(self, spec: SceneSpec):
        self.spec = spec
        self.builder = BUILDERS[spec.builder]
        self._pending = {}
        start_parallel_runtime()
        self._build()

    # ---- checkpoints (checkpoint.py): everything but the builder module, which is named -------------------
    def __getstate__(self):
        state = dict(self.__dict__)
        state["builder"] = self.spec.builder
        return state

    def __setstate__(self, state):
        self.__dict__.update(state)
        self.builder = BUILDERS[state["builder"]]
        start_parallel_runtime()     # a restored run's first kernel is a cached caller of parallel ones

    @classmethod
    def allocated(cls, spec: SceneSpec):
        """The scene's particles and its solid's arrays as a run allocates them, before any kernel runs (no
        neighbour list, fit or force yet; no fluid): what compiling the solid's driver ahead of a run needs, its
        arguments' types (precompile.py). Not a simulation to step."""
        sim = cls.__new__(cls)
        sim.spec, sim.builder = spec, BUILDERS[spec.builder]
        sim._pending = {}
        sim._build(start=False)
        return sim

    # ---- construction -------------------------------------------------------------------------------------
    def _build(self, start=True):
        """The scene's particles, the solid's arrays and (unless not `start`, for `allocated`) everything the
        first step needs: the solid's list, fit and forces, the fluid's solver, the coupling and the settling."""
        v = self.spec.values
        # the mirrored clamp's particles left out: unreached_clamp (scenes/built.without_unreached_clamp)
        built, self.unreached_clamp = build_scene(self.spec.builder, v)
        self.spacing = v["numerics.spacing"]
        self.h = v["numerics.smoothing_ratio"] * self.spacing
        self.solid = built.solid
        self.fluid = built.fluid
        self.walls = built.walls
        self.domain_lo, self.domain_hi = built.domain_lo, built.domain_hi
        self.probes = built.probes
        self.probe_set = ProbeSet(built.probes)
        # a prescribed load on the solid and the damping that settles it to static (scenes/clamped_plate.py);
        # None and 0 in every other scene, which then cost nothing
        self.solid_load, self.load_ramp_time = built.solid_load, built.load_ramp_time
        self.damping_rate = built.damping_rate
        self.fluid_damping_rate = built.fluid_damping_rate
        self.period = built.period
        self.time = 0.0
        self.solid_steps = 0
        self.solid_seconds = 0.0     # wall time inside the solid's steps (summary.json's solid_stepping_time_s)
        self.outer_steps = 0
        self.last_solid_dt = 0.0
        self.last_substeps = 0
        self.warnings = list(built.warnings)
        self.notes = list(built.notes)
        self._artificial_stress_warning = None   # the warnings that follow live changes
        self._cfl_warning = None
        self.solid_solver = None
        if self.solid is not None:
            self.solid_solver = SolidSolver(self.solid, v, self.h, self.spacing, self.period, built.domain_lo,
                                            built.domain_hi, self._clamp_mirror(built, v["solid.clamp"]))
        if not start:
            return
        if self.solid is not None:
            self.solid_solver.start()
            self._warn_if_quadratic_fit_falls_back()
            self._warn_about_solid_settings()
        self.fluid_solver = None
        self.fluid_steps = 0
        self.fluid_iterations = 0          # correction iterations, all steps
        self.fluid_capped_steps = 0        # steps that reached fluid.max_iterations
        self.last_fluid_dt = 0.0
        self.last_fluid_substeps = 0
        self.last_density_iterations = 0   # of the last fluid step
        self.last_density_error = 0.0      # max compression after the last fluid step
        self.last_density_error_mean = 0.0
        self._interval_stats = {}
        self._interval_push = np.zeros(3)   # the water's push on the solid, N, averaged over the last outer step
        self._fluid_dt_clamped = False
        self.coupling = None   # only with both a solid and a fluid (coupling/)
        self.settled = None    # what the settling phase did (fluid.settle_time > 0), for the summary
        self._gate_in_walls = False
        if self.fluid is not None:
            settle_time = v["fluid.settle_time"]
            release = built.release_walls
            lifted = release is not None and built.release_velocity is not None
            self._start_fluid(built, release if settle_time > 0.0 or lifted else None)
            if settle_time > 0.0:
                self.settled = self._settle_water(settle_time)
                if not lifted:
                    self._start_fluid(built, None)   # the release: the plates are gone, the solid is free
            # a gate lifted from t = 0 (_lift_gate): its rows in the fluid's wall array, where it started, how
            self._lift = ((self.walls.count if self.walls is not None else 0, release.pos.copy(),
                           np.asarray(built.release_velocity, dtype=np.float64), built.release_travel)
                          if lifted else None)
            self._gate_in_walls = lifted
            self.fluid_initial_positions = self.fluid.pos.copy()
            self.fluid_lost = np.zeros(self.fluid.count, dtype=np.bool_)   # left the domain: held still
            self._fluid_lost_at = np.zeros((self.fluid.count, 3))
            self.lost_water = LostWater(self.fluid.count, built)   # who left, when, where (fluid/lost_water.py)
        self.watchdog = Watchdog(self, built.domain_lo, built.domain_hi)
        self._probe_readings = self.probe_set.read(self)

    def _start_fluid(self, built, held):
        """The fluid solver and (with a solid) the coupling, against the tank's walls plus `held`: the scene's
        release plates (Built.release_walls) while the water settles, None from t = 0."""
        v = self.spec.values
        walls = self.walls
        if held is not None:
            walls = WallState(pos=np.concatenate([walls.pos, held.pos]) if walls is not None else held.pos,
                              mass=np.concatenate([walls.mass, held.mass]) if walls is not None else held.mass,
                              rho0=held.rho0)
        fluid_walls = walls
        if self.solid is not None:
            self.coupling = Coupling(self.solid, self.fluid, walls, self.h, self.period,
                                     v["fluid.density"], lattice_density_scale(v["numerics.smoothing_ratio"]),
                                     model=v["coupling.model"], gamma=v["coupling.gamma"],
                                     substeps=v["coupling.substeps"], relaxation=v["coupling.relaxation"],
                                     surface_threshold=v["coupling.surface_threshold"],
                                     skin=v["numerics.neighbour_skin"] * self.h, box_lo=built.domain_lo,
                                     box_hi=built.domain_hi)
            fluid_walls = self.coupling.boundary   # the solid is a moving wall of the fluid
        self.fluid_solver = FluidSolver(self.fluid, fluid_walls, self.h, self.period, built.domain_lo,
                                        built.domain_hi, v["numerics.neighbour_skin"] * self.h)
        self._apply_fluid_settings()
        self.last_density_error, self.last_density_error_mean = self.fluid_solver.density()

    def _settle_water(self, duration):
        """The water's start at rest under gravity (fluid.settle_time; METHOD sec. 2's steps, before t = 0).

        A column built on the lattice has no compression and so no pressure: released at once it falls freely
        until it is compressed to the density tolerance, and its load on walls and solid overshoots for tens of
        milliseconds (docs/method.md, fluid, "The start"). An experiment's water at rest is already at hydrostatic
        pressure. So before t = 0 the fluid steps alone for `duration` (the solid held where it was built, the
        scene's release plates in place), its velocity relaxed as dv/dt = -c v with c = SETTLE_RELAXATION /
        duration; then velocities are set to zero and the clock starts. Returns what the phase did."""
        solver = self.fluid_solver
        rate = SETTLE_RELAXATION / duration
        # The correction's work per step grows as dt^2 and the steps as 1 / dt (docs/method.md, fluid, "Time
        # step"): at rest the total falls with dt down to a few iterations per step, at dt ~ h / c_b with c_b =
        # sqrt(|g| H / tolerance) the column's breathing speed (scenes/tank.py). The phase steps there.
        height = float(np.ptp(self.fluid.pos[:, 2])) + self.spacing if self.fluid.count else 0.0
        gravity = float(np.sqrt(np.dot(self.spec["scene.gravity"], self.spec["scene.gravity"])))
        breathing = math.sqrt(gravity * height / self.spec["fluid.density_tolerance"])
        step_limit = SETTLE_STEP_IN_H * self.h / breathing if breathing > 0.0 else math.inf
        wall0 = _time.perf_counter()
        done, steps, iterations, capped = 0.0, 0, 0, 0
        while duration - done > 1e-12 * duration:
            remaining = duration - done
            dt_max = min(self._fluid_dt(-remaining), step_limit)
            n = max(1, math.ceil(remaining / dt_max * (1.0 - 1e-12)))
            dt = remaining / n
            if self.coupling is not None:
                self.coupling.before_fluid_step(solver)
            report = solver.step(dt)
            self.fluid.vel *= math.exp(-rate * dt)
            done += dt
            steps += 1
            iterations += report.iterations
            capped += int(report.capped)
        speed = float(np.sqrt((self.fluid.vel ** 2).sum(axis=1).max())) if self.fluid.count else 0.0
        self.fluid.vel[:] = 0.0
        if capped:
            self.warnings.append(f"settling before t = 0: {capped} of {steps} fluid step(s) reached "
                                 f"fluid.max_iterations = {self.spec['fluid.max_iterations']}")
        return {"settle_time_s": duration, "fluid_steps": steps, "iterations_mean": iterations / max(steps, 1),
                "capped_steps": capped, "relaxation_rate_per_s": rate, "residual_max_speed_m_s": speed,
                "density_error_max": float(report.error_max), "density_error_mean": float(report.error_mean),
                "wall_time_s": _time.perf_counter() - wall0}

    def _clamp_mirror(self, built, clamp):
        """The ghost clamp's mirror map for solid.clamp = mirrored; empty (the fixed clamp) otherwise."""
        if clamp == "fixed" or built.clamp_mirror is None:     # or free bodies only (scenes.build_scene checks)
            return NO_MIRROR
        return np.ascontiguousarray(built.clamp_mirror, dtype=np.int64)

    def _fluid_settings(self, spec):
        """The fluid solver's settings from `spec`; SceneError if a forced fluid.time_step is above the stable limit."""
        v = spec.values
        settings = dict(rho0=v["fluid.density"], nu=v["fluid.viscosity"], gravity=v["scene.gravity"],
                        tolerance=v["fluid.density_tolerance"], tolerance_on=v["fluid.tolerance_on"],
                        coefficient=v["fluid.correction_coefficient"], kappa=v["fluid.correction_kappa"],
                        min_iterations=v["fluid.min_iterations"], max_iterations=v["fluid.max_iterations"])
        forced = v["fluid.time_step"]
        if forced > 0.0:
            limit = self.fluid_solver.stable_dt(v["fluid.cfl"], nu=settings["nu"], gravity=settings["gravity"])
            if forced > limit:
                raise SceneError(f"fluid.time_step = {forced:g} s: above the stable limit {limit:.4g} s "
                                 f"(min of fluid.cfl * h / |v|max, fluid.cfl * sqrt(h / |g|), 0.125 h^2 / nu); "
                                 f"allowed: (0, {limit:.4g}] s, or 0 for automatic")
        return settings

    def _apply_fluid_settings(self):
        self.fluid_solver.configure(**self._fluid_settings(self.spec))

    def _warn_if_quadratic_fit_falls_back(self):
        """The quadratic fit needs three particle layers in every direction; thinner bodies get the linear fit."""
        linear = self.solid_solver.linear_fit_count()
        if linear:
            self.warnings.append(
                f"solid.velocity_gradient = quadratic: {linear} of {self.solid.moving_count} moving solid particles "
                f"have fewer than three particle layers in some direction within their kernel and use the linear fit "
                f"(first order) instead; a finer numerics.spacing (now {self.spacing:g} m) gives the quadratic fit "
                f"three layers")

    def _warn_about_solid_settings(self):
        """The warnings that follow live changes of the solid's settings (solid/solver.py): the previous ones go."""
        v = self.spec.values
        self._artificial_stress_warning = self._replace_live_warning(self._artificial_stress_warning,
                                                                     artificial_stress_warning(v))
        self._cfl_warning = self._replace_live_warning(self._cfl_warning, cfl_warning(v))

    def _replace_live_warning(self, previous, warning):
        """A warning that follows live changes: the previous one goes, the new one (if any) is added."""
        if previous in self.warnings and previous != warning:
            self.warnings.remove(previous)
        if warning is not None and warning not in self.warnings:
            self.warnings.append(warning)
        return warning

    # ---- settings ------------------------------------------------------------------------------------------
    def check(self, overrides):
        """Validate {key: value} against the schema, the scene and the running state, changing nothing.

        Returns (spec with the live keys applied, keys that wait for the next reset). Raises SceneError.
        """
        pending = {**self._pending, **overrides}
        self.spec.with_overrides(pending)           # the whole set must make a valid scene
        deferred = [k for k in overrides if self.spec.schema.params[k].rebuild]
        live_spec = self.spec.with_overrides({k: v for k, v in overrides.items() if k not in deferred})
        if self.solid is not None:
            self.solid_solver.settings_for(live_spec.values)
        if self.fluid is not None:
            self._fluid_settings(live_spec)
        return live_spec, deferred

    def apply(self, overrides):
        """Apply {key: value}: live keys take effect now; keys that need a rebuild wait for reset().

        Returns the keys deferred to the next reset; earlier deferred changes are kept. Raises SceneError
        (state unchanged) on a bad value.
        """
        live_spec, deferred = self.check(overrides)
        self._pending.update({k: overrides[k] for k in deferred})
        self.spec = live_spec
        if self.solid is not None:
            self.solid_solver.configure(self.spec.values)
            self._warn_about_solid_settings()
        if self.fluid is not None:
            self._apply_fluid_settings()
        if self.coupling is not None:
            v = self.spec.values
            self.coupling.configure(v["coupling.model"], v["coupling.gamma"], v["coupling.substeps"],
                                    v["coupling.relaxation"])
        return deferred

    @property
    def pending(self):
        """Changes accepted but waiting for reset(), {key: value}."""
        return dict(self._pending)

    def reset(self):
        """Rebuild from the current settings (including changes that were waiting for a reset), back to t = 0."""
        if self._pending:
            self.spec = self.spec.with_overrides(self._pending)
            self._pending = {}
        self._build()

    # ---- time stepping ------------------------------------------------------------------------------------
    def _solid_dt(self):
        limit = self.solid_solver.stable_dt()
        forced = self.spec["solid.time_step"]
        if forced > 0.0:
            if forced > limit:
                self.warnings.append(f"t = {self.time:.6g} s: solid.time_step {forced:g} s exceeds the stable "
                                     f"limit {limit:.4g} s now; clamped to the limit")
                return limit
            return forced
        return limit

    def outer_step_duration(self):
        return self.spec["output.timeseries_interval"]

    def step(self):
        """Advance one outer step; raises Diverged (state left as found at the check) if the watchdog trips."""
        duration = self.outer_step_duration()
        if self.solid is not None and self.coupling is None:   # coupled: sub-stepped inside each fluid step
            self.watchdog.solid_speed_before_substeps()
            dt_max = self._solid_dt()
            n = max(1, math.ceil(duration / dt_max * (1.0 - 1e-12)))
            dt = duration / n
            self._advance_solid(n, dt, self._prescribed_acceleration(self.time + 0.5 * duration))
        if self.fluid is not None:
            self._advance_fluid(duration)
        self._relax(duration)
        self.time += duration
        self.outer_steps += 1
        if self.fluid is not None and self.domain_lo is not None:
            self._hold_lost_fluid()
        self.watchdog.check()
        self._probe_readings = self.probe_set.read(self)

    def _hold_lost_fluid(self):
        """Water that left the domain box (a splash over a wall, falling outside the tank) is held still on the
        box's face where it left, as DualSPHysics excludes its "out" particles: alone there, it has no neighbours
        and carries no pressure, and the run goes on; lost_water records them. The watchdog stops the run only if
        the scene sets watchdog.max_fluid_lost below 1."""
        f = self.fluid
        out = ((f.pos < self.domain_lo) | (f.pos > self.domain_hi)).any(axis=1) & ~self.fluid_lost
        new = np.flatnonzero(out)
        if len(new):
            self._fluid_lost_at[new] = np.clip(f.pos[new], self.domain_lo, self.domain_hi)
            self.fluid_lost[new] = True
            self.lost_water.record(new, self.time, f.pos[new], self.warnings)
        if self.fluid_lost.any():
            lost = self.fluid_lost
            f.pos[lost] = self._fluid_lost_at[lost]
            f.vel[lost] = 0.0

    def _prescribed_acceleration(self, t):
        """The scene's prescribed load on the solid at time t, as an acceleration per particle, ramped in as
        (1 - cos(pi t / T)) / 2 over the ramp time T; none (NO_EXTERNAL) in scenes without one. Held over an
        outer step."""
        if self.solid_load is None:
            return NO_EXTERNAL
        ramp = 1.0
        if t < self.load_ramp_time:
            ramp = 0.5 * (1.0 - math.cos(math.pi * t / self.load_ramp_time))
        return ramp * self.solid_load / self.solid.mass[:, None]

    def _relax(self, duration):
        """The static cases' relaxation (Built.damping_rate, Built.fluid_damping_rate; 0 elsewhere, costing
        nothing): dv/dt = -c v over the outer step just taken, taken exactly (v *= exp(-c duration)), for the solid
        and for the water (the solid's on the velocity its particles have: SolidSolver.relax). It settles a
        statically loaded case; its rest state does not depend on c."""
        if self.damping_rate > 0.0:
            self.solid_solver.relax(math.exp(-self.damping_rate * duration))
        if self.fluid_damping_rate > 0.0:
            self.fluid.vel *= math.exp(-self.fluid_damping_rate * duration)

    def _advance_solid(self, n, dt, ext_acc=NO_EXTERNAL):
        """`n` solid steps of `dt` (SolidSolver.advance), counted and timed."""
        solver = self.solid_solver
        start = _time.perf_counter()
        capped_first = solver.advance(n, dt, ext_acc)
        self.solid_seconds += _time.perf_counter() - start
        if capped_first:    # once per run; summary.json counts them all
            prm = solver.params
            self.warnings.append(f"t = {self.time:.6g} s: a solid step reached solid.pressure_max_iterations = "
                                 f"{prm.pressure_max_iterations} with its residual above "
                                 f"solid.pressure_tolerance = {prm.pressure_tolerance:g} (summary.json "
                                 f"solid_pressure_solve.capped_steps counts them)")
        self.last_solid_dt, self.last_substeps = dt, n
        self.solid_steps += n

    def _advance_coupled_solid(self, fluid_dt):
        """Satake et al. sec. 2.3: the fluid's push from the step just taken, held over the solid's sub-steps."""
        ext = self.coupling.push(fluid_dt)
        self.watchdog.solid_speed_before_substeps()
        n, warning = self.coupling.substeps(fluid_dt, self.solid_solver.stable_dt())
        if warning:
            self.warnings.append(f"t = {self.time:.6g} s: {warning}")
        self._advance_solid(n, fluid_dt / n, ext)

    def stable_fluid_dt(self):
        """The fluid's stable step (fluid.solver.FluidSolver.stable_dt)."""
        return self.fluid_solver.stable_dt(self.spec["fluid.cfl"])

    def _fluid_dt(self, at_time):
        limit = self.stable_fluid_dt()
        forced = self.spec["fluid.time_step"]
        if forced > 0.0:
            if forced > limit:
                if not self._fluid_dt_clamped:
                    self.warnings.append(f"t = {at_time:.6g} s: fluid.time_step {forced:g} s exceeds the stable "
                                         f"limit {limit:.4g} s now; clamped to the limit while it does")
                self._fluid_dt_clamped = True
                return limit
            self._fluid_dt_clamped = False
            return forced
        return limit

    def _lift_gate(self, t):
        """The scene's gate lifted from t = 0 (Built.release_velocity, e.g. Lobovsky et al.'s 4.53 m/s): its wall
        particles where they are at the end of the step about to be taken, until they have travelled
        Built.release_travel (then they stay there, clear of the water). The lists are remade when it has moved
        half a skin (they compare wall positions to the bit)."""
        offset, start, velocity, travel = self._lift
        speed = float(np.sqrt(velocity @ velocity))
        moved = min(t * speed, travel)
        walls = self.fluid_solver.wall_pos
        walls[offset:offset + len(start)] = start + velocity * (moved / speed)
        if self.coupling is None and self.fluid_solver.wall_neighbours.is_stale(self.fluid.pos, walls):
            self.fluid_solver.rebuild()
        if moved >= travel:
            self._lift = None

    def _advance_fluid(self, duration):
        """Whole fluid steps covering `duration`; per-interval statistics for sample()."""
        solver = self.fluid_solver
        done, steps, iterations, most, capped = 0.0, 0, 0, 0, 0
        worst_max, worst_mean = 0.0, 0.0
        push = np.zeros(3)
        while duration - done > 1e-12 * duration:
            remaining = duration - done
            dt_max = self._fluid_dt(self.time + done)
            n = max(1, math.ceil(remaining / dt_max * (1.0 - 1e-12)))
            dt = remaining / n
            if dt < self.spec["fluid.min_time_step"]:
                self.watchdog.fluid_step_collapsed(dt)
            if self._lift is not None:
                self._lift_gate(self.time + done + dt)
            if self.coupling is not None:
                self.coupling.before_fluid_step(solver)
            report = solver.step(dt)
            if self.coupling is not None:
                self._advance_coupled_solid(dt)
                push += dt * (self.solid.mass @ self.coupling.acc)
            if self.probe_set.averaged():
                self.probe_set.after_fluid_step(self, dt)
            done += dt
            steps += 1
            iterations += report.iterations
            most = max(most, report.iterations)
            worst_max = max(worst_max, report.error_max)
            worst_mean = max(worst_mean, report.error_mean)
            self.last_fluid_dt = dt
            self.last_density_iterations = report.iterations
            self.last_density_error, self.last_density_error_mean = report.error_max, report.error_mean
            if report.capped:
                capped += 1
        self.fluid_steps += steps
        self.fluid_iterations += iterations
        self.last_fluid_substeps = steps
        if capped:
            self.fluid_capped_steps += capped
            self.warnings.append(
                f"t = {self.time:.6g} .. {self.time + duration:.6g} s: {capped} of {steps} fluid step(s) reached "
                f"fluid.max_iterations = {self.spec['fluid.max_iterations']} with max compression "
                f"{100 * worst_max:.3g} % (tolerance {100 * self.spec['fluid.density_tolerance']:g} % on the "
                f"{self.spec['fluid.tolerance_on']})")
        self._interval_stats = {"iterations_mean": iterations / steps, "iterations_max": most,
                                "density_error_max": worst_max, "density_error_mean": worst_mean,
                                "capped_steps": capped}
        # each fluid step's push held over its sub-steps, averaged over the outer step: the last step's alone
        # misread the load where steps alternate (Antoci's gate at rest at a 0.5 ms fluid step: a third of the
        # steps need no correction and push nothing, and the samples read 17 % short)
        self._interval_push = push / done

    # ---- read-only views ----------------------------------------------------------------------------------
    def pressure_solve_stats(self):
        """The implicit pressure's solves so far (solid.pressure = implicit): steps, iterations per step, the most in
        one step, steps that hit solid.pressure_max_iterations; None without it."""
        return None if self.solid is None else self.solid_solver.pressure_solve_stats()

    @property
    def neighbour_builds(self):
        """The solid's neighbour-list builds so far (the fluid's: fluid_solver.builds)."""
        return self.solid_solver.neighbour_builds if self.solid_solver is not None else 0

    def initial_positions(self, phase):
        """(N, 3) m, where the particles of `phase` ('solid' or 'fluid') were at t = 0."""
        return self.solid_solver.initial_positions if phase == "solid" else self.fluid_initial_positions

    @property
    def phases(self):
        return self.spec.phases

    @property
    def particle_count(self):
        """All particles of the scene: solid (clamp included), fluid and wall."""
        return sum(state.count for state in (self.solid, self.fluid, self.walls) if state is not None)

    @property
    def particle_counts(self):
        """{phase: count} for the phases the scene has (solid_moving: the solid without its clamp)."""
        out = {}
        if self.solid is not None:
            out["solid"], out["solid_moving"] = self.solid.count, self.solid.moving_count
        if self.fluid is not None:
            out["fluid"] = self.fluid.count
        if self.walls is not None:
            out["walls"] = self.walls.count
        return out

    def solid_velocity(self):
        """The solid particles' velocity at the end of the step, (N, 3) m/s, as every output reports it
        (SolidSolver.velocity: with the implicit pressure v + u/2; else the stored array, to read, not write)."""
        return self.solid_solver.velocity()

    def energies(self):
        """{'kinetic_energy', 'strain_energy'} in J for the phases the scene has (the solid's kinetic energy from
        solid_velocity)."""
        out = {}
        if self.solid is not None:
            s = self.solid
            out["kinetic_energy"] = kinetic_energy(s.mass, self.solid_velocity(), s.movable)
            out["strain_energy"] = self.solid_solver.strain_energy()
        if self.fluid is not None:
            f = self.fluid
            out["fluid_kinetic_energy"] = float(0.5 * (f.mass * (f.vel ** 2).sum(axis=1)).sum())
        return out

    def probe_readings(self):
        """{probe: (kind, {quantity: value})} at the end of the last outer step (probes.py), in the scene's order;
        the pressure and force probes' values are their means over that step."""
        return self._probe_readings

    def probe_displacements(self):
        """{probe: (dx, dy, dz) m} of the probes that follow particles (the built-in scenes' groups, point probes)."""
        return {name: values["displacement"] for name, (kind, values) in self._probe_readings.items()
                if "displacement" in values}

    def gate_standing(self):
        """Whether the scene's gate (Built.release_walls) is among the fluid's wall particles after t = 0, after the
        scene's walls: a lifted gate (one released at once is gone)."""
        return self._gate_in_walls

    def filling_particles(self):
        """(water positions, water volumes m / rho, wall positions, wall volumes m / rho0): what fills the kernel of
        a water-height probe (probes.py); the walls as the fluid sees them (a gate while it stands, the solid in a
        coupled scene)."""
        f, solver = self.fluid, self.fluid_solver
        return f.pos, f.mass / f.rho, solver.wall_pos, solver.wall_mass / self.spec["fluid.density"]

    def sample(self):
        """One time-series row: time, probes (probes.py), energies, step sizes, scene extras."""
        row = {"time": self.time}
        for name, (kind, values) in self._probe_readings.items():
            row.update(probe_columns(kind, name, values))
        row.update(self.energies())
        if self.solid is not None:
            row["solid_dt"] = self.last_solid_dt
            row["solid_substeps"] = self.last_substeps
            if hasattr(self.builder, "sample"):
                row.update(self.builder.sample(self.solid, self.probes, self.solid_velocity()))
        if self.fluid is not None:
            stats = self._interval_stats or {"iterations_mean": 0.0, "iterations_max": 0,
                                             "density_error_max": self.last_density_error,
                                             "density_error_mean": self.last_density_error_mean, "capped_steps": 0}
            row["fluid_dt"] = self.last_fluid_dt
            row["fluid_substeps"] = self.last_fluid_substeps
            row.update(stats)
            if hasattr(self.builder, "sample_fluid"):
                row.update(self.builder.sample_fluid(self))
        if self.coupling is not None:
            row["coupling_force_x"], row["coupling_force_y"], row["coupling_force_z"] = (
                float(x) for x in self._interval_push)
        return row
