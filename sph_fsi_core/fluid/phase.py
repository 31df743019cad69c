"""The water as a phase of the time loop (simulation.py): its solver (fluid/solver.py) and what its steps need
around them: the start at rest (settling before t = 0), the step's size, the water that leaves the domain, the
relaxation of a static case, and the statistics the outputs report.

Its verbs, as the solid's phase has them (solid/phase.py): `configure` (settings, live changes), `stable_dt`,
`steps_over` (the steps covering an outer step), `step`, `relax`, `sample` (the time series' columns).
"""
import math
import time as _time

import numpy as np

from ..errors import SceneError
from ..numerics.kernels import KERNELS
from .energy import mechanical_energy
from .solver import FluidSolver

# the settling phase's velocity relaxation, rate = SETTLE_RELAXATION / fluid.settle_time: a velocity's memory falls
# to e^-10 over the phase, and the column still sinks into its compression (at g / rate, 0.1 m/s for 0.1 s)
SETTLE_RELAXATION = 10.0
# and its step, in units of h / c_b (settle): about 2 correction iterations per step at 2
SETTLE_STEP_IN_H = 2.0


class FluidPhase:
    """The water (state.FluidState, advanced in place) against the walls of `boundary` (boundary.Boundary).

    `warnings`: the run's list, which the phase appends to; `lost_water`: the record of the water that leaves the
    domain (fluid/lost_water.py); `damping_rate` (1/s): a static case's relaxation of the water's velocities
    (Built.fluid_damping_rate; 0 elsewhere, costing nothing)."""

    def __init__(self, fluid, boundary, values, h, period, box_lo, box_hi, warnings, lost_water, damping_rate=0.0):
        self.fluid = fluid
        self.h = float(h)
        self.period, self.box_lo, self.box_hi = period, box_lo, box_hi
        self.values = values
        self.warnings = warnings
        self.damping_rate = damping_rate
        self.steps = 0
        self.iterations = 0            # correction iterations, all steps
        self.capped_steps = 0          # steps that reached fluid.max_iterations
        self.last_dt = 0.0
        self.last_substeps = 0         # fluid steps in the last outer step
        self.last_iterations = 0       # of the last fluid step
        self.last_error_max = 0.0      # max compression after the last fluid step
        self.last_error_mean = 0.0
        self.interval = {}             # the last outer step's statistics (steps_over)
        self.settled = None            # what the settling phase did (fluid.settle_time > 0), for the summary
        self._dt_clamped = False
        self.lost = np.zeros(fluid.count, dtype=np.bool_)   # left the domain: held still (hold_lost)
        self.lost_water = lost_water
        self._lost_at = np.zeros((fluid.count, 3))
        self.initial_positions = fluid.pos.copy()
        self.solver = None
        self.start(boundary)
        self._start_budget()

    def _start_budget(self):
        """The energy budget's zero (the clock's start): the potential energy now, and no losses yet."""
        self.correction_loss = 0.0     # J, the mechanical energy the steps' corrections took since t = 0
        self.viscous_loss = 0.0        # J, the viscous term's
        self.shifting_loss = 0.0       # J, the shift's (fluid.shifting)
        self.potential_at_start = self.energies()[1]

    def energies(self):
        """(kinetic, potential) mechanical energy of the water, J (fluid/energy.py; the potential zero at the
        origin)."""
        g = self.values["scene.gravity"]
        return mechanical_energy(self.fluid.pos, self.fluid.vel, self.fluid.mass, g[0], g[1], g[2])

    def start(self, boundary):
        """The solver over the walls of `boundary` (made anew: its lists, its work arrays), configured, and the
        density (1) at the current positions."""
        self.boundary = boundary
        walls = boundary if boundary.count else None
        self.solver = FluidSolver(self.fluid, walls, self.h, self.period, self.box_lo, self.box_hi,
                                  self.values["numerics.neighbour_skin"] * self.h, KERNELS[self.values["fluid.kernel"]])
        self.configure(self.values)
        self.last_error_max, self.last_error_mean = self.solver.density()

    # ---- settings ------------------------------------------------------------------------------------------
    def settings_for(self, values):
        """The solver's settings from `values`; SceneError if a forced fluid.time_step is above the stable limit."""
        v = values
        settings = dict(rho0=v["fluid.density"], nu=v["fluid.viscosity"], gravity=v["scene.gravity"],
                        tolerance=v["fluid.density_tolerance"], tolerance_on=v["fluid.tolerance_on"],
                        coefficient=v["fluid.correction_coefficient"], kappa=v["fluid.correction_kappa"],
                        min_iterations=v["fluid.min_iterations"], max_iterations=v["fluid.max_iterations"],
                        partial=v["fluid.partial_iteration"], shifting=v["fluid.shifting"],
                        shifting_speed=v["fluid.shifting_speed"], spacing=v["numerics.spacing"])
        forced = v["fluid.time_step"]
        if forced > 0.0:
            limit = min(self.solver.stable_dt(v["fluid.cfl"], nu=settings["nu"], gravity=settings["gravity"]),
                        self._wall_limit(v["fluid.cfl"]))
            if forced > limit:
                raise SceneError(f"fluid.time_step = {forced:g} s: above the stable limit {limit:.4g} s "
                                 f"(min of fluid.cfl * h / |v|max, fluid.cfl * sqrt(h / |g|), 0.125 h^2 / nu, "
                                 f"fluid.cfl * h / the moving walls' speed); "
                                 f"allowed: (0, {limit:.4g}] s, or 0 for automatic")
        return settings

    def configure(self, values):
        """Apply `values`' settings (a live change takes effect at the next step)."""
        self.solver.configure(**self.settings_for(values))
        self.values = values

    # ---- the step's size -----------------------------------------------------------------------------------
    def stable_dt(self):
        """The solver's stable step at fluid.cfl (fluid.solver.FluidSolver.stable_dt), and no longer than a moving
        wall takes to cross fluid.cfl h (_wall_limit)."""
        cfl = self.values["fluid.cfl"]
        return min(self.solver.stable_dt(cfl), self._wall_limit(cfl))

    def _wall_limit(self, cfl):
        """cfl h / the moving walls' speed bound (boundary.Boundary.wall_speed; inf where none moves): a wall moves
        no further into the water in a step than the water moves itself, so the correction pushes it out as it does
        the water's own compression. The bound holds over the whole run (a commanded wall's is its max_speed), so
        the step does not follow the wall's speed from step to step."""
        speed = self.boundary.wall_speed
        return cfl * self.h / speed if speed > 0.0 else math.inf

    def _dt_limit(self, at_time):
        """The largest step now: the stable one, or the forced fluid.time_step while it is below it."""
        limit = self.stable_dt()
        forced = self.values["fluid.time_step"]
        if forced <= 0.0:
            return limit
        if forced > limit:
            if not self._dt_clamped:
                self.warnings.append(f"t = {at_time:.6g} s: fluid.time_step {forced:g} s exceeds the stable "
                                     f"limit {limit:.4g} s now; clamped to the limit while it does")
            self._dt_clamped = True
            return limit
        self._dt_clamped = False
        return forced

    def steps_over(self, duration, start, watchdog):
        """The fluid steps covering an outer step of `duration` from time `start`, as (t, dt) of each: whole steps,
        each no larger than the limit (_dt_limit, taken anew before each), the last ones shortened evenly so the
        interval ends on a step. A step below fluid.min_time_step trips the watchdog. Once they are all taken,
        the interval's statistics (`interval`, sample()) and the capped steps' warning."""
        done = 0.0
        first_step, first_iterations = self.steps, self.iterations
        self._worst = [0, 0.0, 0.0, 0]      # the most iterations, max and mean errors, capped steps
        while duration - done > 1e-12 * duration:
            remaining = duration - done
            dt_max = self._dt_limit(start + done)
            n = max(1, math.ceil(remaining / dt_max * (1.0 - 1e-12)))
            dt = remaining / n
            if dt < self.values["fluid.min_time_step"]:
                watchdog.fluid_step_collapsed(dt)
            yield start + done, dt
            done += dt
        steps, iterations = self.steps - first_step, self.iterations - first_iterations
        most, worst_max, worst_mean, capped = self._worst
        self.last_substeps = steps
        if capped:
            v = self.values
            self.warnings.append(
                f"t = {start:.6g} .. {start + duration:.6g} s: {capped} of {steps} fluid step(s) reached "
                f"fluid.max_iterations = {v['fluid.max_iterations']} with max compression {100 * worst_max:.3g} % "
                f"(tolerance {100 * v['fluid.density_tolerance']:g} % on the {v['fluid.tolerance_on']})")
        self.interval = {"iterations_mean": iterations / steps, "iterations_max": most,
                         "density_error_max": worst_max, "density_error_mean": worst_mean, "capped_steps": capped}

    # ---- steps ---------------------------------------------------------------------------------------------
    def refresh_walls(self, moved):
        """After the walls' rows moved (a lifted gate, the solid followed): new lists if their skin is used up."""
        if moved:
            self.solver.refresh_wall_lists()

    def step(self, dt):
        """One fluid step of `dt` (fluid.solver.FluidSolver.step), counted."""
        report = self.solver.step(dt)
        self.steps += 1
        self.iterations += report.iterations
        self.last_dt, self.last_iterations = dt, report.iterations
        self.last_error_max, self.last_error_mean = report.error_max, report.error_mean
        worst = self._worst
        worst[0] = max(worst[0], report.iterations)
        worst[1] = max(worst[1], report.error_max)
        worst[2] = max(worst[2], report.error_mean)
        if report.capped:
            worst[3] += 1
            self.capped_steps += 1
        self.correction_loss += report.correction_loss
        self.viscous_loss += report.viscous_loss
        self.shifting_loss += report.shifting_loss
        return report

    def settle(self, duration, follow_solid):
        """The water's start at rest under gravity (fluid.settle_time; METHOD sec. 2's steps, before t = 0).

        A column built on the lattice has no compression and so no pressure: released at once it falls freely
        until it is compressed to the density tolerance, and its load on walls and solid overshoots for tens of
        milliseconds (docs/method.md, fluid, "The start"). An experiment's water at rest is already at hydrostatic
        pressure. So before t = 0 the fluid steps alone for `duration` (the solid held where it was built, the
        scene's gates in place; `follow_solid`: boundary.Boundary.follow_solid, the solid's rows put where it is
        before each step), its velocity relaxed as dv/dt = -c v with c = SETTLE_RELAXATION / duration; then
        velocities are set to zero and the clock starts. Records what the phase did in `settled`."""
        solver = self.solver
        rate = SETTLE_RELAXATION / duration
        # The correction's work per step grows as dt^2 and the steps as 1 / dt (docs/method.md, fluid, "Time
        # step"): at rest the total falls with dt down to a few iterations per step, at dt ~ h / c_b with c_b =
        # sqrt(|g| H / tolerance) the column's breathing speed (scenes/tank.py). The phase steps there.
        spacing = self.values["numerics.spacing"]
        height = float(np.ptp(self.fluid.pos[:, 2])) + spacing if self.fluid.count else 0.0
        gravity = float(np.sqrt(np.dot(self.values["scene.gravity"], self.values["scene.gravity"])))
        breathing = math.sqrt(gravity * height / self.values["fluid.density_tolerance"])
        step_limit = SETTLE_STEP_IN_H * self.h / breathing if breathing > 0.0 else math.inf
        wall0 = _time.perf_counter()
        done, steps, iterations, capped = 0.0, 0, 0, 0
        while duration - done > 1e-12 * duration:
            remaining = duration - done
            dt_max = min(self._dt_limit(-remaining), step_limit)
            n = max(1, math.ceil(remaining / dt_max * (1.0 - 1e-12)))
            dt = remaining / n
            self.refresh_walls(follow_solid())
            report = solver.step(dt)
            self.fluid.vel *= math.exp(-rate * dt)
            done += dt
            steps += 1
            iterations += report.iterations
            capped += int(report.capped)
        speed = float(np.sqrt((self.fluid.vel ** 2).sum(axis=1).max())) if self.fluid.count else 0.0
        self.fluid.vel[:] = 0.0
        self.initial_positions = self.fluid.pos.copy()     # where the water is when the clock starts
        self._start_budget()
        if capped:
            self.warnings.append(f"settling before t = 0: {capped} of {steps} fluid step(s) reached "
                                 f"fluid.max_iterations = {self.values['fluid.max_iterations']}")
        self.settled = {"settle_time_s": duration, "fluid_steps": steps,
                        "iterations_mean": iterations / max(steps, 1), "capped_steps": capped,
                        "relaxation_rate_per_s": rate, "residual_max_speed_m_s": speed,
                        "density_error_max": float(report.error_max), "density_error_mean": float(report.error_mean),
                        "wall_time_s": _time.perf_counter() - wall0}

    def relax(self, duration):
        """The static cases' relaxation over an outer step, dv/dt = -c v taken exactly (none where c = 0)."""
        if self.damping_rate > 0.0:
            self.fluid.vel *= math.exp(-self.damping_rate * duration)

    def hold_lost(self, time, lo, hi):
        """Water that left the domain box [lo, hi] (a splash over a wall, falling outside the tank) is held still on
        the box's face where it left, as DualSPHysics excludes its "out" particles: alone there, it has no
        neighbours and carries no pressure, and the run goes on; `lost_water` records them. The watchdog stops the
        run only if the scene sets watchdog.max_fluid_lost below 1."""
        f = self.fluid
        out = ((f.pos < lo) | (f.pos > hi)).any(axis=1) & ~self.lost
        new = np.flatnonzero(out)
        if len(new):
            self._lost_at[new] = np.clip(f.pos[new], lo, hi)
            self.lost[new] = True
            self.lost_water.record(new, time, f.pos[new], self.warnings)
        if self.lost.any():
            f.pos[self.lost] = self._lost_at[self.lost]
            f.vel[self.lost] = 0.0

    # ---- read-only views -----------------------------------------------------------------------------------
    def wrench(self, rows, point):
        """(force (3,) N, moment (3,) N m about `point`) of the water on the wall rows `rows` (boundary rows), from
        the last step's pressures (fluid.solver.FluidSolver.wall_forces, each row a group of its own)."""
        group = np.full(self.boundary.count, -1, dtype=np.int64)
        group[rows] = np.arange(len(rows))
        forces = self.solver.wall_forces(group, len(rows))
        arms = self.boundary.pos[rows] - point
        return forces.sum(axis=0), np.cross(arms, forces).sum(axis=0)

    def kinetic_energy(self):
        f = self.fluid
        return float(0.5 * (f.mass * (f.vel ** 2).sum(axis=1)).sum())

    def mean_velocity(self):
        """The water's momentum over its mass (m/s, (3,)): what a wall that takes no force along itself keeps."""
        total = float(self.fluid.mass.sum())
        return self.momentum() / total if total > 0.0 else np.zeros(3)

    def momentum(self):
        """The water's momentum (N s, (3,)): what the walls' forces change (an impulse judge's column)."""
        f = self.fluid
        return f.mass @ f.vel

    def filling_particles(self):
        """(water positions, water volumes m / rho, wall positions, wall volumes m / rho0): what fills the kernel of
        a water-height probe (probes.py); the walls as the water sees them (a gate while it stands, the solid in a
        coupled scene)."""
        f, walls = self.fluid, self.boundary
        return f.pos, f.mass / f.rho, walls.pos, walls.mass / self.values["fluid.density"]

    def sample(self):
        """The time series' fluid columns: the step, its count in the last outer step, and that step's
        statistics (before any: the start's density error); and the water's energy budget since t = 0 (J): its
        potential energy's change, and what the corrections and the viscous term took (with the kinetic energy,
        fluid_kinetic_energy, they sum to the kinetic energy at t = 0 but for the water held after leaving the domain
        and a static case's relaxation); its mean velocity (mean_velocity) and its momentum (momentum)."""
        stats = self.interval or {"iterations_mean": 0.0, "iterations_max": 0,
                                  "density_error_max": self.last_error_max,
                                  "density_error_mean": self.last_error_mean, "capped_steps": 0}
        return {"fluid_dt": self.last_dt, "fluid_substeps": self.last_substeps, **stats,
                "fluid_potential_energy": self.energies()[1] - self.potential_at_start,
                "fluid_correction_loss": self.correction_loss, "fluid_viscous_loss": self.viscous_loss,
                **({"fluid_shifting_loss": self.shifting_loss} if self.values["fluid.shifting"] > 0.0 else {}),
                **dict(zip(("fluid_velocity_x", "fluid_velocity_y", "fluid_velocity_z"),
                           (float(u) for u in self.mean_velocity()))),
                **dict(zip(("fluid_momentum_x", "fluid_momentum_y", "fluid_momentum_z"),
                           (float(u) for u in self.momentum())))}
