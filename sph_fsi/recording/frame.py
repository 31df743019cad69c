"""One recorded instant, captured on the simulation thread and written on the recorder's thread.

Capturing copies only what the simulator will overwrite (positions, velocities, pressure and, for the solid,
the deviatoric stress of the moving particles); von Mises stress, colours, point packing, CDR encoding and
compression all happen on the recorder's thread.
"""
from dataclasses import dataclass, field

import numpy as np

from sph_fsi.points import moving_particles, wall_positions

__all__ = ["Frame", "Static", "Final", "capture", "capture_static"]


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
    parts: list                 # [(phase code, pos, vel, pressure, deviatoric stress (M, 6) or None)]
    probes: dict                # name -> (dx, dy, dz) m
    energies: dict              # 'kinetic_energy', 'strain_energy' J (what the scene has)
    diagnostics: dict = field(default_factory=dict)   # key -> str, for /diagnostics
    status: str = "running"


@dataclass
class Final:
    """The last /diagnostics of a recording: how the run ended (finished, diverged, interrupted, failed)."""
    time: float
    status: str
    diagnostics: dict


def capture_static(sim):
    return Static(time=float(sim.time), walls=np.array(wall_positions(sim), dtype=np.float64),
                  scene=sim.spec.name, spacing=float(getattr(sim, "spacing", 0.0)),
                  probes=tuple(p.name for p in getattr(sim, "probes", [])))


def capture(sim, row=None, diagnostics=None):
    """A Frame of `sim` now. `row` (a sim.sample() row) saves recomputing the energies."""
    parts = moving_particles(sim, stress=True)   # boolean indexing: these are copies already
    probes = {k: tuple(float(x) for x in v) for k, v in sim.probe_displacements().items()}
    if row is not None and all(k in row for k in ("kinetic_energy", "strain_energy")):
        energies = {k: float(row[k]) for k in ("kinetic_energy", "strain_energy")}
    else:
        energies = {k: float(v) for k, v in sim.energies().items()}
    return Frame(time=float(sim.time), parts=parts, probes=probes, energies=energies,
                 diagnostics=dict(diagnostics or {}))
