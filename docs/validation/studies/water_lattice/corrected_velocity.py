"""The study's experiment on the velocity's correction from a first-order consistent gradient (docs/validation/OPEN.md
7): the correction still moves the particles by eq. (2)'s whole term (the water held up and kept in order as
before), but their velocity takes, instead of the correction's displacement over dt (eq. (8)), the step's pressure
(the correction's summed pressure, fluid.pressure) through a corrected kernel gradient (Bonet & Lok 1999):

    dv_a = -dt / rho_a  M_a^-1 sum_b V_b (p_b - p_a) grad_a W_ab,    M_a = sum_b V_b grad_a W_ab (r_b - r_a)^T,

over the water alone (V = m / rho). It is exact for a linear pressure, so the column's hydrostatic pressure gives
the velocity exactly g dt back, whatever the arrangement; the background part m_b 2 q_a grad W and the difference
form's zero-order error stay in the positions. M over the water alone keeps the gradient one-sided but consistent
next to walls and the free surface. A particle whose kernel is short of water (sum_b V_b W_ab, its own term
included, below FULL) or whose M is near singular keeps the default's velocity. No scene key does this: it wraps
the fluid solver for the script it runs.

    python docs/validation/studies/water_lattice/corrected_velocity.py FULL SCRIPT [ARGS ...]
    (e.g. 0.5 cell_flow.py 1.5 9.81 0.1; SCRIPT one of the study's scripts; 1.5-2 times the script's time)
"""
import os
import runpy
import sys

import numpy as np
from kernel_pairs import kernel_and_gradient, kernel_fullness, pair_sum, periodic_pairs

import sph_fsi_core.fluid.solver as solver_module

SINGULAR = 1.0e-3   # det(M) below this (M is 1 on a full kernel): the gradient is not trusted


def corrected_pressure_velocity(solver, dt, least_full):
    """-dt / rho_a M_a^-1 sum_b V_b (p_b - p_a) grad_a W_ab for each water particle, and where it is trusted."""
    fl, h = solver.fluid, solver.h
    n = len(fl.pos)
    i, j, d = periodic_pairs(fl.pos, solver.period, solver.box_lo, 2.0 * h)
    w, grad = kernel_and_gradient(d, np.sqrt((d * d).sum(axis=1)), h)   # grad_i W_ij, d = r_i - r_j
    volume = fl.mass / fl.rho
    p = fl.pressure
    # grad_i W_ij (r_j - r_i)^T and grad_j W_ji (r_i - r_j)^T are the same matrix
    outer = (grad[:, :, None] * -d[:, None, :]).reshape(-1, 9)
    moment = pair_sum(i, j, n, volume[j, None] * outer, volume[i, None] * outer).reshape(n, 3, 3)
    # sum_b V_b (p_b - p_a) grad_a W_ab: both ends give V (p_j - p_i) grad_i W_ij
    dp = (p[j] - p[i])[:, None] * grad
    raw = pair_sum(i, j, n, volume[j, None] * dp, volume[i, None] * dp)
    trusted = (kernel_fullness(i, j, w, volume, h) >= least_full) & (np.linalg.det(moment) > SINGULAR)
    dv = np.zeros((n, 3))
    dv[trusted] = -dt * np.linalg.solve(moment[trusted], raw[trusted][:, :, None])[:, :, 0] / fl.rho[trusted, None]
    return dv, trusted


def install(least_full):
    """Take the velocity's correction from the corrected gradient after every FluidSolver.step from now on; returns
    the list each step appends its share of trusted particles to."""
    step, kept = solver_module.FluidSolver.step, []

    def corrected_step(self, dt):
        report = step(self, dt)
        dv, trusted = corrected_pressure_velocity(self, dt, least_full)
        self.fluid.vel[trusted] += dv[trusted] - self.fluid.correction_displacement[trusted] / dt
        kept.append(trusted.mean())
        return report

    solver_module.FluidSolver.step = corrected_step
    return kept


if __name__ == "__main__":
    least = float(sys.argv[1])
    shares = install(least)
    script = os.path.join(os.path.dirname(os.path.abspath(__file__)), sys.argv[2])
    sys.argv = [script] + sys.argv[3:]
    runpy.run_path(script, run_name="__main__")
    print(f"full {least:g}: corrected {100 * np.mean(shares):.1f} % of particle-steps")
