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

    def __post_init__(self):
        n = len(self.pos)
        if self.acc is None:
            self.acc = np.zeros((n, 3))
        if self.pressure is None:
            self.pressure = np.zeros(n)

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
class Probe:
    """A named group of particles whose mean displacement is reported (e.g. a beam's free end)."""
    name: str
    phase: str
    indices: np.ndarray
    reference_position: np.ndarray   # (3,) mean initial position

    def displacement(self, pos):
        return pos[self.indices].mean(axis=0) - self.reference_position
