"""The node's topics: their publishers (only those the scene has, with the chosen QoS) and the messages built from
a simulation, stamped with simulated time. Called from the simulation thread only (sph_fsi.runner's `out`).

~/particles (PointCloud2, moving particles of every phase), ~/walls (PointCloud2, fixed particles; reliable,
transient-local, after every build), ~/tip_displacement (Vector3Stamped, a probe named 'tip'), ~/strain_energy
(Float64, a solid), one topic per probe quantity, ~/probes/<name>/<quantity> (displacement and velocity:
Vector3Stamped, pressure: FluidPressure, surface: PointStamped, force: WrenchStamped; sph_fsi.points), for each wall
driven by commands ~/parts/<name>/pose and ~/parts/<name>/wrench, and the subscriptions it takes commands on,
~/parts/<name>/pose_cmd and ~/parts/<name>/twist_cmd (the callbacks on the executor's thread hand them to
`on_command`), /clock and /diagnostics (always). A frame's messages all carry the simulated time at the end of its
last outer step.
"""
from diagnostic_msgs.msg import DiagnosticArray, DiagnosticStatus, KeyValue
from geometry_msgs.msg import PointStamped, PoseStamped, TwistStamped, Vector3, Vector3Stamped, WrenchStamped
from rclpy.qos import DurabilityPolicy, HistoryPolicy, QoSProfile, ReliabilityPolicy, qos_profile_sensor_data
from rosgraph_msgs.msg import Clock
from sensor_msgs.msg import FluidPressure, PointCloud2
from std_msgs.msg import Float64, Header

from .messages import part_messages, probe_message, stamp_from_seconds, structured_to_cloud, walls_to_cloud
from .points import (command_numbers, command_values, commanded_parts, part_readings, particle_points,
                     probe_readings, probe_values, topic_plan, topic_type, wall_positions)

__all__ = ["Publishing", "TOPIC_TYPES", "LEVELS", "topic_class"]

TOPIC_TYPES = {"particles": PointCloud2, "walls": PointCloud2, "tip_displacement": Vector3Stamped,
               "strain_energy": Float64}
_CLASSES = {"sensor_msgs/msg/PointCloud2": PointCloud2, "geometry_msgs/msg/Vector3Stamped": Vector3Stamped,
            "std_msgs/msg/Float64": Float64, "sensor_msgs/msg/FluidPressure": FluidPressure,
            "geometry_msgs/msg/PointStamped": PointStamped, "geometry_msgs/msg/WrenchStamped": WrenchStamped,
            "geometry_msgs/msg/PoseStamped": PoseStamped, "geometry_msgs/msg/TwistStamped": TwistStamped}
# the commanded walls' topics the node takes (the others it publishes)
COMMAND_TOPICS = ("pose_cmd", "twist_cmd")
LEVELS = {"ok": DiagnosticStatus.OK, "warn": DiagnosticStatus.WARN, "error": DiagnosticStatus.ERROR}


def topic_class(name):
    """A topic_plan name ('particles', 'probes/tip/velocity') -> its message class."""
    return _CLASSES[topic_type(name)]


