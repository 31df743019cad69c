"""The particles the water sees as walls, and who owns which of their rows.

The fluid sums over one array of wall particles (fluid.solver.FluidSolver's walls): a block of rows for each kind of
part, in this order:

    walls   the scene's fixed walls (its wall parts, in file order), then the rigid holder a mirrored clamp leaves
            in the water (scenes/built.without_unreached_clamp)
    gate    the scene's gates while they stand: through the settling phase (fluid.settle_time), and from t = 0 a
            lifted gate until it has travelled its distance (Built.release_velocity, release_travel)
    solid   every solid particle of a coupled scene, a moving wall of the water (Satake et al. sec. 2.3), with the
            mass the coupling gives it (coupling.forces.solid_wall_mass)

`Boundary` hands the rows out by name: a block by its kind, and a geometry scene's part by its own name
(scenes/built.Built.parts), so the force probes and the coupling find their rows without counting offsets. The
parts that move write their own rows: `move_parts(t)` (the prescribed motions, motion.py: a moving wall's, a lifted
gate's; `carried` moves a probe's point with its part, `wall_speed` bounds the walls' speed for the step) and
`follow_solid()` (the solid where it is now); `without_gates()` is the boundary from t = 0 when the gates are gone
at once.
"""
import numpy as np

from .motion import Commanded, Linear

KINDS = ("walls", "gate", "solid")
# a command's stamp is whole nanoseconds (a ROS time): it applies at a step starting within half of one after it
STAMP_RESOLUTION = 1e-9


