"""Energies and the watchdog: the checks that stop a run.

The watchdog runs after every outer step. Checks, in order, for the solid: non-finite state, density out of
[0.5, 2] rho0, particles faster than watchdog.max_speed, particles outside the scene's domain, and (scenes with no
energy input) kinetic + strain energy above watchdog.energy_growth times its initial value; for the fluid:
non-finite state, compression above fluid.max_density_error (the correction lost control), speed, and a stable
fluid step collapsing below fluid.min_time_step. The first that trips raises Diverged naming the check, the
simulated time, the phase and the particles involved (indices within their phase).

Water outside the domain is no divergence: a splash over a tank's rim is held still where it left (Simulation) and
recorded (fluid/lost_water.py), and the run goes on, unless the scene asks it to stop once more than
watchdog.max_fluid_lost of the water has left: then WaterLost, an outcome of its own (status water_lost).
"""
import numpy as np
from numba import njit

from .errors import plain


class Stopped(RuntimeError):
    """The watchdog stopped the run: `check` tripped at `time` on `particles` (indices in `phase`). `outcome` is the
    run's status."""
    outcome = "stopped"

    def __init__(self, check, time, particles, detail, phase="solid"):
        self.check = check
        self.time = time
        self.particles = list(int(i) for i in particles[:10])
        self.detail = detail
        self.phase = phase
        super().__init__(f"{self.outcome.replace('_', ' ')}: {check} at t = {time:.6g} s: {detail}")

    def as_dict(self):
        return {"check": self.check, "time": self.time, "phase": self.phase, "particles": self.particles,
                "detail": self.detail}


class Diverged(Stopped):
    """The run left the physically sensible state (a numerical blow-up)."""
    outcome = "diverged"


class WaterLost(Stopped):
    """More of the water left the domain than watchdog.max_fluid_lost allows: the stop the scene asked for."""
    outcome = "water_lost"


@njit(cache=True, fastmath=False, error_model="numpy", nogil=True)
def kinetic_energy(mass, vel, movable):
    """Sum of m v^2 / 2 over moving particles."""
    total = 0.0
    for a in range(mass.shape[0]):
        if movable[a]:
            total += 0.5 * mass[a] * (vel[a, 0] ** 2 + vel[a, 1] ** 2 + vel[a, 2] ** 2)
    return total


def _where(mask):
    return np.flatnonzero(mask)


