"""The elastic solid as a phase of the time loop (simulation.py): its solver (solid/solver.py) and what its steps need
around them: the step's size, a scene's prescribed load and the relaxation of a static case, the warnings its
settings call for, and the statistics the outputs report.

Its verbs, as the water's phase has them (fluid/phase.py): `configure` (settings, live changes), `stable_dt`,
`advance` (an outer step alone) or `advance_coupled` (the sub-steps of one fluid step), `relax`, `sample`.
"""
import math
import time as _time

import numpy as np

from ..diagnostics import kinetic_energy
from .solver import NO_EXTERNAL, NO_MIRROR, SolidSolver, artificial_stress_warning, cfl_warning


# the most pieces a ramped push takes over one fluid step (coupling.push_ramp): at 16 the staircase that is left
# steps at 16 times the fluid step's frequency, far above the modes a coupled run resolves
RAMP_PIECES = 16


def ramp_pieces(n, pieces):
    """The sub-step indices that cut `n` sub-steps into min(n, pieces) runs of nearly equal length, first 0, last
    n."""
    return np.rint(np.linspace(0.0, n, min(n, pieces) + 1)).astype(np.int64)


def clamp_mirror(built, clamp):
    """The ghost clamp's mirror map for solid.clamp = mirrored; empty for the fixed clamp, and for free bodies only
    (a clamp that cannot be mirrored is refused by scenes.build_scene)."""
    if clamp == "fixed" or built.clamp_mirror is None:
        return NO_MIRROR
    return np.ascontiguousarray(built.clamp_mirror, dtype=np.int64)


