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
    commanded  the pose or the velocity last commanded (a ROS node's part): still until a command, a pose reached
               over the control period, no command faster than its maximum speed

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


def rotation_vector(rotation):
    """The rotation vector (axis times angle, rad) of a rotation matrix, angle in [0, pi]."""
    cos = min(max((np.trace(rotation) - 1.0) / 2.0, -1.0), 1.0)
    angle = math.acos(cos)
    skew = np.array([rotation[2, 1] - rotation[1, 2], rotation[0, 2] - rotation[2, 0],
                     rotation[1, 0] - rotation[0, 1]])
    if angle < 1e-12:
        return 0.5 * skew
    if math.pi - angle > 1e-6:
        return angle * skew / (2.0 * math.sin(angle))
    # near a half turn: the axis from the symmetric part, R = 2 a a^T - I
    column = int(np.argmax(np.diag(rotation)))
    axis = (rotation[:, column] + np.eye(3)[:, column]) / math.sqrt(2.0 * (1.0 + rotation[column, column]))
    return angle * axis


class Commanded(Motion):
    """A wall driven by commands (a ROS node's part), from rest at its built pose until the first one:

    a pose (R, d) is reached from the pose the wall has when the command applies over `period` s at a constant
    velocity and turn rate, then held; a velocity (linear m/s, angular rad/s about `point` as it moves) holds from
    the pose the wall has when it applies. `radius`, the farthest of its particles from `point` (boundary.Boundary
    sets it), makes the speed of any of them at most |v| + |w| radius; a command asking more than `max_speed` is
    refused (`refusal`), so `speed_bound` holds over the whole run."""

    def __init__(self, point=(0.0, 0.0, 0.0), max_speed=0.0, period=0.01):
        self.point = np.asarray(point, dtype=np.float64)
        self.max_speed, self.period = float(max_speed), float(period)
        self.radius = 0.0
        self._since, self._rotation, self._shift = 0.0, np.eye(3), np.zeros(3)
        self._velocity, self._spin, self._until = np.zeros(3), np.zeros(3), math.inf

    def _rates_to(self, t, rotation, shift):
        """(velocity, spin) that reach the pose (rotation, shift) from the pose at t over the period."""
        now_rotation, now_shift = self.pose(t)
        spin = rotation_vector(np.asarray(rotation, dtype=np.float64) @ now_rotation.T) / self.period
        return (np.asarray(shift, dtype=np.float64) - now_shift) / self.period, spin

    def _speed(self, velocity, spin):
        return float(np.sqrt(velocity @ velocity) + np.sqrt(spin @ spin) * self.radius)

    def refusal(self, t, rotation=None, shift=None, velocity=None, spin=None):
        """Why a pose command (rotation, shift) or a velocity command (velocity, spin) at time t cannot be
        followed, or None: a value not finite, or faster than max_speed."""
        given = [np.asarray(v, dtype=np.float64) for v in (rotation, shift, velocity, spin) if v is not None]
        if not all(np.isfinite(v).all() for v in given):
            return "a value is not finite"
        if rotation is not None:
            rotation = np.asarray(rotation, dtype=np.float64)
            if np.abs(rotation @ rotation.T - np.eye(3)).max() > 1e-6 or np.linalg.det(rotation) < 0.0:
                return "the orientation is not a rotation (a unit quaternion)"
            velocity, spin = self._rates_to(t, rotation, shift)
            what = f"reaching it in motion_period = {self.period:g} s"
        else:
            what = "it"
        speed = self._speed(np.asarray(velocity, dtype=np.float64), np.asarray(spin, dtype=np.float64))
        if speed > self.max_speed * (1.0 + 1e-9):
            return (f"{what} moves a particle at {speed:.4g} m/s, faster than motion_max_speed = "
                    f"{self.max_speed:g} m/s")
        return None

    def command_pose(self, t, rotation, shift):
        """From time t towards the pose (R, d), reached after the period and held."""
        velocity, spin = self._rates_to(t, rotation, shift)
        self.command_velocity(t, velocity, spin)
        self._until = float(t) + self.period

    def command_velocity(self, t, velocity, spin):
        """From time t the velocities `velocity` and `spin`, from the pose the wall has then."""
        self._rotation, self._shift = self.pose(t)
        self._since, self._until = float(t), math.inf
        self._velocity, self._spin = np.asarray(velocity, dtype=np.float64), np.asarray(spin, dtype=np.float64)

    def pose(self, t):
        elapsed = min(max(t - self._since, 0.0), self._until - self._since)
        rate = float(np.sqrt(self._spin @ self._spin))
        turn = rotation_about(self._spin / rate, rate * elapsed) if rate > 0.0 else np.eye(3)
        return turn @ self._rotation, self._shift + self._velocity * elapsed

    def velocity(self, t):
        """(linear m/s, angular rad/s) at time t."""
        if t < self._since or t >= self._until:
            return np.zeros(3), np.zeros(3)
        return self._velocity.copy(), self._spin.copy()

    def speed_bound(self, radius):
        return self.max_speed
