"""Probes: what a scene measures at named places, read from the state after each step (docs/method.md, "Probes").

A probe has a name, a kind and its time-series columns:

    displacement  `<name>_dx, _dy, _dz` m: the mean displacement of a group of particles (the built-in scenes' 'tip')
    point         `<name>_dx, _dy, _dz` m and `<name>_vx, _vy, _vz` m/s: the solid's material point nearest to the
                  probe's position when built (its particle's displacement and velocity)
    pressure      `<name>` Pa: the water's pressure at a point on a wall, p = sum_b V_b p_b W(x - x_b) / sum_b V_b W
                  over the water within reach (2h) of the point (Shepard's average; 0 when no water is within
                  reach), each fluid step's averaged over the outer step, weighted by the steps' lengths; a probe on
                  a moving wall (its `part`) rides with it; with an `inset` the point is that far into the water along
                  the wall's normal (scenes/geometry.py places it). W is the probe's own kernel and h where it has
                  them (its kernel, smoothing_ratio), else the water's
    water_height  `<name>` m: the free surface's height above the probe's position along z: up the vertical line
                  through (x, y) from the position, the first point where the water and the walls stop filling half
                  the kernel, sum_b V_b W(x - x_b) < 1/2 over water and wall particles (the walls count as filled,
                  so the line starts full at a floor), less the position's z; 0 when the line is not filled there.
                  The column standing on the floor, as a wave gauge is wetted: a jet or spray above air is not
                  counted. With a span (span_x, span_y), the mean over a grid of such lines covering the rectangle;
                  W as a pressure probe's
    force         `<name>_fx, _fy, _fz` N: the water's force on a part: on a wall, the pressure pair forces of the
                  fluid step's correction (its accumulated pressures at its end positions, fluid.solver
                  FluidSolver.wall_forces); on a solid, the coupling's push on the part's particles; each fluid
                  step's averaged over the outer step

Probes only read the state; Simulation calls `after_fluid_step` after each fluid step (the interval averages) and
`read` once per outer step, and every output (timeseries.csv, the node's topics, MCAP, Rerun) reports `read`'s
values.
"""
import math
from dataclasses import dataclass

import numpy as np
from numba import njit, prange

from .numerics.kernels import SUPPORT_RADIUS_IN_H, kernel_w

KINDS = ("displacement", "point", "pressure", "water_height", "force")
# water_height: the line is sampled at this fraction of a spacing
HEIGHT_SAMPLES_PER_SPACING = 4
# a line is filled where the kernel sum of the particles' volumes reaches this (a flat free surface: 1/2)
FILLED = 0.5


@dataclass
class ProbeSpec:
    """A probe as a scene builds it (scenes/geometry.py): `point` has its solid particle `index` and that particle's
    `reference_position`; `pressure` and `water_height` their `position` (a pressure probe on a moving wall its
    `part`, which carries it); `force` the `part` it measures (by name),
    its `phase` ('walls', 'gate' or 'solid') and its `indices` in that phase's particles."""
    name: str
    kind: str
    position: np.ndarray = None
    index: int = -1
    reference_position: np.ndarray = None
    phase: str = ""
    indices: np.ndarray = None
    part: str = ""
    span: tuple = (0.0, 0.0)      # water_height: the rectangle (x, y) its lines cover (0, 0: one line)
    h: float = 0.0                # pressure, water_height: its own smoothing length, m (0: the water's)
    kernel: int = -1              # pressure, water_height: its own kernel, numerics/kernels.py's id (-1: the water's)


@njit(cache=True, fastmath=False, error_model="numpy", parallel=True, nogil=True)
def shepard_pressure(points, pos, mass, rho, pressure, h, kernel):
    """Shepard's average of the particles' pressure at each point (P, 3): sum_b V_b p_b W_b / sum_b V_b W_b over the
    particles within 2h, V_b = m_b / rho_b, W the water's kernel (`kernel`: numerics/kernels.py's id); 0 where none
    is (docs/method.md, "Probes")."""
    out = np.zeros(points.shape[0])
    reach2 = (SUPPORT_RADIUS_IN_H * h) ** 2
    for i in prange(points.shape[0]):
        num, den = 0.0, 0.0
        px, py, pz = points[i, 0], points[i, 1], points[i, 2]
        for b in range(pos.shape[0]):
            dx, dy, dz = pos[b, 0] - px, pos[b, 1] - py, pos[b, 2] - pz
            r2 = dx * dx + dy * dy + dz * dz
            if r2 < reach2:
                w = mass[b] / rho[b] * kernel_w(math.sqrt(r2), h, kernel)
                num += w * pressure[b]
                den += w
        out[i] = num / den if den > 0.0 else 0.0
    return out


