"""Particle arrays by phase, structure of arrays, float64. A phase that a scene does not have is None.

Solid particles include the clamp: solid particles whose velocity is held at zero (`movable` False). They carry
stress and density like the rest of the body, so the stress field runs continuously into the clamp, but they
never move. They are what `~/walls` shows for a solid-only scene.
"""
from dataclasses import dataclass, field

import numpy as np


@dataclass
class SolidState:
    pos: np.ndarray          # (N, 3) m
    vel: np.ndarray          # (N, 3) m/s
    rho: np.ndarray          # (N,) kg/m^3
    stress: np.ndarray       # (N, 6) Pa, deviatoric S in XX, YY, ZZ, XY, XZ, YZ order
    mass: np.ndarray         # (N,) kg
    movable: np.ndarray      # (N,) bool; False: clamp particle, velocity held at zero
    surface_normal: np.ndarray = None   # (N, 3) outward unit normal, zero inside (set by coupled scenes)
    acc: np.ndarray = field(default=None)        # (N, 3) m/s^2, acceleration at the current positions
    pressure: np.ndarray = field(default=None)   # (N,) Pa
    # (N, 3, 6) Pa/m, d_k S (deviatoric) of solid.nodal_integration = gradient (solid/gradient_integration.py); else (0, 3, 6)
    stress_gradient: np.ndarray = field(default=None)

    def __post_init__(self):
        n = len(self.pos)
        if self.acc is None:
            self.acc = np.zeros((n, 3))
        if self.pressure is None:
            self.pressure = np.zeros(n)
        if self.stress_gradient is None:
            self.stress_gradient = np.zeros((0, 3, 6))

    @classmethod
    def at_rest(cls, pos, movable, density, spacing):
        n = len(pos)
        return cls(pos=np.ascontiguousarray(pos, dtype=np.float64), vel=np.zeros((n, 3)),
                   rho=np.full(n, float(density)), stress=np.zeros((n, 6)),
                   mass=np.full(n, float(density) * spacing ** 3), movable=np.asarray(movable, dtype=np.bool_))

    @property
    def count(self):
        return len(self.pos)

    @property
    def moving_count(self):
        return int(self.movable.sum())


@dataclass
class FluidState:
    """Water particles of the density-correction fluid (Satake et al. sec. 2.2).

    `pressure` is the pressure that made this step's correction: the sum over the step's correction iterations of
    eq. (7)'s c^2 (rho - rho0)_+ (see fluid/okaji.py); `rho` the summation density (1) at the current positions.
    `correction_displacement` is r(t+dt) - r* of the last step, what the density correction moved each particle
    (kept for the coupling of eq. (10)).
    """
    pos: np.ndarray          # (N, 3) m
    vel: np.ndarray          # (N, 3) m/s
    rho: np.ndarray          # (N,) kg/m^3
    pressure: np.ndarray     # (N,) Pa
    mass: np.ndarray         # (N,) kg
    correction_displacement: np.ndarray = field(default=None)   # (N, 3) m

    def __post_init__(self):
        if self.correction_displacement is None:
            self.correction_displacement = np.zeros((len(self.pos), 3))

    @classmethod
    def at_rest(cls, pos, density, spacing, mass_scale=1.0):
        """At rest on a lattice of spacing dp: mass rho0 dp^3 times `mass_scale` (numerics.kernels
        lattice_density_scale)."""
        n = len(pos)
        return cls(pos=np.ascontiguousarray(pos, dtype=np.float64), vel=np.zeros((n, 3)),
                   rho=np.full(n, float(density)), pressure=np.zeros(n),
                   mass=np.full(n, float(density) * spacing ** 3 * mass_scale))

    @property
    def count(self):
        return len(self.pos)


@dataclass
class WallState:
    """Fixed wall particles: they never move; fluid particles count their mass at their positions in eq. (1)."""
    pos: np.ndarray          # (N, 3) m
    mass: np.ndarray         # (N,) kg
    rho0: float              # kg/m^3, the density the wall stands for (the fluid's rest density)

    @classmethod
    def lattice(cls, pos, density, spacing, mass_scale=1.0):
        return cls(pos=np.ascontiguousarray(pos, dtype=np.float64),
                   mass=np.full(len(pos), float(density) * spacing ** 3 * mass_scale), rho0=float(density))

    @property
    def count(self):
        return len(self.pos)


@dataclass
class Probe:
    """A named group of particles whose mean displacement is reported (e.g. a beam's free end)."""
    name: str
    phase: str
    indices: np.ndarray
    reference_position: np.ndarray   # (3,) mean initial position

    def displacement(self, pos):
        return pos[self.indices].mean(axis=0) - self.reference_position