class Boundary:
    """The water's wall particles: `pos` (M, 3) m and `mass` (M,) kg, in blocks by kind (module docstring), with the
    rows of each block and of each named part. Construct with `Boundary.of`."""

    def __init__(self, blocks, parts, rho0, moving=None, gate_motion=None, solid=None):
        """blocks: [(kind, pos, mass)] in KINDS' order; parts: {name: (kind, indices within that kind's block)};
        moving: {name: (rows, positions as built, motion.Motion)} of the walls that move; gate_motion: the same
        triple of a lifted gate, or None; solid: the state.SolidState whose positions the solid block follows."""
        self.rho0 = float(rho0)
        self.pos = np.ascontiguousarray(np.concatenate([p for _, p, _ in blocks])) if blocks else np.zeros((0, 3))
        self.mass = np.concatenate([m for _, _, m in blocks]) if blocks else np.zeros(0)
        self._blocks = {}
        first = 0
        for kind, pos, _ in blocks:
            self._blocks[kind] = slice(first, first + len(pos))
            first += len(pos)
        self._parts = {name: (kind, np.asarray(indices)) for name, (kind, indices) in parts.items()}
        self.moving = dict(moving or {})
        self.gate_motion = gate_motion
        self.solid = solid
        self._parked = set()     # moving walls whose linear motion has reached its travel: they stay there
        self.time = 0.0
        self.commands = []       # (stamp, order, name, kind, values, source) waiting for their step (command)
        self.applied = []        # (time applied, name, kind, values, source), in order
        self.refused = []        # (time, name, why), in order
        self._ordinal = 0
        # the fastest a moving wall's particle goes over the run (the water's step follows it: fluid/phase.py)
        self.wall_speed = max([motion.speed_bound(float(np.sqrt(((built - motion.point) ** 2).sum(axis=1)).max()))
                               for _, built, motion in self.moving.values()], default=0.0)

    @classmethod
    def of(cls, built, rho0, gates=False, solid=None, solid_mass=None):
        """The boundary of a scene as built (scenes/built.Built): its walls (the moving ones by their motions), its
        gates if `gates` (they stand; a lifted one moves from t = 0), and the solid `solid` (state.SolidState,
        counted with `solid_mass` each) in a coupled scene."""
        blocks = []
        if built.walls is not None:
            blocks.append(("walls", built.walls.pos, built.walls.mass))
        moving = {}
        for name, motion in built.motions.items():       # in the walls block, the first: its rows are the part's
            rows = built.parts[name][1]
            if isinstance(motion, Commanded):
                motion.radius = float(np.sqrt(((built.walls.pos[rows] - motion.point) ** 2).sum(axis=1)).max())
            moving[name] = (rows.copy(), built.walls.pos[rows].copy(), motion)
        gate_motion = None
        if gates and built.release_walls is not None:
            first = len(built.walls.pos) if built.walls is not None else 0
            blocks.append(("gate", built.release_walls.pos, built.release_walls.mass))
            if built.release_velocity is not None:      # a lifted gate
                gate_motion = (slice(first, first + len(built.release_walls.pos)), built.release_walls.pos.copy(),
                               Linear(built.release_velocity, 0.0, built.release_travel))
        if solid is not None:
            blocks.append(("solid", solid.pos, solid_mass))
        parts = {name: (phase, idx) for name, (phase, idx) in built.parts.items() if phase != "fluid"}
        return cls(blocks, parts, rho0, moving, gate_motion, solid)

    def without_gates(self):
        """The same boundary with its gates gone (released at t = 0): new arrays, the other blocks as they are (the
        walls block stays first, so the moving walls keep their rows), the commands and their record kept."""
        blocks = [(kind, self.pos[rows], self.mass[rows]) for kind, rows in self._blocks.items() if kind != "gate"]
        boundary = Boundary(blocks, self._parts, self.rho0, self.moving, None, self.solid)
        boundary._parked, boundary.time = set(self._parked), self.time
        boundary.commands, boundary.applied, boundary.refused = self.commands, self.applied, self.refused
        boundary._ordinal = self._ordinal
        return boundary

    @property
    def count(self):
        return len(self.pos)

    def has(self, kind):
        """Whether the boundary holds a block of this kind now ('walls', 'gate', 'solid')."""
        return kind in self._blocks

    def rows(self, kind):
        """The rows of a block (a slice of pos and mass); KeyError if the boundary has none of that kind."""
        return self._blocks[kind]

    def part_rows(self, name):
        """The rows of a scene part by its name (an index array), or None where the part is not among the walls the
        water sees now (a gate after its release, a part of another phase)."""
        if name not in self._parts:
            return None
        kind, indices = self._parts[name]
        if kind not in self._blocks:
            return None
        return self._blocks[kind].start + indices

    def move_parts(self, t):
        """The prescribed motions to time t; True if some rows moved. A linear motion that has reached its travel (a
        lifted gate's, a wall's) leaves its rows there and is not applied again."""
        self.time = t
        moved = False
        for name, (rows, built, motion) in self.moving.items():
            if name not in self._parked:
                self.pos[rows] = motion.positions(built, t)
                moved = True
                if isinstance(motion, Linear) and motion.done(t):
                    self._parked.add(name)
        if self.gate_motion is not None:
            rows, built, motion = self.gate_motion
            self.pos[rows] = motion.positions(built, t)
            moved = True
            if motion.done(t):
                self.gate_motion = None
        return moved

    def commanded(self):
        """The names of the walls driven by commands (motion ros), in file order."""
        return [name for name, (_, _, motion) in self.moving.items() if isinstance(motion, Commanded)]

    def command(self, name, stamp, kind, values, source=None):
        """Queue a command for commanded wall `name`, applied at the first fluid step that starts at or after
        `stamp` (s, to the nanosecond: STAMP_RESOLUTION; a stamp already past: the next step). kind 'pose':
        values (rotation (3, 3), shift (3,)); kind 'velocity': (linear (3,), angular (3,)); `source`: the command as
        it came (a message's numbers), kept with it in `applied` for the record. ValueError for a part that takes
        no commands."""
        if not isinstance(self.part_motion(name), Commanded):
            raise ValueError(f"part {name!r} takes no commands; allowed: " + (", ".join(self.commanded()) or "none"))
        self._ordinal += 1
        self.commands.append((float(stamp), self._ordinal, name, kind,
                              tuple(np.asarray(v, dtype=np.float64) for v in values), source))
        self.commands.sort(key=lambda c: c[:2])

    def apply_commands(self, t):
        """The queued commands stamped at or before t, applied at t in stamp order (those a wall cannot follow
        refused, into `refused`: motion.Commanded.refusal); True if some applied."""
        applied = False
        while self.commands and self.commands[0][0] <= t + STAMP_RESOLUTION / 2:
            _, _, name, kind, values, source = self.commands.pop(0)
            motion = self.moving[name][2]
            why = (motion.refusal(t, rotation=values[0], shift=values[1]) if kind == "pose"
                   else motion.refusal(t, velocity=values[0], spin=values[1]))
            if why is not None:
                self.refused.append((t, name, why))
                continue
            (motion.command_pose if kind == "pose" else motion.command_velocity)(t, *values)
            self.applied.append((t, name, kind, values, source))
            applied = True
        return applied

    def part_motion(self, name):
        """The motion of moving wall `name` (motion.Motion), or None for a part that stays."""
        return self.moving[name][2] if name in self.moving else None

    def moving_walls(self, lag=1.0e-6):
        """(rows, velocities (N, 3) m/s) of the moving walls' particles now (the time of the last move_parts), their
        velocity from where their motion had them `lag` s before; empty where none moves (the outputs show them
        as particles that move: sph_fsi.points)."""
        if not self.moving:
            return np.zeros(0, dtype=np.int64), np.zeros((0, 3))
        rows, velocities = [], []
        for part_rows, built, motion in self.moving.values():
            rows.append(part_rows)
            velocities.append((motion.positions(built, self.time) - motion.positions(built, self.time - lag)) / lag)
        return np.concatenate(rows), np.concatenate(velocities)

    def part_pose(self, name):
        """(position (3,) m, rotation (3, 3)) of moving wall `name` now: where its motion's point has gone, and how
        the wall is turned from its built pose."""
        motion = self.moving[name][2]
        rotation, shift = motion.pose(self.time)
        return motion.point + shift, (np.eye(3) if rotation is None else rotation)

    def carried(self, name, points):
        """Points (P, 3) that ride on part `name`, from where they were at its built pose to where the part is now
        (the time of the last move_parts); as they are for a part that stays."""
        motion = self.part_motion(name)
        return points if motion is None else motion.positions(points, self.time)

    def follow_solid(self):
        """The solid block where the solid is now; True if the boundary has one (its rows may have moved)."""
        if self.solid is None:
            return False
        self.pos[self._blocks["solid"]] = self.solid.pos
        return True
