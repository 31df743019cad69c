"""Fluid-structure coupling of Satake et al. sec. 2.3: the elastic solid as a moving wall of the fluid, and the
fluid's push on the solid, by the paper's eqs. (10)-(11) ('seed') or by equal and opposite pressure pair forces
('pressure').

Per fluid step dt (simulation.py drives it):

1. The solid particles are a moving wall of the fluid: they are the solid block of the walls the fluid sums over
   (boundary.Boundary, which puts them where the solid is before each fluid step), with the mass of a
   fluid-lattice wall particle of the same volume, m'_s = rho0_fluid (m_s / rho_s) s_lattice (`wall_mass`;
   s_lattice: numerics/kernels.lattice_density_scale), so a fluid particle next to the solid sees rho0 as next
   to a fixed wall whatever the solid's own density. In eq. (2) a solid particle carries the Shepard average of
   its fluid neighbours' pressure, as a wall particle does (okaji.wall_pressure). The fluid's wall lists are
   rebuilt when the fluid or the solid has moved half the skin since their build (each at most half: pairs never
   move more than the skin closer).
2. The fluid takes its step (gravity, predictor, density correction, eq. (8), (9)) with the solid held where it is.
3. The push on the solid is computed once from the fluid's step and held over the solid's sub-steps:
   - 'seed', eqs. (10)-(11): adot_b = (r_b(t+dt) - r*_b) / dt^2 for every water particle b (what the density
     correction moved it, okaji.apply_displacement's running total). The paper's (10) prints
     r(t+dt) - r(t), but r(t+dt) - r(t) = v dt is the whole motion, so (10) would be v / dt, not an acceleration,
     and a water column at rest on a gate would push it with its own fall; the text says the force is "from the
     local density gradient applied while correcting positions", which is r(t+dt) - r* (METHOD.md sec. 3, Open).
     For each solid surface particle a with outward normal n_a:
         alpha_a = gamma sum_b (m_b / rho_b) (adot_b . n_a) W_ab (-n_a),         (11)
     gamma = coupling.gamma (the paper: 10). Interior solid particles get nothing. It is not momentum-conserving
     (gamma is a tuning factor); and adot is the water particle's NET correction acceleration, which at rest only
     balances gravity: a column at rest presses on a vertical gate with little more than its noise
     (docs/method.md, coupling).
   - 'pressure': the fluid pressure P (the step's summed correction pressure, okaji.correction_pressure, the
     pressure that held the fluid incompressible over the step, about rho g depth at rest) acts on every solid
     particle s through the same pair term the fluid feels from it in eq. (2):
         F_{s<-a} = m_a m'_s (P_a + P_s) / rho0^2 grad_a W_as = -F_{a<-s},         acc_s = sum_a F_{s<-a} / m_s
     with P_s the Shepard average of the neighbours' P (as in the fluid's wall term) and rho0 for both densities.
     Pair by pair equal and opposite: momentum is conserved (test_coupling.py sums the pairs).
4. The solid takes n sub-steps of dt / n with the push as an external acceleration, n = ceil(dt / dt_solid)
   from the two stable steps (the paper's 200 is what its material gives), or coupling.substeps when set and
   stable; with coupling.push_ramp the push goes linearly from the last step's to this one's over them
   (solid/phase.py), for a stiff solid whose mode a held push's staircase would ring.

Surface particles and normals (the paper does not say how it finds them): from the particle distribution, g_a = -sum_b
V_b grad_a W_ab over the solid's own particles (clamp included; the cubic spline at the solid's own h,
solid.smoothing_ratio) vanishes inside the body and points out of it at a surface (|g| h = 0.59 at a flat face of a
cubic lattice at h = 1.3 dp, 0.06 one layer in, 0 deeper); a particle with |g_a| h > coupling.surface_threshold (0.4)
is a surface particle, n_a = g_a / |g_a|. The set is found once at build (an elastic body keeps its surface
particles); the normals are recomputed from the current positions before every push, so they turn with the body as
it bends (no separate rotation to track). Every pair of a water and a solid particle takes the water's kernel and h.
"""
import math

import numpy as np

from .forces import (pressure_pair_forces, seed_push, shepard_pressure, solid_wall_mass, surface_gradient,
                     surface_normals)
from ..fluid.stepper import FluidArrays
from ..numerics.kernels import CUBIC_SPLINE, SUPPORT_RADIUS_IN_H
from ..numerics.neighbours import NeighbourList

MODELS = ("seed", "pressure")


