"""The one time loop. `Simulation` builds a scene's phases and advances them; everything else only reads state.

A scene has some of three phases, each with its own solver and the same verbs (configure, stable step, advance,
relax, sample): the solid (solid/phase.py), the water (fluid/phase.py) and, with both, the coupling between them
(coupling/solver.py). The water's walls are one boundary.Boundary: the scene's walls, its gates while they stand, and
the solid in a coupled scene. Phases a scene does not have are None and cost nothing.

`step()` advances one outer step, one time-series interval (Satake et al. sec. 2):
- the solid alone takes it as whole solid steps no larger than its stable step;
- the water takes it as whole fluid steps, each no larger than its stable step, the last ones shortened evenly so
  the interval ends on a step; before each, the walls that move (a lifted gate, the solid) are put in place; in a
  coupled scene the solid then takes the sub-steps of that fluid step, the water's push held over them (sec. 2.3);
then the static cases' relaxation, the water that left the domain held still, the watchdog's checks (a run that goes
wrong stops within one outer step with a diagnosis, and nothing non-finite leaves the simulator) and the probes.
"""
from .boundary import Boundary
from .coupling.solver import Coupling
from .diagnostics import Diverged, Watchdog
from .fluid.lost_water import LostWater
from .fluid.phase import FluidPhase
from .jit_cache import start_parallel_runtime
from .numerics.kernels import lattice_density_scale, water_kernel
from .probes import ProbeSet, probe_columns
from .scene import SceneSpec
from .schema import solid_smoothing_ratio
from .scenes import build_scene, interface
from .solid.phase import SolidPhase

__all__ = ["Simulation", "Diverged"]


