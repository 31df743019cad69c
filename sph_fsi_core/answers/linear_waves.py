"""Linear (Airy) water waves over a flat floor: the dispersion relation and a standing wave's velocity field, the
exact answer of the small-amplitude standing wave (Dean & Dalrymple, "Water Wave Mechanics for Engineers and
Scientists", 1991, ch. 3; Lamb, "Hydrodynamics", ch. IX).

A standing wave of amplitude a and wavenumber k = 2 pi / L in water of depth d, its surface

    eta(x, t) = a cos(k (x - x0)) sin(omega t),    omega^2 = g k tanh(k d),

is the velocity potential phi = (a omega / k) cos(k (x - x0)) cosh(k s) / sinh(k d) cos(omega t), s the height
above the floor (the kinematic surface condition eta_t = phi_z at s = d). At t = 0 the surface is flat and the
pressure hydrostatic (phi_t = 0): nothing but the velocity differs from water at rest, so a settled column starts
the wave cleanly with this field. x0 is an antinode where the surface rises first.
"""
import math
from dataclasses import dataclass

import numpy as np
from numba import njit


def dispersion_omega(wavenumber, depth, gravity):
    """omega = sqrt(g k tanh(k d)), rad/s: linear theory's angular frequency (the dispersion relation)."""
    return math.sqrt(gravity * wavenumber * math.tanh(wavenumber * depth))


def standing_wave_period(wavelength, depth, gravity):
    """T = 2 pi / omega, s, of a wave of length L in water of depth d."""
    return 2.0 * math.pi / dispersion_omega(2.0 * math.pi / wavelength, depth, gravity)


@njit(cache=True, fastmath=False, error_model="numpy", nogil=True)
def standing_wave_velocity(pos, amplitude, wavenumber, omega, depth, floor, antinode, out):
    """The standing wave's velocity at t = 0 (module docstring), grad phi at each position (N, 3) into out (N, 3):
    u = -a omega sin(k (x - x0)) cosh(k s) / sinh(k d), w = a omega cos(k (x - x0)) sinh(k s) / sinh(k d), s = z -
    floor; none across (y). Divergence-free: u_x + w_z = 0 term by term."""
    scale = amplitude * omega / math.sinh(wavenumber * depth)
    for i in range(pos.shape[0]):
        phase = wavenumber * (pos[i, 0] - antinode)
        height = wavenumber * (pos[i, 2] - floor)
        out[i, 0] = -scale * math.sin(phase) * math.cosh(height)
        out[i, 1] = 0.0
        out[i, 2] = scale * math.cos(phase) * math.sinh(height)
    return out


@dataclass(frozen=True)
class StandingWave:
    """A standing wave along x over a floor at z = `floor` (m) under gravity `gravity` (m/s^2, down): the initial
    velocity a water part's standing_wave_* keys ask for (scenes/geometry.py), added at t = 0 (simulation.py)."""
    amplitude: float      # a, m
    wavelength: float     # L, m
    depth: float          # d, m
    floor: float          # m
    antinode: float       # x0, m
    gravity: float        # |g|, m/s^2

    @property
    def wavenumber(self):
        return 2.0 * math.pi / self.wavelength

    @property
    def omega(self):
        return dispersion_omega(self.wavenumber, self.depth, self.gravity)

    def velocity(self, pos):
        """(N, 3) m/s at the positions (N, 3)."""
        pos = np.ascontiguousarray(pos, dtype=np.float64)
        return standing_wave_velocity(pos, self.amplitude, self.wavenumber, self.omega, self.depth, self.floor,
                                      self.antinode, np.empty_like(pos))
