"""Prescribed motion of a rigid part: where its particles are at time t, as a rigid motion of where they were built,

    x(t) = R(t) (x0 - c) + c + d(t),

R(t) a rotation about the point c, d(t) a translation (boundary.Boundary.move_parts applies it to a part's rows).
The kinds, each from rest at the built pose:

    linear     d = v min(|v| (t - t0), travel) / |v| for t >= t0 (0 before): a constant velocity v from the start time
               t0 until the part has travelled `travel` (0: without end), then held (a lifted gate's motion)
    sinusoid   a translation s(t) along the unit `axis`, or a rotation by s(t) (degrees) about `axis` through
               `point`: s(t) = A r(t) (sin(2 pi f t + phi) - sin(phi)), ramped in by r(t) = (1 - cos(pi t / T)) / 2
               over the ramp time T (1 after it; T = 0: no ramp): it starts at the built pose, and with a ramp at
               rest (a wavemaker paddle's start)
    table      poses (t, x, y, z [, rx, ry, rz]: m, degrees about x then y then z through `point`) read from a CSV,
               linearly interpolated, held beyond its first and last rows
    commanded  the pose or the velocity last commanded (a ROS node's part): holds still until a command

Each gives `pose(t)` (R, d) and `speed_bound(radius)`, a bound on the speed of any point within `radius` of its
rotation's point over the whole run (the water's step keeps a moving wall within a fraction of h per step).
"""
import math

import numpy as np


def rotation_about(axis, angle):
    """The rotation matrix by `angle` (rad) about the unit vector `axis` (Rodrigues' formula)."""
    x, y, z = axis
    c, s = math.cos(angle), math.sin(angle)
    k = np.array([[0.0, -z, y], [z, 0.0, -x], [-y, x, 0.0]])
    return np.eye(3) + s * k + (1.0 - c) * (k @ k)


def euler_xyz(angles_deg):
    """The rotation by angles (deg) about x, then y, then z (a part's `rotation` key, geometry/shapes.py's rule)."""
    ax, ay, az = np.radians(angles_deg)
    return (rotation_about((0.0, 0.0, 1.0), az) @ rotation_about((0.0, 1.0, 0.0), ay)
            @ rotation_about((1.0, 0.0, 0.0), ax))


def _unit(v, what):
    v = np.asarray(v, dtype=np.float64)
    norm = float(np.sqrt(v @ v))
    if norm == 0.0:
        raise ValueError(f"{what} = [0, 0, 0]: no direction")
    return v / norm


class Motion:
    """A rigid motion from rest at the built pose (module docstring). `point`: the rotation's centre c."""
    point = np.zeros(3)

    def pose(self, t):
        """(R (3, 3), d (3,)) at time t."""
        raise NotImplementedError

    def speed_bound(self, radius):
        """An upper bound (m/s) on the speed of a point within `radius` (m) of `point`, over the whole run."""
        raise NotImplementedError

    def positions(self, built, t):
        """The part's particles at time t from where they were built, (N, 3) m."""
        rotation, shift = self.pose(t)
        if rotation is None:
            return built + shift
        return (built - self.point) @ rotation.T + self.point + shift


class Linear(Motion):
    """A constant velocity `velocity` (m/s) from `start` (s) until it has travelled `travel` (m; 0: without end)."""

    def __init__(self, velocity, start=0.0, travel=0.0):
        self.velocity = np.asarray(velocity, dtype=np.float64)
        self.speed = float(np.sqrt(self.velocity @ self.velocity))
        self.start, self.travel = float(start), float(travel)

    def pose(self, t):
        moved = max(t - self.start, 0.0) * self.speed
        if self.travel > 0.0:
            moved = min(moved, self.travel)
        return None, self.velocity * (moved / self.speed)

    def done(self, t):
        """Whether it has reached its travel by time t (it stays there from then on)."""
        return self.travel > 0.0 and (t - self.start) * self.speed >= self.travel

    def speed_bound(self, radius):
        return self.speed


