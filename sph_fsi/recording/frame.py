"""One recorded instant, captured on the simulation thread and written on the recorder's thread.

Capturing copies only what the simulator will overwrite (positions, velocities, pressure and, for the solid,
the deviatoric stress), as whole arrays; selecting the moving particles, von Mises stress, colours, point
packing, CDR encoding and compression all happen on the recorder's thread. The phases are the same as
sph_fsi.points.moving_particles (fluid first, then solid; only those the scene has). The probes' readings are
copied whole (sph_fsi.points.probe_readings: a few small dicts of floats), so that every sink reports the values
the simulator had at the frame's time.
"""
from dataclasses import dataclass, field

import numpy as np

from sph_fsi.points import (PHASE_CODES, PHASE_WALL, commanded_parts, moving_walls, part_readings, probe_readings,
                            quaternion, wall_positions)
from sph_fsi_core.numerics.tensors import von_mises

__all__ = ["Frame", "Static", "Final", "capture", "capture_static", "applied_commands"]


@dataclass
class Static:
    """What is logged once per simulation build: the fixed particles, the scene's name and spacing."""
    time: float
    walls: np.ndarray           # (W, 3) m, may be empty
    scene: str
    spacing: float
    probes: tuple               # probe names


@dataclass
class Frame:
    time: float                 # s, simulated
    raw: list                   # [(phase code, pos, vel, pressure, stress (N, 6) or None, movable mask)]: full copies
    probes: dict                # name -> (kind, {quantity: float or (x, y, z)}): sph_fsi.points.probe_readings
    energies: dict              # sim.energies(): 'kinetic_energy', 'strain_energy', 'fluid_kinetic_energy' J
    diagnostics: dict = field(default_factory=dict)   # key -> str, for /diagnostics
    status: str = "running"
    walls: dict = field(default_factory=dict)     # the commanded walls' readings (sph_fsi.points.part_readings)
    commands: list = field(default_factory=list)  # commands applied since the last frame (applied_commands)
    _parts: list = None

    @property
    def parts(self):
        """[(phase code, pos, vel, pressure, von Mises)] of the moving particles; computed once, on the recorder's
        thread (masking and von Mises cost ~20 ms per 1e5 particles: kept off the simulation thread)."""
        if self._parts is None:
            parts = []
            for code, pos, vel, pressure, stress, m in self.raw:
                if m is not None and not m.all():
                    pos, vel, pressure = pos[m], vel[m], pressure[m]
                    stress = stress[m] if stress is not None else None
                vm = von_mises(stress) if stress is not None else np.zeros(len(pos))
                parts.append((code, pos, vel, pressure, vm))
            self._parts = parts
        return self._parts

    def forget_parts(self):
        """Drop the computed parts, so the next read of `parts` pays for them again (bench/recording_cost.py)."""
        self._parts = None


@dataclass
class Final:
    """The last /diagnostics of a recording: how the run ended (finished, diverged, water_lost, interrupted, failed)."""
    time: float
    status: str
    diagnostics: dict


def capture_static(sim):
    return Static(time=float(sim.time), walls=np.array(wall_positions(sim), dtype=np.float64),
                  scene=sim.spec.name, spacing=float(getattr(sim, "spacing", 0.0)),
                  probes=tuple(p.name for p in getattr(sim, "probes", [])))


def applied_commands(sim, first=0):
    """The commands the boundary applied from its `first`-th on, as recorded: [(time applied s, part, 'pose_cmd' or
    'twist_cmd', numbers)], their numbers as they came (a message's: sph_fsi.points.command_values), or for a
    command given without them, a pose as (its motion_point's position, quaternion), a velocity as (linear,
    angular)."""
    boundary = getattr(sim, "boundary", None)
    out = []
    for t, name, kind, values, source in (boundary.applied[first:] if boundary is not None else []):
        if source is not None:
            out.append((t, name) + tuple(source))
        elif kind == "pose":
            rotation, shift = values
            out.append((t, name, "pose_cmd", (boundary.part_motion(name).point + shift, quaternion(rotation))))
        else:
            out.append((t, name, "twist_cmd", values))
    return out


def capture(sim, row=None, diagnostics=None, commands_from=0):
    """A Frame of `sim` now: whole-array copies (a memcpy each, ~3 ms per 1e5 particles), masked later.
    `row` (a sim.sample() row) saves recomputing the energies; `commands_from`: the first of the boundary's applied
    commands not yet recorded."""
    raw = []
    for phase in ("fluid", "solid"):
        state = getattr(sim, phase, None)
        if state is None:
            continue
        m = getattr(state, "movable", None)
        stress = getattr(state, "stress", None) if phase == "solid" else None
        # the solid's velocity as every output has it (Simulation.solid_velocity; stand-ins have vel only)
        vel = sim.solid_velocity() if phase == "solid" and hasattr(sim, "solid_velocity") else state.vel
        vel = vel.copy() if vel is state.vel else vel   # solid_velocity's v + u/2 is already a new array
        raw.append((PHASE_CODES[phase], state.pos.copy(), vel, state.pressure.copy(),
                    None if stress is None else stress.copy(), None if m is None else np.array(m, dtype=bool)))
    rows, velocity = moving_walls(sim)
    if len(rows):
        raw.append((PHASE_WALL, sim.boundary.pos[rows], velocity, np.zeros(len(rows)), None, None))
    probes = probe_readings(sim)
    energies = {k: float(v) for k, v in row.items() if k.endswith("energy")} if row is not None else None
    if not energies:
        energies = {k: float(v) for k, v in sim.energies().items()}
    return Frame(time=float(sim.time), raw=raw, probes=probes, energies=energies,
                 diagnostics=dict(diagnostics or {}), walls=part_readings(sim) if commanded_parts(sim) else {},
                 commands=applied_commands(sim, commands_from))
