"""The study's particle shifting (docs/validation/OPEN.md 7), for its experiment scripts: after each fluid step every
water particle is moved, its velocity kept, down the gradient of its kernel's concentration (Lind, Xu, Stansby &
Rogers 2012, J. Comput. Phys. 231, Fickian shifting with their anti-clumping term):

    dr_a = -A h |v_a| dt grad C_a,    grad C_a = sum_b V_b (1 + R (W_ab / W(dp))^n) grad_a W_ab   (R 0.2, n 4)

(with `global_speed` the water's largest |v| in place of |v_a|, as Xu, Stansby & Laurence 2009 scale it, so a
particle near a stagnation point, slow itself, is shifted as much as the flow's fastest)

over water and wall neighbours (V = m / rho0), so the water spreads towards an even arrangement. At a free surface C
falls to about 0.5 and its gradient would throw the water out: a particle is not shifted within the surface's band,
where C < 0.97, h |grad C| > 0.2, or a neighbour has C < 0.9 (Lind et al. shift only along the surface there; in
this flat band that is nearly no shift). No scene key does this: `install(A, dp, free_surface)` wraps
FluidSolver.step for the run of the script that calls it. Pairs and kernel from kernel_pairs.py (an experiment,
not a solver pass).
"""
import numpy as np
from kernel_pairs import kernel_and_gradient, kernel_w, periodic_pairs

from sph_fsi_core.fluid.okaji import wrap_periodic
from sph_fsi_core.fluid.solver import FluidSolver

R, N = 0.2, 4              # Lind et al.'s anti-clumping term
SURFACE_C = 0.9            # a particle with less is on the free surface
BAND_C, BAND_GRADIENT = 0.97, 0.2


def shift(solver, dt, coefficient, dp, free_surface, global_speed=False):
    """Move the water of a FluidSolver by one step's shifting (module docstring); returns the largest move (m)."""
    fl, h, period = solver.fluid, solver.h, solver.period
    n = len(fl.pos)
    points = np.vstack([fl.pos, solver.wall_pos])
    volume = np.concatenate([fl.mass, solver.wall_mass]) / solver.rho0
    i, j, d = periodic_pairs(points, period, solver.box_lo, 2.0 * h)
    w, grad = kernel_and_gradient(d, np.sqrt((d * d).sum(axis=1)), h)
    anti_clump = 1.0 + R * (w / kernel_w(dp, h)) ** N
    conc = volume * kernel_w(0.0, h)
    np.add.at(conc, i, volume[j] * w)
    np.add.at(conc, j, volume[i] * w)
    grad_c = np.zeros((len(points), 3))
    np.add.at(grad_c, i, (volume[j] * anti_clump)[:, None] * grad)
    np.add.at(grad_c, j, -(volume[i] * anti_clump)[:, None] * grad)
    conc, grad_c = conc[:n], grad_c[:n]
    speed = np.sqrt((fl.vel ** 2).sum(axis=1))
    if global_speed and n:
        speed[:] = speed.max()
    move = -(coefficient * h * speed * dt)[:, None] * grad_c
    if free_surface:
        surface = np.concatenate([conc < SURFACE_C, np.zeros(len(points) - n, dtype=bool)])
        band = surface.copy()
        band[i[surface[j]]] = True
        band[j[surface[i]]] = True
        band = band[:n] | (conc < BAND_C) | (h * np.linalg.norm(grad_c, axis=1) > BAND_GRADIENT)
        move[band] = 0.0
    fl.pos += move
    if period.any():
        wrap_periodic(fl.pos, period, solver.box_lo)
    return float(np.abs(move).max()) if n else 0.0


def install(coefficient, dp, free_surface, global_speed=False):
    """Shift after every FluidSolver.step from now on (A = `coefficient`; 0: nothing is installed)."""
    if coefficient <= 0.0:
        return
    step = FluidSolver.step

    def shifted_step(self, dt):
        report = step(self, dt)
        shift(self, dt, coefficient, dp, free_surface, global_speed)
        return report

    FluidSolver.step = shifted_step
