"""The study's experiment on the symmetric pressure gradient's background part (docs/validation/OPEN.md 7): eq. (2)'s
pair term m_b (q_a + q_b) grad_a W_ab (q = p / rho^2) is the difference form's m_b (q_b - q_a) grad_a W_ab, which a
uniform pressure leaves without force, plus m_b 2 q_a grad_a W_ab, which on a disordered arrangement pushes a
particle by its own pressure times the arrangement's error: under the column's weight that part is large. Here the
correction still moves the particles by the whole term (so the water is held up and kept in order as before), but
SHARE of the background part's displacement, summed over the step's iterations (fluid and wall pairs), is kept out
of the velocity (as the transport-velocity formulation keeps its background pressure out of the momentum, Adami,
Hu & Adams 2013); with SMOOTH the velocity's correction is also replaced by its kernel (Shepard) average, which
takes the difference form's particle-scale noise out. No scene key does this: it wraps the fluid solver for the
script it runs.

    python docs/validation/studies/water_lattice/background_split.py SHARE SMOOTH [--full C] SCRIPT [ARGS ...]
    (e.g. 1 1 cell_flow.py 1.5 9.81 0.1; SCRIPT one of the study's scripts; 2-3 times the script's time)

With --full C the velocity is changed only where the kernel is full of water: sum_b V_b W_ab over the water (its
own term included) at least C; elsewhere (at the walls and the free surface, where the background part is the
boundary's real push) it keeps the default's.

SCRIPT may also be a scene file (ARGS its KEY=VALUE overrides): it is run headless and its judges printed with the
water's kinetic energy (mJ) every 0.1 s, to show where a run turns to noise.
"""
import os
import runpy
import sys

import numpy as np
from kernel_pairs import kernel_and_gradient, kernel_fullness, kernel_w, periodic_pairs
from numba import njit

import sph_fsi_core.fluid.solver as solver_module
from sph_fsi_core.fluid.okaji import (apply_displacement, compression_error, pressure_displacement, summation_density,
                                      wall_pressure)
from sph_fsi_core.fluid.stepper import CAPPED, CONVERGED, NEEDS_REBUILD
from sph_fsi_core.numerics.periodic import minimum_image

SHARE, SMOOTH = float(sys.argv[1]), float(sys.argv[2])
FULL = 0.0
if sys.argv[3] == "--full":
    FULL = float(sys.argv[4])
    del sys.argv[3:5]


@njit(cache=True)
def background_displacement(pos, mass, q, start, index, f, src_pos, src_mass, half, period, dt2, out):
    """-dt^2 m_b 2 q_a grad_a W_ab summed over one list's pairs into out[a] (and, for the fluid's half list, the
    pair's share of b, -dt^2 m_a 2 q_b grad_b W_ba, into out[b])."""
    for a in range(pos.shape[0]):
        for k in range(start[a], start[a + 1]):
            b = index[k]
            d0 = minimum_image(pos[a, 0] - src_pos[b, 0], period[0], 0.5 * period[0])
            d1 = minimum_image(pos[a, 1] - src_pos[b, 1], period[1], 0.5 * period[1])
            d2 = minimum_image(pos[a, 2] - src_pos[b, 2], period[2], 0.5 * period[2])
            ca = -dt2 * 2.0 * q[a] * src_mass[b] * f[k]
            out[a, 0] += ca * d0
            out[a, 1] += ca * d1
            out[a, 2] += ca * d2
            if half:
                cb = -dt2 * 2.0 * q[b] * mass[a] * f[k]
                out[b, 0] -= cb * d0
                out[b, 1] -= cb * d1
                out[b, 2] -= cb * d2


_background = {}


