"""The fluid step of Satake et al. sec. 2.2 (Okaji 2002): gravity, predictor (6), density correction, (8), (9).

One step of size dt:

    v += g dt;  r* = r + v dt                                        (body force, eq. (6))
    repeat:  rho from eq. (1) at r*;  stop if converged (below);
             p = c^2 (rho - rho0)_+  (7);  r* += dt^2 dv/dt of eq. (2)    (one correction iteration)
    r(t+dt) = r*;  v* = (r(t+dt) - r(t)) / dt                          (eq. (8))
    v = v* + dt (viscous term of eq. (9), Morris form)
    r(t+dt) += the shift towards an even arrangement (fluid.shifting > 0 only; fluid/shifting.py)

Convergence: the compression (rho - rho0)_+ / rho0 is measured as its maximum and its mean over the fluid; the
one named by fluid.tolerance_on must be at most fluid.density_tolerance (the paper: 1 %), after at least
fluid.min_iterations corrections. A step that reaches fluid.max_iterations stops there and is counted and
reported (`capped`), never silently accepted. With fluid.partial_iteration the iteration that takes the compression
below the tolerance is taken only in the part that brings it to the tolerance (stepper.correction_loop), so a
step's work changes continuously with the state instead of by whole iterations.

The correction coefficient c: one iteration moves a particle by dt^2 c^2 (grad rho)/rho^2 ~ (c dt / h)^2 h
times its relative compression, so what sets the iteration's stability and speed is kappa = c dt / h, not c.
fluid.correction_coefficient = 0 (the default) takes c = kappa h / dt with kappa = fluid.correction_kappa, so the
iteration behaves the same at any dt; a positive value fixes c in m/s (then a large dt can make it unstable).

Neighbour lists (numerics/neighbours.py): fluid-fluid (half: each pair once), fluid-wall, and wall-fluid (for the wall
pressure; only wall particles within reach of the water's bounding box), cutoff 2h + skin, built at r* when some
particle has moved more than half the skin since the last build and reused by every iteration of the step (and by
later steps while valid); every position correction measures how far particles have moved since the build, and the
loop returns for a rebuild mid-step if one may have crossed half the skin.

Pressure output: FluidState.pressure is the sum of the step's iteration pressures (fluid/okaji.py's docstring).
"""
import math
from typing import NamedTuple

import numba
import numpy as np

from .energy import mechanical_energy
from .okaji import (FLUID_BLOCK_COLUMNS, compression_error, gravity_and_predictor, summation_density,
                    velocity_from_displacement, viscous_velocity, wall_pressure, wrap_periodic)
from .shifting import concentration, shift_positions, surface_neighbours
from .stepper import (CAPPED, NEEDS_REBUILD, CorrectionParams, FluidArrays, FluidBuffers, FluidNeighbours,
                      FluidWalls, correction_loop)
from .wall_forces import wall_group_forces
from ..numerics.kernels import CUBIC_SPLINE, SUPPORT_RADIUS_IN_H
from ..numerics.neighbours import INDEX_DTYPE, NeighbourList, inside_box, named_in, position_bounds
from ..numerics.pair_blocks import block_scratch


class StepReport(NamedTuple):
    """What one fluid step did: correction iterations, final compression (max, mean), whether it hit the cap, and
    the mechanical energy (kinetic and potential, J) the step took from the water: by the predictor, the correction
    and eq. (8) together (`correction_loss`: what the walls' and the water's own incompressibility took, with the
    time integration's error), and by the viscous term (`viscous_loss`)."""
    dt: float
    iterations: int
    error_max: float
    error_mean: float
    capped: bool
    rebuilds: int
    correction_loss: float = 0.0
    viscous_loss: float = 0.0
    shifting_loss: float = 0.0    # J, the potential energy the shift took (fluid.shifting; it keeps the velocities)


