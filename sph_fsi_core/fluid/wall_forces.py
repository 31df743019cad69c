"""The water's force on groups of wall particles, from a fluid step's pressures (the `force` probes, probes.py).

The correction moves a fluid particle a by dt^2 dv_a/dt of eq. (2) each iteration; its wall terms are the walls'
push, -m_a sum_w m_w (p_a / rho_a^2 + p_w / rho0^2) grad_a W_aw, and their reaction the water's push on the wall.
Summed over a step's iterations that is the same sum with the step's accumulated pressures P (state.FluidState's
`pressure`, the sum of its iteration pressures) in place of p, up to how far the particles moved within the step's
iterations: the force here, evaluated at the step's end positions, with each wall particle's P_w the Shepard average
of its fluid neighbours' P (fluid.okaji.wall_pressure's rule).
"""
import math

import numpy as np
from numba import njit, prange

from ..numerics.kernels import SUPPORT_RADIUS_IN_H, kernel_f
from ..numerics.neighbours import chunk_first_target, unsigned
from ..numerics.periodic import minimum_image


@njit(cache=True, fastmath=False, error_model="numpy", parallel=True, nogil=True)
def wall_group_forces(fluid, walls, group, neighbours, h, kernel, groups, buf):
    """(groups, 3) N: sum over fluid particles a and their wall neighbours w with group[w] = g >= 0 of
    m_a m_w (P_a / rho_a^2 + q_w) F_aw (r_a - r_w), F = (dW/dr) / r, into row g (the water's push on group g;
    q_w = P_w / rho0^2). `fluid`: fluid.stepper.FluidArrays (P_a its step's summed pressure); `walls`: FluidWalls
    (q_w its p_over_rho2); `neighbours`: FluidNeighbours (its fluid->wall list); `kernel`: numerics/kernels.py's
    id; `buf`: (chunks, groups, 3) scratch."""
    pos = fluid.pos
    mass = fluid.mass
    rho = fluid.rho
    pressure = fluid.pressure
    wall_pos = walls.pos
    wall_mass = walls.mass
    wall_q = walls.p_over_rho2
    wstart = neighbours.wall_start
    windex = neighbours.wall_index
    period = neighbours.period
    chunks = buf.shape[0]
    reach = SUPPORT_RADIUS_IN_H * h
    half_period = 0.5 * period
    for c in prange(chunks):
        out = buf[c]
        out[:] = 0.0
        for a in range(chunk_first_target(wstart, c, chunks), chunk_first_target(wstart, c + 1, chunks)):
            qa = pressure[a] / (rho[a] * rho[a])
            for k in range(unsigned(wstart[a]), unsigned(wstart[a + 1])):
                w = windex[k]
                g = group[w]
                if g < 0:
                    continue
                dx = minimum_image(pos[a, 0] - wall_pos[w, 0], period[0], half_period[0])
                dy = minimum_image(pos[a, 1] - wall_pos[w, 1], period[1], half_period[1])
                dz = minimum_image(pos[a, 2] - wall_pos[w, 2], period[2], half_period[2])
                r = math.sqrt(dx * dx + dy * dy + dz * dz)
                if r >= reach:
                    continue
                coef = mass[a] * wall_mass[w] * (qa + wall_q[w]) * kernel_f(r, h, kernel)
                out[g, 0] += coef * dx
                out[g, 1] += coef * dy
                out[g, 2] += coef * dz
    total = np.zeros((groups, 3))
    for c in range(chunks):
        total += buf[c]
    return total


