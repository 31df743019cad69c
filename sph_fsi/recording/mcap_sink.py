"""MCAP recording with the node's topics: ROS 2 profile, CDR messages, ros2msg schemas (see msgdefs).

Written with mcap + mcap-ros2-support from plain dicts, so it needs neither rclpy nor a running ROS graph.
Topics and types are the node's (only those the scene has): <ns>/particles and <ns>/walls
(sensor_msgs/msg/PointCloud2), <ns>/tip_displacement (geometry_msgs/msg/Vector3Stamped), <ns>/strain_energy
(std_msgs/msg/Float64), one per probe quantity, <ns>/probes/<name>/<quantity> (displacement, velocity:
geometry_msgs/msg/Vector3Stamped; pressure: sensor_msgs/msg/FluidPressure, variance 0; surface:
geometry_msgs/msg/PointStamped; force: geometry_msgs/msg/WrenchStamped, torque 0; sph_fsi.points), /clock
(rosgraph_msgs/msg/Clock), /diagnostics (diagnostic_msgs/msg/DiagnosticArray).
Every message's log and publish time is its simulated time in ns (t = 0 at the start of the run), the same
time as its header stamp, so a player that follows log time replays at the simulator's own pace.
Each channel carries rosbag2's `offered_qos_profiles` metadata (walls: reliable, transient-local).
"""
import numpy as np
from mcap.writer import CompressionType
from mcap_ros2.writer import Writer

from sph_fsi.points import QUANTITY_TYPES, WALL_DTYPE, pack_particles, part_topic, probe_values, topic_type
from sph_fsi.points import TOPIC_TYPES as SCENE_TOPIC_TYPES

from .frame import Frame, Static
from .msgdefs import msgdef_text

__all__ = ["McapSink", "COMPRESSIONS", "TOPIC_TYPES", "probe_dict", "cloud_dict"]

COMPRESSIONS = {"zstd": CompressionType.ZSTD, "lz4": CompressionType.LZ4, "none": CompressionType.NONE}
# every topic's type but the probes' (sph_fsi.points.topic_type): the scene's, then /clock and /diagnostics (always)
TOPIC_TYPES = {**SCENE_TOPIC_TYPES, "/clock": "rosgraph_msgs/msg/Clock",
               "/diagnostics": "diagnostic_msgs/msg/DiagnosticArray"}
# PointField datatypes (sensor_msgs/msg/PointField constants)
_POINTFIELD = {("i", 1): 1, ("u", 1): 2, ("i", 2): 3, ("u", 2): 4, ("i", 4): 5, ("u", 4): 6, ("f", 4): 7,
               ("f", 8): 8}


def _qos_yaml(reliable=True, transient_local=False, depth=10):
    """rosbag2's offered_qos_profiles metadata (what `ros2 bag play` uses to offer the same QoS)."""
    return ("- history: 3\n"
            f"  depth: {depth}\n"
            f"  reliability: {1 if reliable else 2}\n"
            f"  durability: {1 if transient_local else 2}\n"
            "  deadline:\n    sec: 2147483647\n    nsec: 4294967295\n"
            "  lifespan:\n    sec: 2147483647\n    nsec: 4294967295\n"
            "  liveliness: 1\n"
            "  liveliness_lease_duration:\n    sec: 2147483647\n    nsec: 4294967295\n"
            "  avoid_ros_namespace_conventions: false\n")


def _fields(dtype):
    return [{"name": name, "offset": dtype.fields[name][1],
             "datatype": _POINTFIELD[(dtype.fields[name][0].kind, dtype.fields[name][0].itemsize)], "count": 1}
            for name in dtype.names]


