"""The probes' topics, in-process: sph_fsi.publishing on an rclpy node in this process publishes a few outer steps
of the geometry_probes scene (test/data/geometry_probes.yaml: a probe of every kind; ~9,000 particles at 10 mm,
built once per module), and a subscriber node in the same process receives them.

Each probe quantity has its own topic, ~/probes/<name>/<quantity>, of its own type, carrying the value that
Simulation.probe_readings() had at the message's stamp (float64 end to end: equal to the bit), stamped with that
simulated time; a scene without probes (hydrostatic) has no ~/probes topics, and a reset to it removes them.
Discovery on localhost, in a ROS_DOMAIN_ID of this module's own (test_node.py takes the run's base and base + 1,
test_replay.py base + 2 and + 3).
"""
import copy
import os
import random
import threading
import time
from collections import defaultdict
from pathlib import Path

import pytest

os.environ["ROS_AUTOMATIC_DISCOVERY_RANGE"] = "LOCALHOST"

import rclpy  # noqa: E402
from geometry_msgs.msg import PointStamped, Vector3Stamped, WrenchStamped  # noqa: E402
from rclpy.executors import SingleThreadedExecutor  # noqa: E402
from rclpy.qos import QoSProfile, ReliabilityPolicy  # noqa: E402
from rclpy.signals import SignalHandlerOptions  # noqa: E402
from sensor_msgs.msg import FluidPressure  # noqa: E402

from sph_fsi.points import PROBE_QUANTITIES, QUANTITY_TYPES  # noqa: E402
from sph_fsi.publishing import Publishing  # noqa: E402
from sph_fsi.replay import message_class  # noqa: E402

SCENE = Path(__file__).resolve().parents[1] / "data" / "geometry_probes.yaml"
_BASE = int(os.environ.get("ROS_DOMAIN_ID") or random.Random().randint(1, 100))
DOMAIN = 1 + (_BASE + 3) % 100
FRAMES = 4                                   # t = 0 and three outer steps (2 ms each)
NS = "/sph_fsi/probes"
# the scene's probes (tip: point, wall_p: pressure, level: water_height, plate_force and floor_force: force)
EXPECTED = {f"{NS}/tip/displacement": Vector3Stamped, f"{NS}/tip/velocity": Vector3Stamped,
            f"{NS}/wall_p/pressure": FluidPressure, f"{NS}/level/surface": PointStamped,
            f"{NS}/plate_force/force": WrenchStamped, f"{NS}/floor_force/force": WrenchStamped}
TYPE_NAMES = {Vector3Stamped: "geometry_msgs/msg/Vector3Stamped", FluidPressure: "sensor_msgs/msg/FluidPressure",
              PointStamped: "geometry_msgs/msg/PointStamped", WrenchStamped: "geometry_msgs/msg/WrenchStamped"}


def stamp_ns(stamp):
    return stamp.sec * 1_000_000_000 + stamp.nanosec


pytestmark = pytest.mark.usefixtures("one_numba_thread")   # their simulations on one thread


def build(scene, overrides=()):
    from sph_fsi_core.scene import load_scene
    from sph_fsi_core.simulation import Simulation
    return Simulation(load_scene(str(scene), list(overrides)))


@pytest.fixture(scope="module")
def sim():
    return build(SCENE)


class Ros:
    """One context in this process: the node `sph_fsi` (what the real node publishes through) and a listener."""

    def __init__(self):
        self.ctx = rclpy.Context()
        rclpy.init(context=self.ctx, domain_id=DOMAIN, signal_handler_options=SignalHandlerOptions.NO)
        self.node = rclpy.create_node("sph_fsi", context=self.ctx)
        self.listener = rclpy.create_node("sph_fsi_probe_listener", context=self.ctx)
        self.out = Publishing(self.node)
        self.lock = threading.Lock()
        self.msgs = defaultdict(list)
        self.executor = SingleThreadedExecutor(context=self.ctx)
        self.executor.add_node(self.node)
        self.executor.add_node(self.listener)
        self._stop = threading.Event()
        self.thread = threading.Thread(target=self._spin, daemon=True)
        self.thread.start()

    def _spin(self):
        while not self._stop.is_set():
            self.executor.spin_once(timeout_sec=0.05)

    def subscribe(self, topic, mtype):
        def record(msg):
            with self.lock:
                self.msgs[topic].append(msg)
        self.listener.create_subscription(mtype, topic, record,
                                          QoSProfile(depth=100, reliability=ReliabilityPolicy.RELIABLE))

    def published(self):
        """{topic: [types]} of the node `sph_fsi` now, its ~/probes topics only."""
        return {name: types for name, types in self.node.get_publisher_names_and_types_by_node("sph_fsi", "/")
                if name.startswith(NS + "/")}

    def close(self):
        self._stop.set()
        self.thread.join()
        self.executor.shutdown()
        self.listener.destroy_node()
        self.node.destroy_node()
        rclpy.try_shutdown(context=self.ctx)


@pytest.fixture(scope="module")
def ros():
    r = Ros()
    yield r
    r.close()


def wait_until(predicate, timeout=20.0, what="condition"):
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        if predicate():
            return
        time.sleep(0.02)
    raise AssertionError(f"{what}: not within {timeout} s")


