"""The study's experiment that tells gravity from the free surface (docs/validation/OPEN.md 7): Taylor-Green cells,
u = U sin(k x) cos(k z), w = -U cos(k x) sin(k z), between a free-slip floor and lid (z = 0 and pi / k, where w = 0:
32 x 6 x 16 spacings of 5 mm, 7 across at h/dp 1.5 and 4 h/dp + 1 above it, walls 4 layers on the water's lattice
and more where the kernel reaches past them), periodic along x and y, with gravity G. The cells are a steady
inviscid flow whatever G (its hydrostatic pressure added) and there is no free surface: what G changes is how hard
the correction holds the water up. The water (moved at random by up to JITTER spacings first) settles at rest for
1 s, its velocity halved every 5 ms, then takes the cells' field.
Stepped by the fluid's solver alone at DT (default 5 ms) with the default correction. Prints every 0.25 s the
kinetic energy over the start's, the cells' amplitude (the velocity projected on the field at the particles'
positions, over U) and the RMS speed (mm/s); U = 0: the water at rest, its RMS speed alone.

    python docs/validation/studies/water_lattice/cell_flow.py [H_OVER_DP [G [JITTER [U [DT [SHIFT [WARM]]]]]]]
        [--kernel cubic_spline | wendland_c2] [--free-surface]

(20-60 s a run.) SHIFT: A of particle_shifting.py (0: none), on from the start (the settling included). WARM: the
last step's correction carried into the next step's predictor, this fraction of it (a warm start: the correction
then makes up only the change; 0: none, the default solver's), from the start. --kernel: the water's kernel
(fluid.kernel; the cubic spline by default). --free-surface: no lid, the water's top free (the cells' w is 0 there
and their dynamic pressure, rho U^2 / 4 = 0.4 Pa at the default U, would lift it by U^2 / 4g = 0.04 mm: the same
flow to a hundredth of a spacing), to tell what the free surface takes from what the water's bulk does.
"""
import math
import sys

import numpy as np
from cells import cell_amplitude, kinetic_energy, start_cells
from particle_shifting import install

from sph_fsi_core.fluid.solver import FluidSolver
from sph_fsi_core.numerics.kernels import KERNELS, lattice_density_scale
from sph_fsi_core.state import FluidState, WallState

kernel = "cubic_spline"
if "--kernel" in sys.argv:
    at = sys.argv.index("--kernel")
    kernel = sys.argv[at + 1]
    del sys.argv[at:at + 2]
free_surface = "--free-surface" in sys.argv
if free_surface:
    sys.argv.remove("--free-surface")
ratio = float(sys.argv[1]) if len(sys.argv) > 1 else 1.5
gravity = float(sys.argv[2]) if len(sys.argv) > 2 else 9.81
jitter = float(sys.argv[3]) if len(sys.argv) > 3 else 0.1
speed = float(sys.argv[4]) if len(sys.argv) > 4 else 0.04
dt = float(sys.argv[5]) if len(sys.argv) > 5 else 0.005
shift = float(sys.argv[6]) if len(sys.argv) > 6 else 0.0
warm = float(sys.argv[7]) if len(sys.argv) > 7 else 0.0
dp, n = 0.005, 32
layers = max(4, math.ceil(2.0 * ratio) + 1)                            # the walls reach past the kernel's 2h
across = 6 if ratio < 1.4 else (7 if ratio <= 1.5 else int(4.0 * ratio) + 1)   # the period wider than 4h
depth = n // 2
plane = [(np.arange(m) + 0.5) * dp for m in (n, across)]
heights = (np.arange(depth) + 0.5) * dp
pos = np.stack(np.meshgrid(*plane, heights, indexing="ij"), axis=-1).reshape(-1, 3)
wall_heights = np.concatenate([-(np.arange(layers) + 0.5) * dp]
                              + ([] if free_surface else [depth * dp + (np.arange(layers) + 0.5) * dp]))
wall_pos = np.stack(np.meshgrid(*plane, wall_heights, indexing="ij"), axis=-1).reshape(-1, 3)
if jitter:
    pos += jitter * dp * np.random.default_rng(0).uniform(-1.0, 1.0, pos.shape)
    pos[:, 2] = np.clip(pos[:, 2], 0.3 * dp, (depth - 0.3) * dp)
scale = lattice_density_scale(ratio, KERNELS[kernel])
water = FluidState.at_rest(pos, 1000.0, dp, mass_scale=scale)
walls = WallState.lattice(wall_pos, 1000.0, dp, mass_scale=scale)
period = np.array([n * dp, across * dp, 0.0])
lo = np.array([0.0, 0.0, -layers * dp - 0.05])
hi = np.array([n * dp, across * dp, (depth + layers) * dp + 0.05])
solver = FluidSolver(water, walls, ratio * dp, period, lo, hi, 0.1 * ratio * dp, KERNELS[kernel])
solver.configure(rho0=1000.0, nu=1.0e-6, gravity=(0.0, 0.0, -gravity), tolerance=0.01, tolerance_on="max",
                 coefficient=0.0, kappa=1.0, min_iterations=0, max_iterations=300)
install(shift, dp, free_surface=False)


def fluid_step():
    """One fluid step, with WARM of the last step's correction displacement given to the predictor."""
    if warm:
        water.vel += warm * water.correction_displacement / dt
    return solver.step(dt)


for _ in range(round(1.0 / dt)):
    fluid_step()
    water.vel *= 0.5 ** (dt / 0.005)
water.vel[:] = 0.0
k = 2.0 * math.pi / (n * dp)
k0 = start_cells(water, k, speed)
every = round(0.25 / dt)
rows, iterations = [], []
for step in range(1, 6 * every + 1):
    iterations.append(fluid_step().iterations)
    if step % every == 0:
        rms = 1e3 * math.sqrt((water.vel ** 2).sum(axis=1).mean())
        if speed > 0.0:
            rows.append(f"{step * dt:.2f} s: {kinetic_energy(water) / k0:.3f} / "
                        f"{cell_amplitude(water, k, speed):+.3f} / {rms:.1f}")
        else:
            rows.append(f"{step * dt:.2f} s: {rms:.1f}")
print(f"{kernel}{', free surface' if free_surface else ''}, h/dp {ratio:g}, g {gravity:g} m/s^2, "
      f"jitter {jitter:g} dp, U {speed:g} m/s, dt {1e3 * dt:g} ms, shift {shift:g}, warm {warm:g}: "
      + ("kinetic energy / start, amplitude / U, RMS speed [mm/s]: " if speed > 0.0 else "RMS speed [mm/s]: ")
      + "; ".join(rows) + f"; {np.mean(iterations):.1f} iterations a step")