class Simulation:
    """A scene's particles and the loop that advances them. Construct from a validated SceneSpec."""

    def __init__(self, spec: SceneSpec):
        self.spec = spec
        self.builder = interface(spec.builder, spec.values)
        self._pending = {}
        start_parallel_runtime()
        self._build()

    # ---- checkpoints (checkpoint.py): everything but the builder module, which is named -------------------
    def __getstate__(self):
        return {**self.__dict__, "builder": self.spec.builder}

    def __setstate__(self, state):
        self.__dict__.update(state)
        self.builder = interface(state["builder"], self.spec.values)
        start_parallel_runtime()     # a restored run's first kernel is a cached caller of parallel ones

    # ---- construction -------------------------------------------------------------------------------------
    def _build(self):
        """The scene's particles and phases at t = 0: the solid's list, fit and forces, the water settled if the
        scene asks (fluid.settle_time), the coupling, the boundary, the watchdog and the first probe readings."""
        v = self.spec.values
        # unreached_clamp: the mirrored clamp's particles left out (scenes/built.without_unreached_clamp)
        built, self.unreached_clamp = build_scene(self.spec.builder, v)
        self.spacing = v["numerics.spacing"]
        self.h = v["numerics.smoothing_ratio"] * self.spacing      # the water's and the walls'
        self.solid_h = solid_smoothing_ratio(v) * self.spacing     # the solid's own (solid.smoothing_ratio)
        self.fluid_kernel = water_kernel(v)   # numerics/kernels.py's id of the water's kernel (fluid.kernel)
        self.solid, self.fluid, self.walls = built.solid, built.fluid, built.walls
        self.domain_lo, self.domain_hi, self.period = built.domain_lo, built.domain_hi, built.period
        self.probes = built.probes
        self.probe_set = ProbeSet(built.probes)
        self.time = 0.0
        self.outer_steps = 0
        self.warnings = list(built.warnings)     # what the run should be told, and what it is told for the record
        self.notes = list(built.notes)
        self.solid_phase = self.fluid_phase = self.coupling = self.boundary = None
        if self.solid is not None:
            self.solid_phase = SolidPhase(self.solid, built, v, self.solid_h, self.warnings)
            self.solid_phase.start()
        if self.fluid is not None:
            self._start_water(built, v)
        self.watchdog = Watchdog(self, built.domain_lo, built.domain_hi)
        self._probe_readings = self.probe_set.read(self)

    def _start_water(self, built, v):
        """The water's phase against its boundary; settled at rest first if the scene asks, its gates holding it,
        then released: gone at once, or (a lifted gate) moving from t = 0."""
        if self.solid is not None:
            self.coupling = Coupling(self.solid, self.fluid, self.h, self.period, v["fluid.density"],
                                     lattice_density_scale(v["numerics.smoothing_ratio"], water_kernel(v)),
                                     kernel=water_kernel(v), model=v["coupling.model"],
                                     gamma=v["coupling.gamma"], substeps=v["coupling.substeps"],
                                     relaxation=v["coupling.relaxation"],
                                     surface_threshold=v["coupling.surface_threshold"],
                                     skin=v["numerics.neighbour_skin"] * self.h, box_lo=built.domain_lo,
                                     box_hi=built.domain_hi, solid_h=self.solid_h, ramp=v["coupling.push_ramp"])
        settle_time = v["fluid.settle_time"]
        lifted = built.release_walls is not None and built.release_velocity is not None
        self.boundary = Boundary.of(built, v["fluid.density"], gates=settle_time > 0.0 or lifted, solid=self.solid,
                                    solid_mass=self.coupling.wall_mass if self.coupling is not None else None)
        self.fluid_phase = FluidPhase(self.fluid, self.boundary, v, self.h, self.period, built.domain_lo,
                                      built.domain_hi, self.warnings, LostWater(self.fluid.count, built),
                                      built.fluid_damping_rate)
        if settle_time > 0.0:
            self.fluid_phase.settle(settle_time, self.boundary.follow_solid)
            if not lifted:                 # the release: the gates are gone, the water's lists made anew
                self.boundary = self.boundary.without_gates()
                self.fluid_phase.start(self.boundary)
        # after the settling, which ends at rest: a wave's field is laid on the water where it settled
        for rows, field in built.fluid_start:
            self.fluid.vel[rows] += field.velocity(self.fluid.pos[rows])

    # ---- settings ------------------------------------------------------------------------------------------
    def check(self, overrides):
        """Validate {key: value} against the schema, the scene and the running state, changing nothing.

        Returns (spec with the live keys applied, keys that wait for the next reset). Raises SceneError.
        """
        pending = {**self._pending, **overrides}
        self.spec.with_overrides(pending)           # the whole set must make a valid scene
        deferred = [k for k in overrides if self.spec.schema.params[k].rebuild]
        live_spec = self.spec.with_overrides({k: v for k, v in overrides.items() if k not in deferred})
        for phase in (self.solid_phase, self.fluid_phase):
            if phase is not None:
                phase.settings_for(live_spec.values)
        return live_spec, deferred

    def apply(self, overrides):
        """Apply {key: value}: live keys take effect now; keys that need a rebuild wait for reset().

        Returns the keys deferred to the next reset; earlier deferred changes are kept. Raises SceneError
        (state unchanged) on a bad value.
        """
        live_spec, deferred = self.check(overrides)
        self._pending.update({k: overrides[k] for k in deferred})
        self.spec = v = live_spec
        for phase in (self.solid_phase, self.fluid_phase):
            if phase is not None:
                phase.configure(v.values)
        if self.coupling is not None:
            self.coupling.configure(v["coupling.model"], v["coupling.gamma"], v["coupling.substeps"],
                                    v["coupling.relaxation"], v["coupling.push_ramp"])
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
    def outer_step_duration(self):
        return self.spec["output.timeseries_interval"]

    def step(self):
        """Advance one outer step; raises Diverged (state left as found at the check) if the watchdog trips."""
        duration = self.outer_step_duration()
        if self.solid_phase is not None and self.coupling is None:   # coupled: sub-stepped inside each fluid step
            self.solid_phase.advance(duration, self.time, self.watchdog)
        if self.fluid_phase is not None:
            self._advance_water(duration)
        for phase in (self.solid_phase, self.fluid_phase):
            if phase is not None:
                phase.relax(duration)
        self.time += duration
        self.outer_steps += 1
        if self.fluid_phase is not None and self.domain_lo is not None:
            self.fluid_phase.hold_lost(self.time, self.domain_lo, self.domain_hi)
        self.watchdog.check()
        self._probe_readings = self.probe_set.read(self)

    def _advance_water(self, duration):
        """The fluid steps of an outer step; in a coupled scene the solid's sub-steps inside each, under the push of
        the fluid step just taken (Satake et al. sec. 2.3)."""
        water, coupling = self.fluid_phase, self.coupling
        for t, dt in water.steps_over(duration, self.time, self.watchdog):
            if self.boundary.commands:
                self.boundary.apply_commands(t)
            water.refresh_walls(self.boundary.move_parts(t + dt) | self.boundary.follow_solid())
            water.step(dt)
            if coupling is not None:
                push = coupling.push(dt)
                self.solid_phase.advance_coupled(push, dt, coupling.substeps, self.time, self.watchdog,
                                                 coupling.ramp_start())
            if self.probe_set.averaged():
                self.probe_set.after_fluid_step(self, dt)
        if coupling is not None:
            coupling.end_interval()

    # ---- read-only views ----------------------------------------------------------------------------------
    def initial_positions(self, phase):
        """(N, 3) m, where the particles of `phase` ('solid' or 'fluid') were at t = 0."""
        return (self.solid_phase.solver.initial_positions if phase == "solid"
                else self.fluid_phase.initial_positions)

    @property
    def phases(self):
        return self.spec.phases

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

    @property
    def particle_count(self):
        """All particles of the scene: solid (clamp included), fluid and wall."""
        return sum(state.count for state in (self.solid, self.fluid, self.walls) if state is not None)

    def solid_velocity(self):
        """The solid particles' velocity at the end of the step, (N, 3) m/s, as every output reports it
        (solid/solver.SolidSolver.velocity: with the implicit pressure v + u/2; else the stored array, to read)."""
        return self.solid_phase.solver.velocity()

    def energies(self):
        """{'kinetic_energy', 'strain_energy', 'fluid_kinetic_energy'} in J for the phases the scene has."""
        out = self.solid_phase.energies() if self.solid_phase is not None else {}
        if self.fluid_phase is not None:
            out["fluid_kinetic_energy"] = self.fluid_phase.kinetic_energy()
        return out

    def probe_readings(self):
        """{probe: (kind, {quantity: value})} at the end of the last outer step (probes.py), in the scene's order;
        the pressure and force probes' values are their means over that step."""
        return self._probe_readings

    def probe_displacements(self):
        """{probe: (dx, dy, dz) m} of the probes that follow particles (the built-in scenes' groups, point probes)."""
        return {name: values["displacement"] for name, (kind, values) in self._probe_readings.items()
                if "displacement" in values}

    def sample(self):
        """One time-series row: time, probes (probes.py), energies, the phases' steps and statistics, the scene's
        own columns (a builder's sample and sample_fluid), the water's push on the solid."""
        row = {"time": self.time}
        for name, (kind, values) in self._probe_readings.items():
            row.update(probe_columns(kind, name, values))
        row.update(self.energies())
        if self.solid_phase is not None:
            row.update(self.solid_phase.sample())
            if self.builder.sample is not None:
                row.update(self.builder.sample(self.solid, self.probes, self.solid_velocity()))
        if self.fluid_phase is not None:
            row.update(self.fluid_phase.sample())
            if self.builder.sample_fluid is not None:
                row.update(self.builder.sample_fluid(self))
        if self.coupling is not None:
            row["coupling_force_x"], row["coupling_force_y"], row["coupling_force_z"] = (
                float(x) for x in self.coupling.mean_push)
        return row
