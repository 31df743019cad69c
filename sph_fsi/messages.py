"""NumPy <-> ROS messages: particle clouds as sensor_msgs/PointCloud2, simulated time as builtin_interfaces/Time,
probe readings as their topics' messages (`probe_message`; the topics and types: sph_fsi.points).

Pure functions, no node. Clouds are built with a NumPy structured array whose layout is the PointCloud2 point
layout (little-endian, point_step padded to a multiple of 4), and `msg.data` is filled with
`array.array('B', buf.tobytes())`: assigning a NumPy array to `msg.data` directly is ~100x slower.

`~/particles` points: float32 x y z [m], vx vy vz [m/s], pressure [Pa], von_mises [Pa], uint8 phase
(1 fluid, 2 solid, 3 a wall that moves), padded from 33 to 36 bytes. `~/walls` points: float32 x y z [m].
"""
import array

import numpy as np
from builtin_interfaces.msg import Time
from geometry_msgs.msg import (Point, PointStamped, Pose, PoseStamped, Quaternion, Vector3, Vector3Stamped, Wrench,
                               WrenchStamped)
from sensor_msgs.msg import FluidPressure, PointCloud2, PointField
from std_msgs.msg import Header

from .points import (PARTICLE_DTYPE, PHASE_FLUID, PHASE_SOLID, WALL_DTYPE,  # layouts, defined ROS-free
                     part_topic)

__all__ = ["PHASE_FLUID", "PHASE_SOLID", "PARTICLE_DTYPE", "WALL_DTYPE", "particle_array", "wall_array",
           "structured_to_cloud", "particles_to_cloud", "walls_to_cloud", "cloud_to_structured",
           "stamp_from_seconds", "seconds_from_stamp", "probe_message", "part_messages"]

# NumPy (kind, itemsize) <-> PointField datatype
_TO_POINTFIELD = {("i", 1): PointField.INT8, ("u", 1): PointField.UINT8, ("i", 2): PointField.INT16,
                  ("u", 2): PointField.UINT16, ("i", 4): PointField.INT32, ("u", 4): PointField.UINT32,
                  ("f", 4): PointField.FLOAT32, ("f", 8): PointField.FLOAT64}
_FROM_POINTFIELD = {PointField.INT8: "i1", PointField.UINT8: "u1", PointField.INT16: "i2", PointField.UINT16: "u2",
                    PointField.INT32: "i4", PointField.UINT32: "u4", PointField.FLOAT32: "f4",
                    PointField.FLOAT64: "f8"}


