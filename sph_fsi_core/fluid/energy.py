"""The water's mechanical energy, for its budget step by step (fluid/solver.py, fluid/phase.py): what the
correction and the viscous term take from it."""
from numba import njit


@njit(cache=True, fastmath=False, error_model="numpy", nogil=True)
def mechanical_energy(pos, vel, mass, gx, gy, gz):
    """(kinetic, potential) in J: sum_a m_a |v_a|^2 / 2 and sum_a -m_a g . r_a (zero at the origin)."""
    kinetic = 0.0
    potential = 0.0
    for a in range(pos.shape[0]):
        m = mass[a]
        kinetic += 0.5 * m * (vel[a, 0] * vel[a, 0] + vel[a, 1] * vel[a, 1] + vel[a, 2] * vel[a, 2])
        potential -= m * (gx * pos[a, 0] + gy * pos[a, 1] + gz * pos[a, 2])
    return kinetic, potential