class Watchdog:
    def __init__(self, sim, domain_lo, domain_hi):
        self.sim = sim
        self.lo = domain_lo
        self.hi = domain_hi
        self.conservative = sim.builder.conservative
        energies = sim.energies()
        self.initial_energy = sum(energies.values())

    def _trip(self, check, bad, detail, phase="solid", stop=Diverged):
        initial = self.sim.initial_positions(phase)
        idx = bad[:3]
        where = "; ".join(f"{phase} particle {i} (initially at {plain(initial[i], 4)} m)"
                          for i in idx)
        raise stop(check, self.sim.time, bad, f"{detail}; {len(bad)} {phase} particle(s), e.g. {where}", phase)

    def fluid_step_collapsed(self, dt):
        """Called by the fluid loop when its stable step falls below fluid.min_time_step: names the fastest."""
        f = self.sim.fluid
        speed = np.sqrt((f.vel ** 2).sum(axis=1))
        self._trip("fluid time step", np.argsort(-speed)[:3],
                   f"stable fluid step {dt:.3g} s below fluid.min_time_step = "
                   f"{self.sim.spec['fluid.min_time_step']:g} s (largest speed {speed.max():.4g} m/s)", "fluid")

    def solid_speed_before_substeps(self):
        """Called before the solid's sub-steps are planned: the speed check of check_solid, there. The solid's stable
        step falls as cfl h / (c + |v|max), so a diverging solid would otherwise take ever more sub-steps per outer
        step and never finish one for check() to see (Antoci's gate at solid.cfl = 0.35 ran on for 13 minutes in
        one outer step)."""
        self._check_solid_speed(" before the solid's sub-steps (their stable step falls with the speed)")

    def _check_solid_speed(self, when=""):
        """A solid particle faster than watchdog.max_speed trips "speed", the fastest named first."""
        s = self.sim.solid
        speed = np.sqrt((s.vel ** 2).sum(axis=1))
        limit = self.sim.spec["watchdog.max_speed"]
        bad = _where(speed > limit)
        if len(bad):
            bad = bad[np.argsort(-speed[bad], kind="stable")]    # the fastest first: where it ran away
            self._trip("speed", bad, f"speed {speed[bad[0]]:.4g} m/s above watchdog.max_speed = {limit:g} m/s{when}")
        return speed

    def check(self):
        if self.sim.fluid is not None:
            self.check_fluid()
        if self.sim.solid is not None:
            self.check_solid()

    def check_fluid(self):
        sim = self.sim
        f = sim.fluid
        v = sim.spec.values
        finite = np.isfinite(f.pos).all(axis=1) & np.isfinite(f.vel).all(axis=1) & np.isfinite(f.rho)
        if not finite.all():
            self._trip("non-finite state", _where(~finite), "fluid position, velocity or density is NaN/inf",
                       "fluid")
        compression = f.rho / v["fluid.density"] - 1.0
        bad = _where(compression > v["fluid.max_density_error"])
        if len(bad):
            bad = bad[np.argsort(-compression[bad])]
            self._trip("density error", bad, f"fluid compressed by {100 * compression[bad[0]]:.3g} % after the "
                                             f"correction, above fluid.max_density_error = "
                                             f"{100 * v['fluid.max_density_error']:g} %", "fluid")
        speed = np.sqrt((f.vel ** 2).sum(axis=1))
        bad = _where(speed > v["watchdog.max_speed"])
        if len(bad):
            self._trip("speed", bad, f"fluid speed {speed[bad[0]]:.4g} m/s above watchdog.max_speed = "
                                     f"{v['watchdog.max_speed']:g} m/s", "fluid")
        limit = v["watchdog.max_fluid_lost"]
        if self.lo is not None and limit < 1.0:      # 1: never (the default)
            lost = sim.fluid_phase.lost
            if lost.sum() > limit * len(lost):
                self._trip("left the domain", _where(lost),
                           f"{int(lost.sum())} water particle(s) left the box {plain(self.lo)} .. {plain(self.hi)} m, "
                           f"more than watchdog.max_fluid_lost = {limit:g} of the water "
                           f"({int(limit * len(lost))} particles)", "fluid", WaterLost)

    def check_solid(self):
        sim = self.sim
        s = sim.solid
        v = sim.spec.values
        finite = (np.isfinite(s.pos).all(axis=1) & np.isfinite(s.vel).all(axis=1)
                  & np.isfinite(s.stress).all(axis=1) & np.isfinite(s.rho))
        if not finite.all():
            self._trip("non-finite state", _where(~finite), "position, velocity, density or stress is NaN/inf")
        ratio = s.rho / v["solid.density"]
        bad = _where((ratio < 0.5) | (ratio > 2.0))
        if len(bad):
            self._trip("density", bad, f"solid density ratio {ratio[bad[0]]:.3g} outside [0.5, 2]")
        speed = self._check_solid_speed()
        if self.lo is not None:
            bad = _where(((s.pos < self.lo) | (s.pos > self.hi)).any(axis=1))
            if len(bad):
                self._trip("left the domain", bad, f"outside the box {plain(self.lo)} .. {plain(self.hi)} m")
        if self.conservative and self.initial_energy > 0.0:
            energy = sum(sim.energies().values())
            limit = v["watchdog.energy_growth"] * self.initial_energy
            if energy > limit:
                top = np.argsort(-speed)[:3]
                self._trip("energy growth", top, f"kinetic + strain energy {energy:.4g} J above "
                                                 f"{v['watchdog.energy_growth']:g} x its initial {self.initial_energy:.4g} J")