def value_of(msg):
    """A probe message's value, as Simulation.probe_readings() gives it."""
    if isinstance(msg, Vector3Stamped):
        return (msg.vector.x, msg.vector.y, msg.vector.z)
    if isinstance(msg, FluidPressure):
        assert msg.variance == 0.0
        return msg.fluid_pressure
    if isinstance(msg, PointStamped):
        return (msg.point.x, msg.point.y, msg.point.z)
    t = msg.wrench.torque
    assert (t.x, t.y, t.z) == (0.0, 0.0, 0.0)
    return (msg.wrench.force.x, msg.wrench.force.y, msg.wrench.force.z)


def reading_of(readings, topic):
    """The value a topic /sph_fsi/probes/<name>/<quantity> must carry, from Simulation.probe_readings()."""
    name, quantity = topic[len(NS) + 1:].split("/")
    return readings[name][1][quantity]


def test_every_kind_of_probe_has_topics():
    """Each probe kind of the core has its topics, and each topic's quantity a message type replay can load."""
    from sph_fsi_core.probes import KINDS
    assert set(PROBE_QUANTITIES) == set(KINDS)
    assert {q for qs in PROBE_QUANTITIES.values() for q in qs} == set(QUANTITY_TYPES)
    for type_name in QUANTITY_TYPES.values():
        assert TYPE_NAMES[message_class(type_name)] == type_name


def test_probe_topics_carry_the_simulators_readings_stamped_with_simulated_time(sim, ros):
    assert {name: kind for name, (kind, _) in sim.probe_readings().items()} == {
        "tip": "point", "wall_p": "pressure", "level": "water_height", "plate_force": "force",
        "floor_force": "force"}
    ros.out.sync_topics(sim, "reliable")
    wait_until(lambda: set(ros.published()) == set(EXPECTED), what="the probe publishers")
    assert ros.published() == {t: [TYPE_NAMES[m]] for t, m in EXPECTED.items()}
    for topic, mtype in EXPECTED.items():
        ros.subscribe(topic, mtype)
    ros.subscribe("/sph_fsi/tip_displacement", Vector3Stamped)   # kept for a probe named tip, point kind too
    wait_until(lambda: all(ros.out.pubs[t[len("/sph_fsi/"):]].get_subscription_count() >= 1
                           for t in list(EXPECTED) + ["/sph_fsi/tip_displacement"]), what="matching")
    readings = {}
    for k in range(FRAMES):
        if k:
            sim.step()
        readings[round(sim.time * 1e9)] = copy.deepcopy(sim.probe_readings())
        assert ros.out.publish_frame(sim, "map")
    wait_until(lambda: all(len(ros.msgs[t]) >= FRAMES for t in EXPECTED), what="every frame's messages")
    time.sleep(0.2)   # nothing more comes
    times = sorted(readings)
    assert times == [round(k * 2e6) for k in range(FRAMES)]
    for topic in EXPECTED:
        msgs = ros.msgs[topic]
        assert [stamp_ns(m.header.stamp) for m in msgs] == times, topic
        for m in msgs:
            assert m.header.frame_id == "map"
            assert value_of(m) == reading_of(readings[stamp_ns(m.header.stamp)], topic), topic
    # the kept topic: the point probe's displacement, the same messages
    assert [(stamp_ns(m.header.stamp), value_of(m)) for m in ros.msgs["/sph_fsi/tip_displacement"]] == [
        (stamp_ns(m.header.stamp), value_of(m)) for m in ros.msgs[f"{NS}/tip/displacement"]]
    # not a comparison of zeros: by the last frame the plate moves, the water presses on the wall and the floor,
    # and the surface is above the probe's position, below the water's initial 0.1 m height plus a spacing
    last = {t: value_of(ros.msgs[t][-1]) for t in EXPECTED}
    assert abs(last[f"{NS}/tip/velocity"][2]) > 1e-4 and abs(last[f"{NS}/tip/displacement"][2]) > 1e-6
    assert last[f"{NS}/wall_p/pressure"] > 0.0
    assert last[f"{NS}/floor_force/force"][2] < 0.0            # the water pushes the floor down
    x, y, z = last[f"{NS}/level/surface"]
    assert (x, y) == (0.05, 0.05) and 0.09 < z < 0.11
    assert readings[times[-1]]["level"][1]["height"] == z       # the probe stands at z = 0


def test_a_scene_without_probes_has_no_probe_topics(sim, ros):
    """A reset from the probes' scene to one without probes (hydrostatic) removes every ~/probes topic."""
    ros.out.sync_topics(sim, "reliable")
    wait_until(lambda: set(ros.published()) == set(EXPECTED), what="the probe publishers")
    hydrostatic = build("hydrostatic", ["numerics.spacing=0.005"])
    assert hydrostatic.probe_readings() == {}
    ros.out.sync_topics(hydrostatic, "reliable")
    assert not [name for name in ros.out.pubs if name.startswith("probes/")], ros.out.pubs
    wait_until(lambda: ros.published() == {}, what="the probe publishers gone")
    assert ros.out.publish_frame(hydrostatic, "map")
    published = dict(ros.node.get_publisher_names_and_types_by_node("sph_fsi", "/"))
    assert "/sph_fsi/particles" in published and "/sph_fsi/tip_displacement" not in published
    assert not [name for name in published if "probes" in name], published
