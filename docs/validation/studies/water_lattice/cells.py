"""Taylor-Green cells, u = U sin(k x) cos(k z), w = -U cos(k x) sin(k z), for the study's scripts (taylor_green.py,
cell_flow.py): the field laid on the water and what is measured of it."""
import numpy as np


def cell_field(k, pos):
    """(u, w) / U at the positions (N, 3)."""
    x, z = pos[:, 0], pos[:, 2]
    return np.sin(k * x) * np.cos(k * z), -np.cos(k * x) * np.sin(k * z)


def start_cells(water, k, speed):
    """Lay the cells at `speed` on the water's velocity (x and z); returns the kinetic energy it then has (J)."""
    ux, uz = cell_field(k, water.pos)
    water.vel[:, 0], water.vel[:, 2] = speed * ux, speed * uz
    return kinetic_energy(water)


def kinetic_energy(water):
    return 0.5 * (water.mass * (water.vel ** 2).sum(axis=1)).sum()


def cell_amplitude(water, k, speed):
    """The water's velocity projected on the cells' field at its positions, over U."""
    ux, uz = cell_field(k, water.pos)
    return (water.vel[:, 0] * ux + water.vel[:, 2] * uz).sum() / (ux * ux + uz * uz).sum() / speed
