"""Prescribed motions of rigid parts (motion.py) against their formulas: a constant velocity to a travel, a ramped
sinusoid (translation and rotation), a table of poses, commanded poses and velocities; rigid (distances kept) and
from rest at the built pose."""
import math

import numpy as np
import pytest

from sph_fsi_core.motion import Commanded, Linear, Sinusoid, Table, euler_xyz, rotation_about, rotation_vector

BUILT = np.array([[0.0, 0.0, 0.0], [0.1, 0.0, 0.0], [0.1, 0.2, 0.0], [0.1, 0.2, 0.3]])


def _distances(x):
    return np.sqrt(((x[:, None, :] - x[None, :, :]) ** 2).sum(-1))


def test_linear_moves_at_its_velocity_from_its_start_until_its_travel():
    m = Linear([0.0, 3.0, 4.0], start=0.5, travel=2.0)
    assert np.array_equal(m.positions(BUILT, 0.4), BUILT)
    assert np.allclose(m.positions(BUILT, 0.7) - BUILT, [0.0, 0.6, 0.8])
    assert np.allclose(m.positions(BUILT, 5.0) - BUILT, [0.0, 1.2, 1.6]) and m.done(0.9) and not m.done(0.85)
    assert m.speed_bound(1.0) == 5.0


def test_a_ramped_sinusoid_starts_at_rest_and_then_follows_its_formula():
    a, f, phase, ramp = 0.02, 1.5, 30.0, 0.4
    m = Sinusoid([0.0, 0.0, 2.0], a, f, phase, ramp)
    assert np.array_equal(m.positions(BUILT, 0.0), BUILT)
    dt = 1e-6
    assert abs(m.value(dt) / dt) < 1e-3 * a * 2 * math.pi * f          # at rest at t = 0
    t = 1.3
    exact = a * (math.sin(2 * math.pi * f * t + math.radians(phase)) - math.sin(math.radians(phase)))
    assert np.allclose(m.positions(BUILT, t) - BUILT, [0.0, 0.0, exact], atol=1e-15)
    speeds = [abs(m.value(t + dt) - m.value(t)) / dt for t in np.linspace(0.0, 3.0, 3001)]
    assert max(speeds) <= m.speed_bound(0.0) and max(speeds) > 0.5 * m.speed_bound(0.0)


def test_a_rotation_keeps_the_body_rigid_and_turns_it_by_its_angle_about_its_point():
    point = np.array([0.1, 0.0, 0.0])
    m = Sinusoid([0.0, 1.0, 0.0], 10.0, 0.5, phase=0.0, ramp=0.0, rotate=True, point=point)
    t = 0.5                                            # a quarter period: the full 10 degrees
    x = m.positions(BUILT, t)
    assert np.allclose(_distances(x), _distances(BUILT), atol=1e-14)
    assert np.allclose(x[1], point, atol=1e-15)        # the point itself stays
    arm0, arm = BUILT[0] - point, x[0] - point
    assert math.degrees(math.acos(arm0 @ arm / (arm0 @ arm0))) == pytest.approx(10.0, rel=1e-12)


def test_a_table_is_interpolated_and_held_beyond_its_ends():
    rows = [[0.0, 0, 0, 0, 0, 0, 0], [1.0, 0.2, 0, 0, 0, 0, 90.0], [2.0, 0.2, 0.4, 0, 0, 0, 90.0]]
    m = Table(rows, point=(0.0, 0.0, 0.0))
    assert np.allclose(m.positions(BUILT, -1.0), BUILT)
    x = m.positions(BUILT, 1.0)
    assert np.allclose(x[1], [0.2, 0.1, 0.0], atol=1e-15)                 # (0.1, 0) turned 90 deg about z, shifted
    assert np.allclose(m.positions(BUILT, 1.5) - m.positions(BUILT, 1.0), [0.0, 0.2, 0.0])
    assert np.allclose(m.positions(BUILT, 9.0), m.positions(BUILT, 2.0))
    assert m.speed_bound(0.5) == pytest.approx(max(0.2 + math.radians(90.0) * 0.5, 0.4))
    with pytest.raises(ValueError, match="increase"):
        Table([[1.0, 0, 0, 0], [1.0, 1, 0, 0]])


def test_commanded_poses_and_velocities():
    """A pose reached over the period at constant rates, then held; a velocity from the pose the wall has; commands
    faster than max_speed (the farthest particle's speed |v| + |w| radius) or not finite refused."""
    m = Commanded(point=(0.0, 0.0, 0.0), max_speed=1.0, period=0.5)
    m.radius = 0.1
    assert np.array_equal(m.positions(BUILT, 3.0), BUILT)                  # still until a command
    turn = euler_xyz([0.0, 0.0, 90.0])
    assert "faster than motion_max_speed = 1 m/s" in m.refusal(1.0, turn, [0.0, 0.0, 0.5])   # 1 + pi/2 / 0.5 * 0.1
    m.max_speed = 2.0
    assert m.refusal(1.0, turn, [0.0, 0.0, 0.5]) is None
    m.command_pose(1.0, turn, [0.0, 0.0, 0.5])
    half = m.positions(BUILT, 1.25)[1]                                     # halfway: 45 deg and 0.25 m
    assert np.allclose(half, [0.1 * math.sqrt(0.5), 0.1 * math.sqrt(0.5), 0.25], atol=1e-15)
    assert np.allclose(m.positions(BUILT, 1.5)[1], [0.0, 0.1, 0.5], atol=1e-15)
    assert np.allclose(m.positions(BUILT, 2.0)[1], [0.0, 0.1, 0.5], atol=1e-15)         # held
    assert np.allclose(m.velocity(1.2)[0], [0.0, 0.0, 1.0]) and not m.velocity(1.6)[0].any()
    m.command_velocity(2.0, [1.0, 0.0, 0.0], [0.0, 0.0, 0.0])
    assert np.allclose(m.positions(BUILT, 2.5)[1], [0.5, 0.1, 0.5], atol=1e-15)
    m.command_velocity(2.5, [0.0, 0.0, 0.0], [0.0, 0.0, math.pi])          # half a turn per second
    assert np.allclose(m.positions(BUILT, 3.5)[1], [0.5, -0.1, 0.5], atol=1e-14)     # about the moved point
    assert "faster than motion_max_speed = 2" in m.refusal(4.0, velocity=[2.0, 0.0, 0.0], spin=[0.0, 0.0, 1.0])
    assert m.refusal(4.0, velocity=[float("nan"), 0.0, 0.0], spin=[0.0, 0.0, 0.0]) == "a value is not finite"
    assert "not a rotation" in m.refusal(4.0, 2.0 * np.eye(3), [0.0, 0.0, 0.0])
    for angle in (0.0, 1e-9, 0.7, math.pi - 1e-9, math.pi):
        axis = np.array([0.3, -0.4, math.sqrt(0.75)])
        assert np.allclose(rotation_vector(rotation_about(axis, angle)), angle * axis, atol=1e-9)
    assert np.allclose(rotation_about([0.0, 0.0, 1.0], math.pi / 2) @ [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], atol=1e-15)