class Coupling:
    """The coupling's state: the solid's mass as the water's wall, its surface set and normals, the push and its
    mean over an outer step. Exists only when a scene has both a solid and a fluid (simulation.py).
    """

    def __init__(self, solid, fluid, h, period, fluid_rho0, lattice_scale, model="seed", gamma=10.0,
                 substeps=0, relaxation=1.0, surface_threshold=0.4, skin=None, box_lo=None, box_hi=None,
                 kernel=CUBIC_SPLINE, solid_h=None, ramp=False):
        if model not in MODELS:
            raise ValueError(f"coupling.model = {model!r}; allowed: one of {', '.join(MODELS)}")
        self.solid, self.fluid = solid, fluid
        self.h = float(h)             # the water's: every pair of a water and a solid particle
        self.kernel = int(kernel)     # the water's (fluid.kernel); the solid's surface is found with the spline
        self.solid_h = self.h if solid_h is None else float(solid_h)   # the solid's own, for its surface
        self.period = np.asarray(period, dtype=np.float64)
        self.rho0 = float(fluid_rho0)
        self.push_start = None        # with coupling.push_ramp: the push the ramp starts from (the last step's)
        self.pushes = 0               # fluid steps pushed so far: the first has no push before it to ramp from
        self._ramped = False          # whether the last push ramps (push_start then holds where from)
        self.configure(model, gamma, substeps, relaxation, ramp)
        self.volume = solid.mass / solid.rho                       # initial volumes m / rho0_s
        self.wall_mass = solid_wall_mass(solid.mass, solid.rho, self.rho0, lattice_scale)
        self.solid_p = np.zeros(solid.count)
        self.acc = np.zeros((solid.count, 3))
        self.force = np.zeros((solid.count, 3))
        self.gradient = np.zeros((solid.count, 3))
        skin = 0.1 * self.h if skin is None else float(skin)
        self._list_args = (SUPPORT_RADIUS_IN_H * self.h, skin, self.period, box_lo, box_hi)
        solid_skin = skin if self.solid_h == self.h else skin * self.solid_h / self.h     # the same share of h
        self.solid_neighbours = NeighbourList(SUPPORT_RADIUS_IN_H * self.solid_h, solid_skin, period=self.period,
                                              box_lo=box_lo, box_hi=box_hi)
        self.fluid_neighbours = NeighbourList(SUPPORT_RADIUS_IN_H * self.h, skin, period=self.period,
                                              box_lo=box_lo, box_hi=box_hi)   # solid targets, fluid sources
        self.solid_neighbours.build(solid.pos, solid.pos)
        surface_gradient(solid.pos, self.volume, self.solid_neighbours.start, self.solid_neighbours.index,
                         self.period, self.solid_h, self.gradient)
        self.surface = np.sqrt((self.gradient ** 2).sum(axis=1)) * self.solid_h > surface_threshold
        if solid.surface_normal is None or len(solid.surface_normal) != solid.count:
            solid.surface_normal = np.zeros((solid.count, 3))
        surface_normals(self.gradient, self.surface, solid.surface_normal)
        self.last_substeps = 0
        self._forced_warned = False
        # each fluid step's push (N) held over its sub-steps, summed over an outer step with the steps' lengths
        self._push_sum, self._push_time, self.mean_push = np.zeros(3), 0.0, np.zeros(3)

    def configure(self, model, gamma, substeps, relaxation=1.0, ramp=False):
        if model not in MODELS:
            raise ValueError(f"coupling.model = {model!r}; allowed: one of {', '.join(MODELS)}")
        if not 0.0 < relaxation <= 1.0:
            raise ValueError(f"coupling.relaxation = {relaxation!r}; allowed: (0, 1]")
        self.model, self.gamma, self.forced_substeps = model, float(gamma), int(substeps)
        if getattr(self, "relaxation", None) != float(relaxation):
            self.previous_acc = None      # a push held under another setting is not this one's to blend with
        self.relaxation = float(relaxation)
        self.ramp = bool(ramp)

    @property
    def surface_count(self):
        return int(self.surface.sum())

    def refresh_normals(self):
        s = self.solid
        nb = self.solid_neighbours
        nb.update(s.pos, s.pos)
        surface_gradient(s.pos, self.volume, nb.start, nb.index, self.period, self.solid_h, self.gradient)
        surface_normals(self.gradient, self.surface, s.surface_normal)

    def push(self, dt):
        """The solid's external acceleration from the fluid step just taken, held over the sub-steps; with
        coupling.push_ramp ramped to from the last step's push, which this keeps in `push_start` (ramp_start(): None
        at the first step, which is held)."""
        s, f = self.solid, self.fluid
        self._ramped = self.ramp and self.pushes > 0
        if self._ramped:
            if self.push_start is None:
                self.push_start = np.zeros_like(self.acc)
            self.push_start[:] = self.acc
        if self.model == "seed":
            pos = s.pos
            nb = self.fluid_neighbours
            nb.update(pos, f.pos)
            self.refresh_normals()
            seed_push(pos, s.surface_normal, self.surface, s.movable, nb.start, nb.index, FluidArrays.of(f),
                      1.0 / (dt * dt), self.period, self.h, self.kernel, self.gamma, self.acc)
        else:
            self.pressure_forces()
            self.acc[:] = self.force / s.mass[:, None]
            self.acc[~s.movable] = 0.0
        self._relax_push()
        felt = self.acc if self.ramp_start() is None else 0.5 * (self.acc + self.push_start)   # over the step
        self._push_sum += dt * (s.mass @ felt)
        self._push_time += dt
        self.pushes += 1
        return self.acc

    def ramp_start(self):
        """The push the solid's sub-steps ramp from to the one just computed (coupling.push_ramp), or None: held."""
        return self.push_start if self._ramped else None

    def end_interval(self):
        """The push on the solid averaged over the outer step just taken (`mean_push`, N), each fluid step's held
        over its sub-steps: the last step's alone misread the load where steps alternate (Antoci's gate at rest at a
        0.5 ms fluid step: a third of the steps need no correction and push nothing, and the samples read 17 %
        short)."""
        self.mean_push = self._push_sum / self._push_time
        self._push_sum, self._push_time = np.zeros(3), 0.0

    def _relax_push(self):
        """coupling.relaxation: the push held is w a_new + (1 - w) a_held (the first one as it is). A staggered
        push answers the solid's motion of the step before: under a fluid of added mass m_a a solid of mass m_s
        alternates step to step by -m_a / m_s (the added-mass instability); relaxed, by (1 - w) - w m_a / m_s,
        below 1 in size when w < 2 / (1 + m_a / m_s). A fixed point (a static load) is unchanged."""
        w = self.relaxation
        if w < 1.0:
            if self.previous_acc is None:
                self.previous_acc = self.acc.copy()
            else:
                self.acc *= w
                self.acc += (1.0 - w) * self.previous_acc
                self.previous_acc[:] = self.acc

    def pressure_forces(self):
        """'pressure' model: P_s and the forces on the solid particles (self.force, N) from the fluid's current P."""
        s, f = self.solid, self.fluid
        nb = self.fluid_neighbours
        pos = s.pos
        nb.update(pos, f.pos)
        shepard_pressure(pos, nb.start, nb.index, f.pos, f.pressure, self.period, self.h, self.kernel, self.solid_p)
        pressure_pair_forces(pos, self.wall_mass, self.solid_p, nb.start, nb.index, f.pos, f.mass, f.pressure,
                             self.period, self.h, self.kernel, self.rho0, self.force)
        return self.force

    def fluid_side_forces(self):
        """'pressure' model bookkeeping: the forces of the same pairs on the fluid particles (N_fluid, 3), from a
        fluid->solid list of their own (call pressure_forces() first for P_s)."""
        f, s = self.fluid, self.solid
        radius, skin, period, lo, hi = self._list_args
        nb = NeighbourList(radius, skin, period=period, box_lo=lo, box_hi=hi)
        pos = s.pos
        nb.build(f.pos, pos)
        out = np.zeros((f.count, 3))
        pressure_pair_forces(f.pos, f.mass, f.pressure, nb.start, nb.index, pos, self.wall_mass, self.solid_p,
                             self.period, self.h, self.kernel, self.rho0, out)
        return out

    def substeps(self, fluid_dt, solid_dt_limit):
        """Solid sub-steps per fluid step: ceil(dt_fluid / dt_solid) from the stable steps, or the forced ratio
        when it is stable (else the automatic one, with a warning returned once)."""
        auto = max(1, math.ceil(fluid_dt / solid_dt_limit * (1.0 - 1e-12)))
        warning = None
        n = auto
        if self.forced_substeps > 0:
            if self.forced_substeps >= auto:
                n = self.forced_substeps
            elif not self._forced_warned:
                self._forced_warned = True
                warning = (f"coupling.substeps = {self.forced_substeps}: solid step dt_fluid / n above the solid's "
                           f"stable limit (needs at least {auto}); using {auto} while it does")
        self.last_substeps = n
        return n, warning