def correction_loop(it_start, fluid, walls, neighbours, prm, work, partial, last_p, before):
    """stepper.correction_loop's iterations (without the partial iteration), with the background part summed."""
    out = _background["out"]
    it = it_start
    while True:
        summation_density(fluid, walls, neighbours, prm, work)
        emax, emean = compression_error(fluid.rho, prm.rho0)
        if it >= prm.min_iterations and (emean if prm.on_mean else emax) <= prm.tolerance:
            return it, emax, emean, CONVERGED
        if it >= prm.max_iterations:
            return it, emax, emean, CAPPED
        if walls.pos.shape[0] > 0:
            wall_pressure(walls, fluid.pos, work.p, neighbours, prm.h, prm.rho0, prm.kernel)
        pressure_displacement(fluid, walls, neighbours, prm, work)
        background_displacement(fluid.pos, fluid.mass, work.p_over_rho2, neighbours.fluid_start,
                                neighbours.fluid_index, work.f_fluid, fluid.pos, fluid.mass, True, neighbours.period,
                                prm.dt2, out)
        if walls.pos.shape[0] > 0:
            background_displacement(fluid.pos, fluid.mass, work.p_over_rho2, neighbours.wall_start,
                                    neighbours.wall_index, work.f_wall, walls.pos, walls.mass, False,
                                    neighbours.period, prm.dt2, out)
        apply_displacement(fluid.pos, work.disp, fluid.correction_displacement, neighbours.targets_at_build,
                           work.moved2)
        it += 1
        if work.moved2.max() > prm.half_skin * prm.half_skin:
            return it, -1.0, -1.0, NEEDS_REBUILD


def water_pairs(solver):
    """(i, j, W_ij) of the water's pairs (kernel_pairs.py's: an experiment) and each particle's volume m / rho."""
    fl, h = solver.fluid, solver.h
    i, j, d = periodic_pairs(fl.pos, solver.period, solver.box_lo, 2.0 * h)
    w, _ = kernel_and_gradient(d, np.sqrt((d * d).sum(axis=1)), h)
    return i, j, w, fl.mass / fl.rho


def shepard_average(pairs, h, field):
    """Each water particle's kernel average of `field` over the water (`pairs`: water_pairs')."""
    i, j, w, volume = pairs
    num = field * (volume * kernel_w(0.0, h))[:, None]
    den = volume * kernel_w(0.0, h)
    np.add.at(num, i, field[j] * (volume[j] * w)[:, None])
    np.add.at(num, j, field[i] * (volume[i] * w)[:, None])
    np.add.at(den, i, volume[j] * w)
    np.add.at(den, j, volume[i] * w)
    return num / den[:, None]


_step = solver_module.FluidSolver.step


def split_step(self, dt):
    """The solver's step with the background part's share kept out of the velocity (and the rest smoothed)."""
    fl = self.fluid
    out = _background.get("out")
    if out is None or out.shape[0] != fl.count:
        out = _background["out"] = np.zeros((fl.count, 3))
    out[:] = 0.0
    report = _step(self, dt)
    pairs = water_pairs(self) if SMOOTH or FULL else None
    split = kernel_fullness(*pairs, self.h) >= FULL if FULL else slice(None)
    fl.vel[split] -= SHARE * out[split] / dt
    if SMOOTH:
        kept = fl.correction_displacement - SHARE * out
        fl.vel[split] += (SMOOTH * (shepard_average(pairs, self.h, kept) - kept) / dt)[split]
    return report


solver_module.correction_loop = correction_loop
solver_module.FluidSolver.step = split_step
if sys.argv[3].endswith(".yaml"):
    import tempfile

    from sph_fsi_core.run import run_scene
    from sph_fsi_core.scene import load_scene
    with tempfile.TemporaryDirectory() as out_dir:
        summary = run_scene(load_scene(sys.argv[3], ["output.snapshot_interval=0"] + sys.argv[4:]), out_dir=out_dir)
        series = np.genfromtxt(f"{out_dir}/timeseries.csv", delimiter=",", names=True)
    judged = "; ".join(f"{name} {j['measured']:.4g} (error {j['error_signed']:+.4g})" if j.get("measured") is not None
                       else f"{name} -" for name, j in summary["judges"].items())
    every = max(1, round(0.1 / float(series["time"][1] - series["time"][0])))
    energy = " ".join(f"{1e3 * e:.2f}" for e in series["fluid_kinetic_energy"][::every])
    print(f"share {SHARE:g}, smooth {SMOOTH:g}, {sys.argv[3]} {' '.join(sys.argv[4:])}: {judged}; kinetic energy "
          f"[mJ] every 0.1 s: {energy}")
else:
    script = os.path.join(os.path.dirname(os.path.abspath(__file__)), sys.argv[3])
    sys.argv = [script] + sys.argv[4:]
    runpy.run_path(script, run_name="__main__")