@njit(cache=True, fastmath=False, error_model="numpy", nogil=True)
def _line_fill(z, x, y, pos, volume, near, h, kernel):
    """sum_b V_b W(|(x, y, z) - x_b|) over the particles `near`."""
    fill = 0.0
    for b in near:
        dx, dy, dz = pos[b, 0] - x, pos[b, 1] - y, pos[b, 2] - z
        fill += volume[b] * kernel_w(math.sqrt(dx * dx + dy * dy + dz * dz), h, kernel)
    return fill


@njit(cache=True, fastmath=False, error_model="numpy", nogil=True)
def _near_line(x, y, pos, reach):
    """Indices of the particles within `reach` of the vertical line through (x, y)."""
    keep = np.zeros(pos.shape[0], dtype=np.bool_)
    reach2 = reach * reach
    for b in range(pos.shape[0]):
        dx, dy = pos[b, 0] - x, pos[b, 1] - y
        keep[b] = dx * dx + dy * dy < reach2
    return np.flatnonzero(keep)


@njit(cache=True, fastmath=False, error_model="numpy", nogil=True)
def surface_height(x, y, z0, water_pos, water_volume, wall_pos, wall_volume, h, kernel, step):
    """Up the vertical line through (x, y) from z0: where the water and the walls stop filling the kernel, the first
    z at which sum_b V_b W(x - x_b) falls below FILLED (linear between samples `step` apart), less z0; 0 where the
    line is not filled at z0 (module docstring). The column standing on z0, as a wave gauge's wire is wetted from
    the floor: spray or a jet flying above it does not count."""
    reach = SUPPORT_RADIUS_IN_H * h
    water = _near_line(x, y, water_pos, reach)
    walls = _near_line(x, y, wall_pos, reach)
    top = z0
    for b in water:
        top = max(top, water_pos[b, 2] + reach)
    previous = 0.0
    n = int(math.ceil((top - z0) / step)) + 1
    for k in range(n):
        z = z0 + k * step
        fill = (_line_fill(z, x, y, water_pos, water_volume, water, h, kernel)
                + _line_fill(z, x, y, wall_pos, wall_volume, walls, h, kernel))
        if fill < FILLED:
            return 0.0 if k == 0 else (k - 1) * step + step * (previous - FILLED) / (previous - fill)
        previous = fill
    return (n - 1) * step


