"""The study's experiment without gravity and walls (docs/validation/OPEN.md 7): a Taylor-Green vortex,
u = U sin(k x) cos(k z), w = -U cos(k x) sin(k z), in a box periodic on every axis (32 x 6 x 32 spacings of 5 mm;
7 across at h/dp 1.5), stepped by the fluid's solver alone at 5 ms with the default correction. The water's
viscosity (1e-6 m^2/s) takes exp(-4 nu k^2 t) = 0.6 % of the kinetic energy in a second: what goes beyond is the
method's. Prints the kinetic energy over the start's and the vortex's amplitude (the velocity projected on the
field at the particles' positions, over U) every 0.2 s.

    python docs/validation/studies/water_lattice/taylor_green.py [H_OVER_DP [U [JITTER [SHIFT]]]]   (about 30 s a run)

SHIFT: A of particle_shifting.py (0: none), on from the start (the disordered water's relaxation included).
"""
import math
import sys

import numpy as np
from cells import cell_amplitude, kinetic_energy, start_cells
from particle_shifting import install

from sph_fsi_core.fluid.solver import FluidSolver
from sph_fsi_core.numerics.kernels import lattice_density_scale
from sph_fsi_core.state import FluidState

ratio = float(sys.argv[1]) if len(sys.argv) > 1 else 1.3
speed = float(sys.argv[2]) if len(sys.argv) > 2 else 0.04
jitter = float(sys.argv[3]) if len(sys.argv) > 3 else 0.0
shift = float(sys.argv[4]) if len(sys.argv) > 4 else 0.0
dp, n, dt = 0.005, 32, 0.005
across = 6 if ratio < 1.4 else 7
axes = [(np.arange(m) + 0.5) * dp for m in (n, across, n)]
pos = np.stack(np.meshgrid(*axes, indexing="ij"), axis=-1).reshape(-1, 3)
if jitter:
    pos += jitter * dp * np.random.default_rng(0).uniform(-1.0, 1.0, pos.shape)
water = FluidState.at_rest(pos, 1000.0, dp, mass_scale=lattice_density_scale(ratio))
period = np.array([n * dp, across * dp, n * dp])
solver = FluidSolver(water, None, ratio * dp, period, np.zeros(3), period, 0.1 * ratio * dp)
solver.configure(rho0=1000.0, nu=1.0e-6, gravity=(0.0, 0.0, 0.0), tolerance=0.01, tolerance_on="max",
                 coefficient=0.0, kappa=1.0, min_iterations=0, max_iterations=200)
install(shift, dp, free_surface=False)
k = 2.0 * math.pi / (n * dp)
if jitter:   # the disordered water relaxed at rest first
    for _ in range(100):
        solver.step(dt)
        water.vel *= 0.5
    water.vel[:] = 0.0
k0 = start_cells(water, k, speed)
rows = []
for step in range(1, 201):
    solver.step(dt)
    if step % 40 == 0:
        rows.append(f"{step * dt:.1f} s: {kinetic_energy(water) / k0:.3f} / {cell_amplitude(water, k, speed):+.3f}")
print(f"h/dp {ratio:g}, U {speed:g} m/s, jitter {jitter:g} dp, shift {shift:g}: kinetic energy / start, amplitude / U: "
      + "; ".join(rows))