def _stamp(t):
    ns = int(round(float(t) * 1e9))
    return {"sec": ns // 1_000_000_000, "nanosec": ns % 1_000_000_000}, ns


def cloud_dict(points, stamp, frame_id):
    """A PointCloud2 as the dict mcap_ros2 encodes (height 1, dense, little-endian; data as bytes)."""
    return {"header": {"stamp": stamp, "frame_id": frame_id}, "height": 1, "width": len(points),
            "fields": _fields(points.dtype), "is_bigendian": False, "point_step": points.dtype.itemsize,
            "row_step": points.dtype.itemsize * len(points), "data": points.tobytes(), "is_dense": True}


def _pose(position, orientation):
    x, y, z, w = orientation
    return {"position": _xyz(position), "orientation": {"x": float(x), "y": float(y), "z": float(z), "w": float(w)}}


def _xyz(v):
    return {"x": float(v[0]), "y": float(v[1]), "z": float(v[2])}


def probe_dict(quantity, value, header):
    """One probe topic's message (QUANTITY_TYPES[quantity]) as the dict mcap_ros2 encodes; the same fields and
    values as sph_fsi.messages.probe_message."""
    if quantity in ("displacement", "velocity"):
        return {"header": header, "vector": _xyz(value)}
    if quantity == "pressure":
        return {"header": header, "fluid_pressure": float(value), "variance": 0.0}
    if quantity == "surface":
        return {"header": header, "point": _xyz(value)}
    if quantity == "force":
        return {"header": header, "wrench": {"force": _xyz(value), "torque": _xyz((0.0, 0.0, 0.0))}}
    raise ValueError(f"probe quantity {quantity!r}: no message type (allowed: {', '.join(QUANTITY_TYPES)})")


class McapSink:
    """Writes Static, Frame and Final items (sph_fsi.recording.frame) to one MCAP file."""

    def __init__(self, path, topics, compression="zstd", frame_id="map", namespace="/sph_fsi",
                 chunk_size=4 * 1024 * 1024):
        """`topics`: the scene-dependent topic names the scene has (sph_fsi.points.topic_plan)."""
        if compression not in COMPRESSIONS:
            raise ValueError(f"mcap compression {compression!r}: allowed: {', '.join(COMPRESSIONS)}")
        self.path = str(path)
        self.frame_id = frame_id
        self._fh = open(self.path, "wb")
        self._writer = Writer(self._fh, chunk_size=chunk_size, compression=COMPRESSIONS[compression])
        self._writer.add_metadata("sph_fsi", {"time": "log and publish times are simulated time in ns from t = 0",
                                              "frame_id": frame_id})
        self._schemas = {}
        self._topics = {}
        ns = namespace.rstrip("/")
        for name in sorted(topics) + ["/clock", "/diagnostics"]:
            full = name if name.startswith("/") else f"{ns}/{name}"
            datatype = TOPIC_TYPES.get(name) or topic_type(name)
            self._topics[name] = (full, self._channel(full, datatype, latched=(name == "walls")))
        self.counts = {full: 0 for full, _ in self._topics.values()}
        self._seq = 0
        self._closed = False

    def _channel(self, topic, datatype, latched):
        schema = self._schemas.get(datatype)
        if schema is None:
            schema = self._schemas[datatype] = self._writer.register_msgdef(datatype, msgdef_text(datatype))
        # Register the channel ourselves to attach rosbag2's QoS metadata; mcap_ros2's Writer then reuses it.
        inner = self._writer._writer
        channel_id = inner.register_channel(topic=topic, message_encoding="cdr", schema_id=schema.id,
                                            metadata={"offered_qos_profiles": _qos_yaml(transient_local=latched,
                                                                                        depth=1 if latched else 10)})
        self._writer._channel_ids[topic] = channel_id
        return schema

    def _put(self, name, message, ns):
        if name not in self._topics:
            return
        topic, schema = self._topics[name]
        self._seq += 1
        self._writer.write_message(topic, schema, message, log_time=ns, publish_time=ns, sequence=self._seq)
        self.counts[topic] += 1

    def write(self, item):
        stamp, ns = _stamp(item.time)
        header = {"stamp": stamp, "frame_id": self.frame_id}
        if isinstance(item, Static):
            if len(item.walls):
                pts = np.zeros(len(item.walls), dtype=WALL_DTYPE)
                pts["x"], pts["y"], pts["z"] = item.walls[:, 0], item.walls[:, 1], item.walls[:, 2]
                self._put("walls", cloud_dict(pts, stamp, self.frame_id), ns)
            return
        if isinstance(item, Frame):
            self._put("particles", cloud_dict(pack_particles(item.parts), stamp, self.frame_id), ns)
            tip = item.probes.get("tip")
            if tip is not None and "displacement" in tip[1]:
                self._put("tip_displacement", probe_dict("displacement", tip[1]["displacement"], header), ns)
            for topic, quantity, value in probe_values(item.probes):
                self._put(topic, probe_dict(quantity, value, header), ns)
            if "strain_energy" in item.energies:
                self._put("strain_energy", {"data": item.energies["strain_energy"]}, ns)
            for name, r in item.walls.items():
                self._put(part_topic(name, "pose"), {"header": header, "pose": _pose(r["position"],
                                                                                     r["orientation"])}, ns)
                self._put(part_topic(name, "wrench"), {"header": header, "wrench": {
                    "force": _xyz(r["force"]), "torque": _xyz(r["moment"])}}, ns)
            for t, name, what, values in item.commands:       # stamped when they applied: a replay's stamps
                at, at_ns = _stamp(t)
                command = {"header": {"stamp": at, "frame_id": self.frame_id}}
                if what == "pose_cmd":
                    command["pose"] = _pose(*values)
                else:
                    command["twist"] = {"linear": _xyz(values[0]), "angular": _xyz(values[1])}
                self._put(part_topic(name, what), command, at_ns)
            self._put("/clock", {"clock": stamp}, ns)
        self._put("/diagnostics", _diagnostics(header, item), ns)

    def close(self):
        if self._closed:
            return
        self._closed = True
        try:
            self._writer.finish()
        finally:
            self._fh.close()


_LEVEL = {"running": 0, "finished": 0, "interrupted": 1, "water_lost": 1, "diverged": 2, "failed": 2}


def _diagnostics(header, item):
    status = item.status
    values = [{"key": k, "value": str(v)} for k, v in item.diagnostics.items()]
    return {"header": header, "status": [{"level": _LEVEL.get(status, 0), "name": "sph_fsi",
                                          "message": status, "hardware_id": "sph_fsi", "values": values}]}

