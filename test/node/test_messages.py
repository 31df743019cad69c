"""sph_fsi.messages: NumPy -> PointCloud2 -> NumPy round trips (no node, no DDS)."""
import numpy as np
import pytest
from sensor_msgs.msg import PointField

from sph_fsi.messages import (PARTICLE_DTYPE, PHASE_FLUID, PHASE_SOLID, WALL_DTYPE, cloud_to_structured,
                              particles_to_cloud, seconds_from_stamp, stamp_from_seconds, structured_to_cloud,
                              walls_to_cloud)

PARTICLE_FIELDS = ["x", "y", "z", "vx", "vy", "vz", "pressure", "von_mises", "phase"]


def _random_cloud(rng, n):
    pos = rng.normal(scale=0.05, size=(n, 3))
    vel = rng.normal(scale=2.0, size=(n, 3))
    pressure = rng.normal(scale=1e5, size=n)
    vm = np.abs(rng.normal(scale=1e4, size=n))
    phase = rng.choice([PHASE_FLUID, PHASE_SOLID], size=n).astype(np.uint8)
    return pos, vel, pressure, vm, phase


@pytest.mark.parametrize("n", [0, 1, 7, 1000])
def test_particles_round_trip(n):
    rng = np.random.default_rng(n)
    pos, vel, pressure, vm, phase = _random_cloud(rng, n)
    msg = particles_to_cloud(pos, vel, pressure, vm, phase, stamp_from_seconds(1.25), "map")
    assert [f.name for f in msg.fields] == PARTICLE_FIELDS
    assert [f.datatype for f in msg.fields] == [PointField.FLOAT32] * 8 + [PointField.UINT8]
    assert [f.offset for f in msg.fields] == [0, 4, 8, 12, 16, 20, 24, 28, 32]
    assert all(f.count == 1 for f in msg.fields)
    assert msg.point_step == 36 and msg.point_step % 4 == 0
    assert msg.height == 1 and msg.width == n
    assert msg.row_step == msg.point_step * msg.width
    assert len(msg.data) == msg.row_step
    assert msg.is_dense and not msg.is_bigendian
    assert msg.header.frame_id == "map" and seconds_from_stamp(msg.header.stamp) == 1.25

    back = cloud_to_structured(msg)
    assert len(back) == n
    f32 = lambda a: np.asarray(a, dtype=np.float32)  # noqa: E731
    for i, name in enumerate("xyz"):
        np.testing.assert_array_equal(back[name], f32(pos[:, i]))
        np.testing.assert_array_equal(back["v" + name], f32(vel[:, i]))
    np.testing.assert_array_equal(back["pressure"], f32(pressure))
    np.testing.assert_array_equal(back["von_mises"], f32(vm))
    np.testing.assert_array_equal(back["phase"], phase)
    # and to float32 precision of the float64 inputs
    np.testing.assert_allclose(back["x"], pos[:, 0], rtol=1e-7, atol=0)
    # padding bytes are zero
    raw = np.frombuffer(bytes(msg.data), np.uint8).reshape(n, 36)
    assert not raw[:, 33:].any()


def test_scalar_phase_and_walls():
    rng = np.random.default_rng(3)
    pos, vel, pressure, vm, _ = _random_cloud(rng, 5)
    back = cloud_to_structured(particles_to_cloud(pos, vel, pressure, vm, PHASE_SOLID, stamp_from_seconds(0), "w"))
    assert (back["phase"] == PHASE_SOLID).all()
    walls = walls_to_cloud(pos, stamp_from_seconds(0.5), "map")
    assert [f.name for f in walls.fields] == ["x", "y", "z"]
    assert walls.point_step == 12 and walls.row_step == 60 and walls.width == 5
    back = cloud_to_structured(walls)
    np.testing.assert_array_equal(np.stack([back["x"], back["y"], back["z"]], axis=1), pos.astype(np.float32))


def test_generic_structured_round_trip_and_padding():
    dtype = np.dtype([("a", "<f8"), ("b", "<i2"), ("c", "u1")])   # 11 bytes
    pts = np.zeros(4, dtype)
    pts["a"], pts["b"], pts["c"] = [1.5, -2, 3, 4], [-1, 2, 300, 4], [1, 2, 3, 255]
    msg = structured_to_cloud(pts, stamp_from_seconds(0), "map")
    assert msg.point_step == 11   # a plain dtype keeps its own itemsize; the node's dtypes are padded
    back = cloud_to_structured(msg)
    for name in "abc":
        np.testing.assert_array_equal(back[name], pts[name])
    assert PARTICLE_DTYPE.itemsize % 4 == 0 and WALL_DTYPE.itemsize % 4 == 0


def test_big_endian_message_is_read():
    dtype = np.dtype({"names": ["x", "y"], "formats": [">f4", ">f4"], "offsets": [0, 4], "itemsize": 8})
    pts = np.array([(1.0, 2.0), (3.0, -4.5)], dtype=dtype)
    msg = structured_to_cloud(np.zeros(2, np.dtype([("x", "<f4"), ("y", "<f4")])), stamp_from_seconds(0), "m")
    msg.is_bigendian = True
    msg.data = pts.tobytes()
    back = cloud_to_structured(msg)
    np.testing.assert_array_equal(back["x"], [1.0, 3.0])
    np.testing.assert_array_equal(back["y"], [2.0, -4.5])


@pytest.mark.parametrize("t", [0.0, 1e-9, 0.005, 0.25, 1.999999999, 12.3456789])
def test_stamp_round_trip(t):
    stamp = stamp_from_seconds(t)
    assert 0 <= stamp.nanosec < 1_000_000_000
    assert abs(seconds_from_stamp(stamp) - t) <= 0.5e-9 + 1e-15 * t
