"""The study's experiment on a pressure field solved each step instead of the paper's correction (docs/validation/
OPEN.md 7): does the loss under gravity belong to the correction? It steps the water by the IISPH prototype of
studies/partial_iteration (Ihmsen et al. 2014: relaxed Jacobi on the pressure Poisson equation with the density and
divergence source, warm-started from the last step's pressure; iisph_prototype.patch there, its module taken from
the patch as it stands) in place of FluidSolver.step, for the script it runs:

    python docs/validation/studies/water_lattice/iisph_step.py OMEGA WARM GAMMA SCRIPT [ARGS ...]
    (e.g. 0.15 0.5 1 cell_flow.py 1.5 9.81 0.1; OMEGA the Jacobi relaxation (0.3 diverges on a disordered start),
    WARM the share of the last step's pressure it starts from, GAMMA the density error's share of the source)

The solve stops where the predicted compression is within the script's tolerance, as the correction does.
"""
import importlib.util
import os
import runpy
import sys
import tempfile

import numpy as np

import sph_fsi_core.fluid.solver as solver_module
from sph_fsi_core.fluid.okaji import summation_density, viscous_velocity, wrap_periodic
from sph_fsi_core.fluid.stepper import CAPPED, FluidArrays

HERE = os.path.dirname(os.path.abspath(__file__))
PATCH = os.path.join(HERE, "..", "partial_iteration", "iisph_prototype.patch")


def prototype_module():
    """fluid/iisph.py as the patch adds it, its relative imports made absolute, imported from a temporary file."""
    lines, inside = [], False
    for line in open(PATCH):
        if line.startswith("diff --git"):
            if inside:
                break
            inside = line.rstrip().endswith("sph_fsi_core/fluid/iisph.py")
        elif inside and line.startswith("+") and not line.startswith("+++"):
            lines.append(line[1:])
    source = "".join(lines).replace("from .", "from sph_fsi_core.fluid.").replace(
        "from sph_fsi_core.fluid..numerics", "from sph_fsi_core.numerics").replace(
        "prm.h, prm.rho0)", "prm.h, prm.rho0, prm.kernel)")   # wall_pressure takes the water's kernel since
    path = os.path.join(tempfile.mkdtemp(), "iisph_prototype.py")
    with open(path, "w") as out:
        out.write(source)
    spec = importlib.util.spec_from_file_location("iisph_prototype", path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def install(omega, warm, gamma):
    """Step every FluidSolver by the prototype from now on; returns the list of each step's solve evaluations."""
    iisph, evaluations = prototype_module(), []

    def field_step(self, dt):
        """The prototype's step (its FluidSolver._field_step, fixed walls): the density and the other forces at
        r(t), the pressure that keeps the water at rho0 over the step, then v and r (symplectic Euler)."""
        fl, n = self.fluid, self.fluid.count
        if getattr(self, "_field", None) is None:
            self._field = {"buf": np.zeros((self.buf.shape[0], n, iisph.SETUP_COLUMNS)), "source": np.zeros(n),
                           "diagonal": np.zeros(n), "predicted": np.zeros(n), "scratch": np.zeros(n),
                           "wall_vel": np.zeros_like(self.wall_pos)}
        field, rebuilds = self._field, 0
        if self.fluid_neighbours.is_stale(fl.pos, fl.pos):
            self.rebuild()
            rebuilds += 1
        arrays, walls = FluidArrays.of(fl), self.wall_arrays()
        prm = self.correction_params(0.0, dt)
        neighbours, work = self.neighbours(), self.buffers()
        summation_density(arrays, walls, neighbours, prm, work)
        if self.nu > 0.0:
            viscous_velocity(fl.pos, fl.vel, fl.mass, fl.rho, neighbours, work, self.h, self.nu, dt, self.vel_work)
            fl.vel[:] = self.vel_work
        iisph.add_body_force(fl.vel, *(g * dt for g in self.gravity))
        iisph.poisson_setup(arrays, fl.vel, walls, field["wall_vel"], neighbours, work, self.rho0, dt, gamma,
                            field["buf"], field["source"], field["diagonal"])
        iisph.warm_start(self.p, self.p_over_rho2, fl.rho, fl.pressure, warm)
        field["scratch"][:] = 0.0
        solve_arrays = FluidArrays(fl.pos, fl.mass, fl.rho, field["scratch"], fl.correction_displacement)
        it, emax, emean, status = iisph.pressure_solve(solve_arrays, walls, neighbours, prm, work, field["source"],
                                                       field["diagonal"], field["predicted"], omega)
        fl.pressure[:] = self.p
        fl.correction_displacement[:] = self.disp
        iisph.advance(fl.pos, fl.vel, self.disp, dt, self.pos_old)
        if self.period.any():
            wrap_periodic(fl.pos, self.period, self.box_lo)
        evaluations.append(it)
        return solver_module.StepReport(dt, it, emax, emean, status == CAPPED, rebuilds, 0.0, 0.0)

    solver_module.FluidSolver.step = field_step
    return evaluations


if __name__ == "__main__":
    settings = [float(a) for a in sys.argv[1:4]]
    counted = install(*settings)
    script = os.path.join(HERE, sys.argv[4])
    sys.argv = [script] + sys.argv[5:]
    runpy.run_path(script, run_name="__main__")
    print(f"omega {settings[0]:g}, warm {settings[1]:g}, gamma {settings[2]:g}: {np.mean(counted):.1f} solve "
          "evaluations a step")