def stamp_from_seconds(t):
    """Simulated time [s] -> builtin_interfaces/Time, rounded to the nanosecond."""
    ns = int(round(float(t) * 1e9))
    return Time(sec=ns // 1_000_000_000, nanosec=ns % 1_000_000_000)


def seconds_from_stamp(stamp):
    return stamp.sec + stamp.nanosec * 1e-9


def particle_array(pos, vel, pressure, von_mises, phase):
    """Structured PARTICLE_DTYPE array from (N,3) pos, (N,3) vel, (N,) pressure, (N,) von Mises, phase.

    `phase` is a scalar code for all points or an (N,) array of codes.
    """
    pos = np.asarray(pos)
    n = len(pos)
    out = np.zeros(n, dtype=PARTICLE_DTYPE)   # zeros: the padding bytes are deterministic
    out["x"], out["y"], out["z"] = pos[:, 0], pos[:, 1], pos[:, 2]
    vel = np.asarray(vel)
    out["vx"], out["vy"], out["vz"] = vel[:, 0], vel[:, 1], vel[:, 2]
    out["pressure"] = pressure
    out["von_mises"] = von_mises
    out["phase"] = phase
    return out


def wall_array(pos):
    pos = np.asarray(pos)
    out = np.zeros(len(pos), dtype=WALL_DTYPE)
    out["x"], out["y"], out["z"] = pos[:, 0], pos[:, 1], pos[:, 2]
    return out


def structured_to_cloud(points, stamp, frame_id):
    """A 1-D structured array (little-endian numeric fields) -> PointCloud2 (height 1, dense)."""
    points = np.ascontiguousarray(points)
    dtype = points.dtype
    if dtype.names is None or points.ndim != 1:
        raise ValueError("expected a 1-D structured array")
    fields = []
    for name in dtype.names:
        ftype, offset = dtype.fields[name][:2]
        if ftype.byteorder == ">":
            raise ValueError(f"field {name!r}: big-endian fields are not supported")
        key = (ftype.kind, ftype.itemsize)
        if key not in _TO_POINTFIELD or ftype.shape:
            raise ValueError(f"field {name!r}: type {ftype} has no PointField datatype")
        fields.append(PointField(name=name, offset=offset, datatype=_TO_POINTFIELD[key], count=1))
    msg = PointCloud2()
    msg.header = Header(stamp=stamp, frame_id=frame_id)
    msg.height = 1
    msg.width = len(points)
    msg.fields = fields
    msg.is_bigendian = False
    msg.point_step = dtype.itemsize
    msg.row_step = dtype.itemsize * len(points)
    msg.is_dense = True
    msg.data = array.array("B", points.tobytes())
    return msg


def particles_to_cloud(pos, vel, pressure, von_mises, phase, stamp, frame_id):
    return structured_to_cloud(particle_array(pos, vel, pressure, von_mises, phase), stamp, frame_id)


def walls_to_cloud(pos, stamp, frame_id):
    return structured_to_cloud(wall_array(pos), stamp, frame_id)


def cloud_to_structured(msg):
    """PointCloud2 -> 1-D structured array (height * width points) with the message's fields and layout."""
    endian = ">" if msg.is_bigendian else "<"
    names, formats, offsets = [], [], []
    for f in msg.fields:
        if f.datatype not in _FROM_POINTFIELD:
            raise ValueError(f"field {f.name!r}: unknown PointField datatype {f.datatype}")
        base = np.dtype(endian + _FROM_POINTFIELD[f.datatype])
        names.append(f.name)
        formats.append(base if f.count <= 1 else (base, (f.count,)))
        offsets.append(f.offset)
    dtype = np.dtype({"names": names, "formats": formats, "offsets": offsets, "itemsize": msg.point_step})
    n = msg.height * msg.width
    raw = np.frombuffer(bytes(msg.data), dtype=np.uint8)
    if msg.height > 1 and msg.row_step != msg.point_step * msg.width:
        # rows may be padded: drop each row's tail
        raw = raw.reshape(msg.height, msg.row_step)[:, : msg.point_step * msg.width].reshape(-1)
    if raw.size < n * msg.point_step:
        raise ValueError(f"data has {raw.size} bytes, expected {n * msg.point_step}")
    return np.frombuffer(raw[: n * msg.point_step].tobytes(), dtype=dtype, count=n)


def _vector3(v):
    return Vector3(x=float(v[0]), y=float(v[1]), z=float(v[2]))


def probe_message(quantity, value, header):
    """One probe topic's message (sph_fsi.points: QUANTITY_TYPES) for a reading's `value`, with `header`:
    displacement, velocity -> Vector3Stamped; pressure -> FluidPressure (variance 0); surface -> PointStamped;
    force -> WrenchStamped (torque 0)."""
    if quantity in ("displacement", "velocity"):
        return Vector3Stamped(header=header, vector=_vector3(value))
    if quantity == "pressure":
        return FluidPressure(header=header, fluid_pressure=float(value), variance=0.0)
    if quantity == "surface":
        return PointStamped(header=header, point=Point(x=float(value[0]), y=float(value[1]), z=float(value[2])))
    if quantity == "force":
        return WrenchStamped(header=header, wrench=Wrench(force=_vector3(value), torque=Vector3()))
    raise ValueError(f"probe quantity {quantity!r}: no message type")


def _vector(v):
    return Vector3(x=float(v[0]), y=float(v[1]), z=float(v[2]))


def part_messages(readings, header):
    """[(topic, message)] of the commanded walls' readings (sph_fsi.points.part_readings): parts/<name>/pose
    (PoseStamped) and parts/<name>/wrench (WrenchStamped)."""
    out = []
    for name, r in readings.items():
        (x, y, z), (qx, qy, qz, qw) = r["position"], r["orientation"]
        pose = Pose(position=Point(x=x, y=y, z=z), orientation=Quaternion(x=qx, y=qy, z=qz, w=qw))
        out.append((part_topic(name, "pose"), PoseStamped(header=header, pose=pose)))
        out.append((part_topic(name, "wrench"), WrenchStamped(header=header, wrench=Wrench(
            force=_vector(r["force"]), torque=_vector(r["moment"])))))
    return out