class FluidSolver:
    """The fluid's work arrays, neighbour lists and settings; `step(dt)` advances the fluid by one step."""

    def __init__(self, fluid, walls, h, period, box_lo, box_hi, skin, kernel=CUBIC_SPLINE):
        self.fluid = fluid
        self.walls = walls
        self.h = float(h)
        self.kernel = int(kernel)     # numerics/kernels.py's id (fluid.kernel)
        self.period = np.asarray(period, dtype=np.float64)
        self.box_lo = np.asarray(box_lo if box_lo is not None else np.zeros(3), dtype=np.float64)
        n = fluid.count
        radius = SUPPORT_RADIUS_IN_H * self.h
        self.skin = float(skin)
        # half list: each fluid pair once (fluid/okaji.py), which halves the pair work of every pass and the build
        self.fluid_neighbours = NeighbourList(radius, skin, period=period, box_lo=box_lo, box_hi=box_hi, half=True)
        self.xz_periodic = self.fluid_neighbours.xz_periodic   # the passes' (periodic.xz_periodic_marker)
        # the fixed walls' grid is made once (with a solid in the boundary it moves and is remade)
        self.wall_neighbours = NeighbourList(radius, skin, period=period, box_lo=box_lo, box_hi=box_hi,
                                             keep_grid_while_sources_stay=True)
        self.wall_fluid_neighbours = NeighbourList(radius, skin, period=period, box_lo=box_lo, box_hi=box_hi)
        self.wall_pos = walls.pos if walls is not None else np.zeros((0, 3))
        self.wall_mass = walls.mass if walls is not None else np.zeros(0)
        self.wall_p_over_rho2 = np.zeros(len(self.wall_mass))
        self.active_walls = np.zeros(0, dtype=np.int64)
        self._no_walls_start = np.zeros(n + 1, dtype=np.int64)
        self._no_walls_index = np.zeros(0, dtype=INDEX_DTYPE)
        self.pos_old = np.zeros((n, 3))
        self.disp = np.zeros((n, 3))
        self.p = np.zeros(n)
        self.p_over_rho2 = np.zeros(n)
        self.vel_work = np.zeros((n, 3))
        self.moved2 = np.zeros(n)
        self.buf = np.zeros((max(numba.get_num_threads(), 1), n, 3))   # per-chunk pair accumulators
        self.density_buf = np.zeros(self.buf.shape[:2])   # per-chunk density sums
        self.blocks = block_scratch(self.buf.shape[0], FLUID_BLOCK_COLUMNS)   # per-chunk pair blocks
        self.f_fluid = np.zeros(0)
        self.f_wall = np.zeros(0)
        self.builds = 0
        # settings (configure())
        self.rho0 = 1000.0
        self.nu = 1.0e-6
        self.gravity = (0.0, 0.0, 0.0)
        self.tolerance = 0.01
        self.on_mean = False
        self.coefficient = 0.0
        self.kappa = 1.0
        self.min_iterations = 1
        self.max_iterations = 100
        self.partial = False
        self.last_p = np.zeros(n)          # the last iteration's pressures (fluid.partial_iteration)
        self.error_before = np.zeros(2)    # and the (max, mean) compression before it
        self.shifting = 0.0                # fluid.shifting's A (0: none)
        self.shift_own_speed = False
        self.spacing = self.h
        self.shift_work = None             # (conc, grad, surface count, squared move), made at the first shift
        self.rebuild()
        self.density()

    def configure(self, rho0, nu, gravity, tolerance, tolerance_on, coefficient, kappa, min_iterations,
                  max_iterations, partial=False, shifting=0.0, shifting_speed="largest", spacing=None):
        self.partial = bool(partial)
        self.shifting, self.shift_own_speed = float(shifting), shifting_speed == "own"
        self.spacing = float(spacing) if spacing is not None else self.h
        self.rho0, self.nu = float(rho0), float(nu)
        self.gravity = tuple(float(g) for g in gravity)
        self.tolerance = float(tolerance)
        self.on_mean = tolerance_on == "mean"
        self.coefficient, self.kappa = float(coefficient), float(kappa)
        self.min_iterations, self.max_iterations = int(min_iterations), int(max_iterations)

    # ---- neighbour lists -------------------------------------------------------------------------------
    def rebuild(self):
        pos = self.fluid.pos
        self.fluid_neighbours.build(pos, pos)
        self.crossing = self.fluid_neighbours.crossing
        self.wall_crossing = np.zeros(0, dtype=np.bool_)
        if len(self.f_fluid) < self.fluid_neighbours.pairs:
            self.f_fluid = np.zeros(int(1.25 * self.fluid_neighbours.pairs) + 16)
        if self.walls is not None:
            # Only wall particles within the cutoff of the water's bounding box can have fluid neighbours; the
            # others would be clamped into the grid's edge cells and scan them for nothing.
            reach = self.wall_fluid_neighbours.cutoff
            lo, hi = position_bounds(pos)
            lo -= reach
            hi += reach
            for k in range(3):
                if self.period[k] > 0.0:
                    lo[k], hi[k] = -np.inf, np.inf
            self.active_walls = inside_box(self.wall_pos, lo, hi)
            # the fluid's grid, just made by the half list's build
            self.wall_fluid_neighbours.build(np.ascontiguousarray(self.wall_pos[self.active_walls]), pos,
                                             grid=self.fluid_neighbours.grid)
            # The fluid->wall list holds the same pairs as the wall->fluid one, seen from the fluid (the cutoff test
            # is symmetric to the bit): only the fluid particles that list names can have a wall neighbour, so only
            # they are scanned (at 10^5 fluid particles in the dam break, 1 in 6; 17 of a 93 ms rebuild before).
            self.wall_neighbours.build(pos, self.wall_pos,
                                       scanned=named_in(self.wall_fluid_neighbours.index, len(pos)))
            # a fluid target's rows: fluid and wall (numerics.neighbours.NeighbourList.crossing)
            self.crossing = self.fluid_neighbours.crossing | self.wall_neighbours.crossing
            self.wall_crossing = self.wall_fluid_neighbours.crossing
            self.wall_p_over_rho2[:] = 0.0
            if len(self.f_wall) < self.wall_neighbours.pairs:
                self.f_wall = np.zeros(int(1.25 * self.wall_neighbours.pairs) + 16)
        self.builds += 1

    def refresh_wall_lists(self):
        """New lists once the water or a wall particle (a moving part's, the solid's in a coupled scene) has moved
        half the skin since the build; the lists compare wall positions to the bit."""
        if self.wall_neighbours.is_stale(self.fluid.pos, self.wall_pos):
            self.rebuild()

    def _wall_rows(self):
        """(fluid->wall start, index, wall->fluid start, index); empty rows when the scene has no walls."""
        if self.walls is None:
            return self._no_walls_start, self._no_walls_index, np.zeros(1, dtype=np.int64), self._no_walls_index
        return (self.wall_neighbours.start, self.wall_neighbours.index, self.wall_fluid_neighbours.start,
                self.wall_fluid_neighbours.index)

    def neighbours(self):
        """The lists as the correction loop takes them (replaced by every rebuild)."""
        nb = self.fluid_neighbours
        wstart, windex, wfstart, wfindex = self._wall_rows()
        return FluidNeighbours(nb.start, nb.index, wstart, windex, self.active_walls, wfstart, wfindex, self.crossing,
                               self.wall_crossing, nb.targets_at_build, self.period, self.xz_periodic)

    def buffers(self):
        """The work arrays as the correction loop takes them (the pair caches may be replaced by a rebuild)."""
        return FluidBuffers(self.p, self.p_over_rho2, self.f_fluid, self.f_wall, self.disp, self.moved2, self.buf,
                            self.density_buf, self.blocks)

    def wall_arrays(self, p_over_rho2=None):
        """The wall rows as the passes take them, with the solver's wall pressures or `p_over_rho2`."""
        return FluidWalls(self.wall_pos, self.wall_mass, self.wall_p_over_rho2 if p_over_rho2 is None else p_over_rho2)

    def correction_params(self, c, dt):
        """The correction's numbers for a step of `dt` at eq. (7)'s `c` (correction_c)."""
        return CorrectionParams(self.h, self.rho0, c * c, dt * dt, self.tolerance, self.on_mean, self.min_iterations,
                                self.max_iterations, 0.5 * self.skin, self.kernel)

    def density(self):
        """Eq. (1) at the current positions (lists must be valid); returns (max, mean) compression."""
        fl = self.fluid
        summation_density(FluidArrays.of(fl), self.wall_arrays(), self.neighbours(), self.correction_params(0.0, 0.0),
                          self.buffers())
        return compression_error(fl.rho, self.rho0)

    # ---- time step ---------------------------------------------------------------------------------------
    def max_speed(self):
        v = self.fluid.vel
        return float(np.sqrt((v * v).sum(axis=1).max())) if len(v) else 0.0

    def stable_dt(self, cfl, nu=None, gravity=None):
        """min of: cfl h / |v|max (advection), cfl sqrt(h / |g|) (body force), 0.125 h^2 / nu (viscous diffusion,
        Morris et al. 1997). At rest only the last two bound it. `nu`, `gravity`: other settings than the solver's
        (a change being checked before it is applied)."""
        nu = self.nu if nu is None else nu
        gravity = self.gravity if gravity is None else gravity
        limits = [0.125 * self.h * self.h / nu]
        g = math.sqrt(sum(x * x for x in gravity))
        if g > 0.0:
            limits.append(cfl * math.sqrt(self.h / g))
        vmax = self.max_speed()
        if vmax > 0.0:
            limits.append(cfl * self.h / vmax)
        return min(limits)

    def wall_forces(self, group, count):
        """(count, 3) N: the water's push on groups of wall particles (group: (walls,) int64, each wall particle's
        group, -1 for none) from the last step's pressures at the current positions (fluid/wall_forces.py)."""
        fl = self.fluid
        walls = self.wall_arrays(np.zeros(len(self.wall_mass)))
        neighbours = self.neighbours()
        if len(self.active_walls):
            wall_pressure(walls, fl.pos, fl.pressure, neighbours, self.h, self.rho0, self.kernel)
        return wall_group_forces(FluidArrays.of(fl), walls, np.ascontiguousarray(group, dtype=np.int64), neighbours,
                                 self.h, self.kernel, int(count), np.zeros((self.buf.shape[0], int(count), 3)))

    def correction_c(self, dt):
        """c of eq. (7): fluid.correction_coefficient, or kappa h / dt when that is 0 (module docstring)."""
        return self.coefficient if self.coefficient > 0.0 else self.kappa * self.h / dt

    # ---- one step ----------------------------------------------------------------------------------------
    def step(self, dt):
        fl = self.fluid
        gx, gy, gz = self.gravity
        energy_before = sum(mechanical_energy(fl.pos, fl.vel, fl.mass, gx, gy, gz))
        gravity_and_predictor(fl.pos, fl.vel, dt, gx, gy, gz, self.pos_old)
        fl.correction_displacement[:] = 0.0
        fl.pressure[:] = 0.0
        c = self.correction_c(dt)
        arrays = FluidArrays.of(fl)
        walls = self.wall_arrays()
        prm = self.correction_params(c, dt)
        it, rebuilds = 0, 0
        self.error_before[:] = -1.0
        while True:
            if self.fluid_neighbours.is_stale(fl.pos, fl.pos):
                self.rebuild()
                rebuilds += 1
            # a rebuild replaces the lists and may replace the pair caches: taken anew each call
            it, emax, emean, status = correction_loop(it, arrays, walls, self.neighbours(), prm, self.buffers(),
                                                      self.partial, self.last_p, self.error_before)
            if status != NEEDS_REBUILD:
                break
            if rebuilds > self.max_iterations + 2:   # cannot happen unless particles fly: let the watchdog see it
                break
            self.rebuild()
            rebuilds += 1
        velocity_from_displacement(fl.pos, self.pos_old, dt, fl.vel)
        kinetic, potential = mechanical_energy(fl.pos, fl.vel, fl.mass, gx, gy, gz)
        viscous_loss = 0.0
        if self.nu > 0.0:
            viscous_velocity(fl.pos, fl.vel, fl.mass, fl.rho, self.neighbours(), self.buffers(), self.h, self.nu, dt,
                             self.vel_work)
            fl.vel[:] = self.vel_work
            viscous_loss = kinetic - mechanical_energy(fl.pos, fl.vel, fl.mass, gx, gy, gz)[0]
        shifting_loss = 0.0
        if self.shifting > 0.0:
            self.shift(dt)
            shifting_loss = potential - mechanical_energy(fl.pos, fl.vel, fl.mass, gx, gy, gz)[1]
        if self.period.any():
            wrap_periodic(fl.pos, self.period, self.box_lo)
        return StepReport(dt, it, emax, emean, status == CAPPED, rebuilds, energy_before - kinetic - potential,
                          viscous_loss, shifting_loss)

    def shift(self, dt):
        """The step's shift (fluid/shifting.py) over the lists the step left (valid at its positions); returns the
        largest move (m)."""
        fl = self.fluid
        n = len(fl.pos)
        if self.shift_work is None:
            self.shift_work = (np.zeros(n), np.zeros((n, 3)), np.zeros(n), np.zeros(n))
        conc, grad, surface, moved2 = self.shift_work
        neighbours = self.neighbours()
        concentration(fl.pos, fl.mass, self.wall_pos, self.wall_mass, neighbours, self.h, self.rho0, self.spacing,
                      self.kernel, self.density_buf, self.buf, conc, grad)
        surface_neighbours(fl.pos, conc, neighbours, self.h, self.density_buf, surface)
        return shift_positions(fl.pos, fl.vel, conc, grad, surface, self.shifting, self.h, dt, self.shift_own_speed,
                               moved2)