class Publishing:
    """The publishers of one node; `ok()` turns False once its context shuts down (publishing then stops
    quietly)."""

    def __init__(self, node, on_command=None):
        """`on_command(part, stamp, kind, values, source)`: where a commanded wall's commands go (sph_fsi.runner
        .Runner.part_command), with the message's numbers as `source`; a command that cannot be read arrives as
        kind 'unreadable' with the reason."""
        self.node = node
        self.on_command = on_command
        self.pubs = {}
        self.subs = {}
        self._points = {}                       # each commanded wall's motion_point (its pose commands' origin)
        self.qos = None                         # the streamed topics' QoS name, once created
        self.clock = node.create_publisher(Clock, "/clock", QoSProfile(depth=10))
        self.diagnostics = node.create_publisher(DiagnosticArray, "/diagnostics", QoSProfile(depth=10))

    def ok(self):
        return self.node.context.ok()

    def sync_topics(self, sim, qos):
        """Publishers for the topics `sim` has (topic_plan), dropping the others; a new QoS recreates every
        streamed topic (~/walls keeps its own)."""
        want = topic_plan(sim)
        if self.qos is not None and qos != self.qos:
            for name in list(self.pubs):
                if name != "walls":
                    self.node.destroy_publisher(self.pubs.pop(name))
        self.qos = qos
        for name in list(self.pubs):
            if name not in want:
                self.node.destroy_publisher(self.pubs.pop(name))
        stream_qos = qos_profile_sensor_data if qos == "sensor_data" else QoSProfile(depth=10)
        latched = QoSProfile(depth=1, history=HistoryPolicy.KEEP_LAST, reliability=ReliabilityPolicy.RELIABLE,
                             durability=DurabilityPolicy.TRANSIENT_LOCAL)
        self._points = {name: sim.boundary.part_motion(name).point.copy() for name in commanded_parts(sim)}
        takes = {t for t in want if t.rsplit("/", 1)[-1] in COMMAND_TOPICS}
        for name in list(self.subs):
            if name not in takes:
                self.node.destroy_subscription(self.subs.pop(name))
        for name in sorted(takes - set(self.subs)):
            self.subs[name] = self.node.create_subscription(topic_class(name), f"~/{name}",
                                                            self._command_callback(name), QoSProfile(depth=10))
        for name in sorted(want - takes - set(self.pubs)):
            self.pubs[name] = self.node.create_publisher(topic_class(name), f"~/{name}",
                                                         latched if name == "walls" else stream_qos)

    def _command_callback(self, topic):
        """The callback of a commanded wall's command topic (executor thread): the command, read, to on_command."""
        part, what = topic.split("/")[1], topic.rsplit("/", 1)[1]

        def take(msg):
            stamp, numbers = command_numbers(what, msg)
            try:
                kind, values = command_values(self._points[part], what, numbers)
            except ValueError as exc:
                kind, values, numbers = "unreadable", str(exc), None
            if self.on_command is not None:
                self.on_command(part, stamp, kind, values, (what, numbers))
        return take

    def publish_walls(self, sim, frame_id):
        pub = self.pubs.get("walls")
        if pub is None or not self.ok():
            return
        pub.publish(walls_to_cloud(wall_positions(sim), stamp_from_seconds(sim.time), frame_id))

    def publish_frame(self, sim, frame_id):
        """Particles, probes, energies and /clock at the simulated time; False if the node shut down."""
        if not self.ok():
            return False
        header = Header(stamp=stamp_from_seconds(sim.time), frame_id=frame_id)
        try:
            pub = self.pubs.get("particles")
            if pub is not None:
                pub.publish(structured_to_cloud(particle_points(sim), header.stamp, header.frame_id))
            pub = self.pubs.get("tip_displacement")
            if pub is not None:
                d = sim.probe_displacements()["tip"]
                pub.publish(Vector3Stamped(header=header, vector=Vector3(x=float(d[0]), y=float(d[1]),
                                                                         z=float(d[2]))))
            for topic, quantity, value in probe_values(probe_readings(sim)):
                pub = self.pubs.get(topic)
                if pub is not None:
                    pub.publish(probe_message(quantity, value, header))
            if commanded_parts(sim):
                for topic, msg in part_messages(part_readings(sim), header):
                    pub = self.pubs.get(topic)
                    if pub is not None:
                        pub.publish(msg)
            pub = self.pubs.get("strain_energy")
            if pub is not None:
                pub.publish(Float64(data=float(sim.energies()["strain_energy"])))
            self.clock.publish(Clock(clock=header.stamp))
        except Exception:
            if self.ok():
                raise
            return False   # shut down during the publish
        return True

    def publish_diagnostics(self, t, level, message, values, frame_id):
        """One DiagnosticStatus 'sph_fsi' stamped `t`; level 'ok' | 'warn' | 'error'."""
        if not self.ok():
            return
        status = DiagnosticStatus(level=LEVELS[level], name="sph_fsi", message=message, hardware_id="sph_fsi",
                                  values=[KeyValue(key=k, value=v) for k, v in values.items()])
        msg = DiagnosticArray(header=Header(stamp=stamp_from_seconds(t), frame_id=frame_id), status=[status])
        try:
            self.diagnostics.publish(msg)
        except Exception:
            if self.ok():
                raise