class ProbeSet:
    """A scene's probes (Built.probes: state.Probe groups and geometry probe specs), read together."""

    def __init__(self, probes):
        self.order = []             # (name, kind) in the scene's order
        self.groups = []            # state.Probe of the 'displacement' kind
        self.points = []            # (name, solid index, reference position)
        self.pressure = []          # (name, position)
        self.heights = []           # (name, position)
        self.forces = []            # (name, phase, indices into that phase's particles)
        for probe in probes:
            kind = getattr(probe, "kind", "displacement")
            self.order.append((probe.name, kind))
            {"displacement": self.groups, "point": self.points, "pressure": self.pressure,
             "water_height": self.heights, "force": self.forces}[kind].append(probe)
        self._pressure_points = np.array([p.position for p in self.pressure], dtype=np.float64).reshape(-1, 3)
        # the pressure probes by their kernel and h ((0.0, -1): the water's), each group read in one pass
        kernels = [(p.h, p.kernel) for p in self.pressure]
        self._pressure_groups = [(np.array([k for k, own in enumerate(kernels) if own == key]), key)
                                 for key in dict.fromkeys(kernels)]
        self._riding = [(k, p.part) for k, p in enumerate(self.pressure) if p.part]   # on a moving wall
        self._pressure_mean = IntervalMean(len(self.pressure))
        self._force_mean = IntervalMean((len(self.forces), 3))
        self._wall_groups = None

    def averaged(self):
        """Whether some probe averages over each outer step's fluid steps (Simulation calls after_fluid_step)."""
        return bool(self.pressure or self.forces)

    def after_fluid_step(self, sim, dt):
        """The pressure and force probes' values after a fluid step of `dt`, into their outer step's means."""
        if self.pressure:
            f = sim.fluid
            points = self._points_now(sim)
            values = np.empty(len(points))
            for rows, own in self._pressure_groups:
                values[rows] = shepard_pressure(points[rows], f.pos, f.mass, f.rho, f.pressure, *_kernel_of(own, sim))
            self._pressure_mean.add(values, dt)
        if self.forces:
            self._force_mean.add(self._forces(sim), dt)

    def _points_now(self, sim):
        """The pressure probes' points, those on a moving wall carried with it (boundary.Boundary.carried)."""
        if not self._riding:
            return self._pressure_points
        points = self._pressure_points.copy()
        for k, part in self._riding:
            points[k] = sim.boundary.carried(part, self._pressure_points[k:k + 1])[0]
        return points

    def _groups(self, sim):
        """Each of the water's wall particles' force probe (-1: none): the rows of the probed wall or gate part
        (boundary.Boundary.part_rows; a gate's only while it stands). Made anew when the boundary is."""
        boundary = sim.boundary
        if self._wall_groups is None or self._wall_groups[0] is not boundary:
            groups = np.full(boundary.count, -1, dtype=np.int64)
            for k, probe in enumerate(self.forces):
                rows = boundary.part_rows(probe.part) if probe.phase != "solid" else None
                if rows is not None:
                    groups[rows] = k
            self._wall_groups = (boundary, groups)
        return self._wall_groups[1]

    def _forces(self, sim):
        out = np.zeros((len(self.forces), 3))
        groups = self._groups(sim)
        if (groups >= 0).any():
            out += sim.fluid_phase.solver.wall_forces(groups, len(self.forces))
        for k, probe in enumerate(self.forces):
            if probe.phase == "solid" and sim.coupling is not None:
                out[k] += sim.solid.mass[probe.indices] @ sim.coupling.acc[probe.indices]
        return out

    def read(self, sim):
        """{name: (kind, {quantity: value})} now, in the scene's order (the interval means since the last read)."""
        out = {}
        for probe in self.groups:
            positions = sim.solid.pos if probe.phase == "solid" else sim.fluid.pos
            out[probe.name] = ("displacement", {"displacement": _triple(probe.displacement(positions))})
        if self.points:
            vel = sim.solid_velocity()
            for probe in self.points:
                out[probe.name] = ("point", {
                    "displacement": _triple(sim.solid.pos[probe.index] - probe.reference_position),
                    "velocity": _triple(vel[probe.index])})
        if self.pressure:
            for probe, p in zip(self.pressure, self._pressure_mean.take()):
                out[probe.name] = ("pressure", {"pressure": float(p)})
        if self.heights:
            water_pos, water_volume, wall_pos, wall_volume = sim.fluid_phase.filling_particles()
            step = sim.spacing / HEIGHT_SAMPLES_PER_SPACING
            for probe in self.heights:
                x, y, z0 = probe.position
                h, kernel = _kernel_of((probe.h, probe.kernel), sim)
                height = np.mean([surface_height(lx, ly, z0, water_pos, water_volume, wall_pos, wall_volume, h,
                                                 kernel, step)
                                  for lx, ly in _lines(x, y, probe.span, sim.spacing)])
                out[probe.name] = ("water_height", {"height": float(height),
                                                    "surface": (float(x), float(y), float(z0 + height))})
        if self.forces:
            for probe, f in zip(self.forces, self._force_mean.take()):
                out[probe.name] = ("force", {"force": _triple(f)})
        return {name: out[name] for name, _ in self.order}


def _kernel_of(own, sim):
    """(h, kernel id) a probe reads with: its own (ProbeSpec.h, .kernel) where it has them, else the water's."""
    h, kernel = own
    return h or sim.h, sim.fluid_kernel if kernel < 0 else kernel


def _lines(x, y, span, spacing):
    """The (x, y) of a water-height probe's vertical lines: (x, y) itself, or a grid over the rectangle `span`
    centred on it, as many lines along each axis as whole spacings fit (at least one), each at its cell's centre."""
    axes = []
    for centre, length in zip((x, y), span):
        n = max(int(round(length / spacing)), 1) if length > 0.0 else 1
        axes.append(centre - 0.5 * length + (np.arange(n) + 0.5) * length / n if length > 0.0 else np.array([centre]))
    return [(float(a), float(b)) for a in axes[0] for b in axes[1]]


def _triple(v):
    return (float(v[0]), float(v[1]), float(v[2]))


class IntervalMean:
    """A value averaged over the fluid steps of an outer step, weighted by their lengths."""

    def __init__(self, shape=()):
        self.total = np.zeros(shape)
        self.duration = 0.0
        self.last = np.zeros(shape)

    def add(self, value, dt):
        self.total += dt * np.asarray(value)
        self.duration += dt

    def take(self):
        """The mean since the last take (the last mean again if no step was added)."""
        if self.duration > 0.0:
            self.last = self.total / self.duration
        self.total = np.zeros_like(self.total)
        self.duration = 0.0
        return self.last


def probe_columns(kind, name, values):
    """The time-series columns of one probe's values (module docstring)."""
    if kind in ("displacement", "point"):
        d = values["displacement"]
        out = {f"{name}_dx": d[0], f"{name}_dy": d[1], f"{name}_dz": d[2]}
        if "velocity" in values:
            v = values["velocity"]
            out.update({f"{name}_vx": v[0], f"{name}_vy": v[1], f"{name}_vz": v[2]})
        return out
    if kind == "pressure":
        return {name: values["pressure"]}
    if kind == "water_height":
        return {name: values["height"]}
    f = values["force"]
    return {f"{name}_fx": f[0], f"{name}_fy": f[1], f"{name}_fz": f[2]}