class SolidPhase:
    """The solid (state.SolidState, advanced in place) of a scene as built (scenes/built.Built): its prescribed load
    (`solid_load`, ramped in over `load_ramp_time`) and its relaxation (`damping_rate`), both absent and costing
    nothing in most scenes. `warnings`: the run's list, which the phase appends to."""

    def __init__(self, solid, built, values, h, warnings):
        self.solid = solid
        self.values = values
        self.warnings = warnings
        self.load, self.load_ramp_time = built.solid_load, built.load_ramp_time
        self.damping_rate = built.damping_rate
        spacing = values["numerics.spacing"]
        self.solver = SolidSolver(solid, values, h, spacing, built.period, built.domain_lo, built.domain_hi,
                                  clamp_mirror(built, values["solid.clamp"]))
        self.steps = 0
        self.seconds = 0.0          # wall time inside the solid's steps (summary.json's solid_stepping_time_s)
        self.last_dt = 0.0
        self.last_substeps = 0
        self._live_warnings = {}    # the warnings that follow live changes of the settings

    def start(self):
        """The list, the fit and the forces at the built positions (solid/solver.SolidSolver.start), and the
        warnings the scene's settings call for."""
        self.solver.start()
        linear = self.solver.linear_fit_count()
        if linear:
            self.warnings.append(
                f"solid.velocity_gradient = quadratic: {linear} of {self.solid.moving_count} moving solid particles "
                f"have fewer than three particle layers in some direction within their kernel and use the linear fit "
                f"(first order) instead; a finer numerics.spacing (now {self.values['numerics.spacing']:g} m) gives "
                f"the quadratic fit three layers")
        self._warn_about_settings()

    # ---- settings ------------------------------------------------------------------------------------------
    def settings_for(self, values):
        """Check `values`' settings against the running state without applying them (SceneError)."""
        return self.solver.settings_for(values)

    def configure(self, values):
        """Apply `values`' settings (a live change takes effect at the next step)."""
        self.solver.configure(values)
        self.values = values
        self._warn_about_settings()

    def _warn_about_settings(self):
        """The warnings that follow live changes (solid/solver.py): the previous ones go, the new ones come."""
        for name, warning in (("artificial stress", artificial_stress_warning(self.values)),
                              ("cfl", cfl_warning(self.values))):
            previous = self._live_warnings.get(name)
            if previous in self.warnings and previous != warning:
                self.warnings.remove(previous)
            if warning is not None and warning not in self.warnings:
                self.warnings.append(warning)
            self._live_warnings[name] = warning

    # ---- steps ---------------------------------------------------------------------------------------------
    def stable_dt(self, time):
        """The step alone: the stable one (solid/solver.SolidSolver.stable_dt), or the forced solid.time_step while
        it is below it."""
        limit = self.solver.stable_dt()
        forced = self.values["solid.time_step"]
        if forced > 0.0:
            if forced > limit:
                self.warnings.append(f"t = {time:.6g} s: solid.time_step {forced:g} s exceeds the stable "
                                     f"limit {limit:.4g} s now; clamped to the limit")
                return limit
            return forced
        return limit

    def prescribed_acceleration(self, t):
        """The scene's prescribed load at time t, as an acceleration per particle, ramped in as
        (1 - cos(pi t / T)) / 2 over the ramp time T; none (NO_EXTERNAL) in scenes without one."""
        if self.load is None:
            return NO_EXTERNAL
        ramp = 1.0
        if t < self.load_ramp_time:
            ramp = 0.5 * (1.0 - math.cos(math.pi * t / self.load_ramp_time))
        return ramp * self.load / self.solid.mass[:, None]

    def advance(self, duration, time, watchdog):
        """An outer step of `duration` from `time` alone (no water): whole steps no larger than the stable one, the
        prescribed load held at its value at mid-step."""
        watchdog.solid_speed_before_substeps()
        dt_max = self.stable_dt(time)
        n = max(1, math.ceil(duration / dt_max * (1.0 - 1e-12)))
        self._advance(n, duration / n, self.prescribed_acceleration(time + 0.5 * duration), time)

    def advance_coupled(self, push, fluid_dt, substeps, time, watchdog, push_start=None):
        """Satake et al. sec. 2.3: the sub-steps of one fluid step `fluid_dt`, the water's push `push` held over
        them; `substeps(fluid_dt, stable_dt)` gives their number and a warning or None (coupling.solver).

        With `push_start` (coupling.push_ramp: the previous fluid step's push) the push goes linearly from it to
        `push` over the step instead, in at most RAMP_PIECES pieces of whole sub-steps, each held at the ramp's
        value at its middle (so the impulse is the ramp's exactly): a held push changes in a staircase at the
        fluid step's frequency, which rings a stiff solid whose mode lies there (docs/method.md, coupling)."""
        watchdog.solid_speed_before_substeps()
        n, warning = substeps(fluid_dt, self.solver.stable_dt())
        if warning:
            self.warnings.append(f"t = {time:.6g} s: {warning}")
        dt = fluid_dt / n
        if push_start is None:
            self._advance(n, dt, push, time)
            return
        ends = ramp_pieces(n, RAMP_PIECES)
        change = push - push_start
        for first, last in zip(ends[:-1], ends[1:]):
            self._advance(int(last - first), dt, push_start + (0.5 * (first + last) / n) * change, time)
        self.last_substeps = n

    def _advance(self, n, dt, ext_acc, time):
        """`n` solid steps of `dt` (SolidSolver.advance), counted and timed."""
        start = _time.perf_counter()
        capped_first = self.solver.advance(n, dt, ext_acc)
        self.seconds += _time.perf_counter() - start
        if capped_first:    # once per run; summary.json counts them all
            prm = self.solver.params
            self.warnings.append(f"t = {time:.6g} s: a solid step reached solid.pressure_max_iterations = "
                                 f"{prm.pressure_max_iterations} with its residual above "
                                 f"solid.pressure_tolerance = {prm.pressure_tolerance:g} (summary.json "
                                 f"solid_pressure_solve.capped_steps counts them)")
        self.last_dt, self.last_substeps = dt, n
        self.steps += n

    def relax(self, duration):
        """The static cases' relaxation over an outer step: dv/dt = -c v taken exactly on the velocity the particles
        have (SolidSolver.relax); it settles a statically loaded case, whose rest state does not depend on c."""
        if self.damping_rate > 0.0:
            self.solver.relax(math.exp(-self.damping_rate * duration))

    # ---- read-only views -----------------------------------------------------------------------------------
    def energies(self):
        """{'kinetic_energy', 'strain_energy'} in J (the kinetic from SolidSolver.velocity)."""
        s = self.solid
        return {"kinetic_energy": kinetic_energy(s.mass, self.solver.velocity(), s.movable),
                "strain_energy": self.solver.strain_energy()}

    def sample(self):
        """The time series' solid columns: the step and how many the last outer step (or fluid step) took."""
        return {"solid_dt": self.last_dt, "solid_substeps": self.last_substeps}