class Sinusoid(Motion):
    """s(t) = A r(t) (sin(2 pi f t + phi) - sin(phi)) along `axis` (rotate False: a translation, A in m) or about
    `axis` through `point` (rotate True: A in degrees); `phase` phi in degrees, `ramp` T in s."""

    def __init__(self, axis, amplitude, frequency, phase=0.0, ramp=0.0, rotate=False, point=(0.0, 0.0, 0.0)):
        self.axis = _unit(axis, "axis")
        self.amplitude, self.frequency = float(amplitude), float(frequency)
        self.phase, self.ramp, self.rotate = math.radians(phase), float(ramp), bool(rotate)
        self.point = np.asarray(point, dtype=np.float64)

    def value(self, t):
        """s(t): m, or for a rotation degrees."""
        r = 1.0
        if self.ramp > 0.0 and t < self.ramp:
            r = 0.5 * (1.0 - math.cos(math.pi * max(t, 0.0) / self.ramp))
        omega = 2.0 * math.pi * self.frequency
        return self.amplitude * r * (math.sin(omega * t + self.phase) - math.sin(self.phase))

    def pose(self, t):
        s = self.value(t)
        if self.rotate:
            return rotation_about(self.axis, math.radians(s)), np.zeros(3)
        return None, s * self.axis

    def speed_bound(self, radius):
        # |ds/dt| <= A (|r'| |sin - sin| + r omega) <= A (pi / (2 T) 2 + omega)
        ramping = math.pi / self.ramp if self.ramp > 0.0 else 0.0
        rate = abs(self.amplitude) * (2.0 * math.pi * self.frequency + ramping)
        return math.radians(rate) * radius if self.rotate else rate


class Table(Motion):
    """Poses from rows (t, x, y, z[, rx, ry, rz]) in increasing t: translations (m) and rotations (degrees about x,
    then y, then z, through `point`), linearly interpolated in each column, held beyond the ends."""

    def __init__(self, rows, point=(0.0, 0.0, 0.0)):
        rows = np.asarray(rows, dtype=np.float64)
        if rows.ndim != 2 or rows.shape[1] not in (4, 7) or len(rows) < 1:
            raise ValueError("a motion table has rows of t, x, y, z (and rx, ry, rz): 4 or 7 columns")
        if len(rows) > 1 and not (np.diff(rows[:, 0]) > 0.0).all():
            raise ValueError("a motion table's times must increase from row to row")
        self.rows = rows
        self.point = np.asarray(point, dtype=np.float64)

    def _at(self, t):
        return np.array([np.interp(t, self.rows[:, 0], self.rows[:, k]) for k in range(1, self.rows.shape[1])])

    def pose(self, t):
        column = self._at(t)
        rotation = euler_xyz(column[3:6]) if len(column) == 6 else None
        return rotation, column[:3]

    def speed_bound(self, radius):
        if len(self.rows) < 2:
            return 0.0
        dt = np.diff(self.rows[:, 0])
        shift = np.sqrt((np.diff(self.rows[:, 1:4], axis=0) ** 2).sum(axis=1)) / dt
        turn = (np.radians(np.abs(np.diff(self.rows[:, 4:7], axis=0)).sum(axis=1)) / dt
                if self.rows.shape[1] == 7 else np.zeros_like(dt))
        return float((shift + turn * radius).max())


class Commanded(Motion):
    """The pose last commanded (a translation and a rotation about `point`, relative to the built pose), or a velocity
    (linear, m/s, and angular, rad/s) from the pose at the command's time; still until the first command. Its speed
    bound is the one the scene declares (`max_speed`): commands beyond it are refused where they arrive."""

    def __init__(self, point=(0.0, 0.0, 0.0), max_speed=0.0):
        self.point = np.asarray(point, dtype=np.float64)
        self.max_speed = float(max_speed)
        self._since, self._rotation, self._shift = 0.0, np.eye(3), np.zeros(3)
        self._velocity, self._spin = np.zeros(3), np.zeros(3)

    def command_pose(self, t, rotation, shift):
        """From time t the pose (R, d), held."""
        self._since = float(t)
        self._rotation, self._shift = np.asarray(rotation, dtype=np.float64), np.asarray(shift, dtype=np.float64)
        self._velocity, self._spin = np.zeros(3), np.zeros(3)

    def command_velocity(self, t, velocity, spin):
        """From time t the velocities `velocity` and `spin`, from the pose the part has then."""
        self._rotation, self._shift = self.pose(t)
        self._since = float(t)
        self._velocity, self._spin = np.asarray(velocity, dtype=np.float64), np.asarray(spin, dtype=np.float64)

    def pose(self, t):
        elapsed = max(t - self._since, 0.0)
        rate = float(np.sqrt(self._spin @ self._spin))
        turn = rotation_about(self._spin / rate, rate * elapsed) if rate > 0.0 else np.eye(3)
        return turn @ self._rotation, self._shift + self._velocity * elapsed

    def speed_bound(self, radius):
        return self.max_speed
