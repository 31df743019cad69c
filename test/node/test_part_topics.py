"""A wall driven from ROS, across processes: the node runs test/data/commanded_paddle.yaml (a paddle with
`motion: ros` above water in a tank) in lockstep; this process is the controller. It answers each frame's pose with
a twist command stamped at that frame's time, so the node runs exactly as far as it is commanded: the paddle's pose
follows the commanded velocity from each command's stamp, the node waits (and says so on /diagnostics) while no
command for the time now has come, a command it cannot follow (NaN, faster than motion_max_speed) is refused on
/diagnostics and the run goes on, and the MCAP recording holds the commands as they applied.
Discovery on localhost, in a ROS_DOMAIN_ID of this module's own (test_node.py takes the run's base and base + 1,
test_replay.py base + 2, test_probe_topics.py base + 3).
"""
import os
import random
import threading
import time
from pathlib import Path

import pytest

os.environ["ROS_AUTOMATIC_DISCOVERY_RANGE"] = "LOCALHOST"

import rclpy  # noqa: E402
from diagnostic_msgs.msg import DiagnosticArray  # noqa: E402
from geometry_msgs.msg import PoseStamped, TwistStamped, WrenchStamped  # noqa: E402
from rclpy.executors import SingleThreadedExecutor  # noqa: E402
from rclpy.qos import QoSProfile  # noqa: E402
from rclpy.signals import SignalHandlerOptions  # noqa: E402
from rosgraph_msgs.msg import Clock  # noqa: E402

from sph_fsi.messages import seconds_from_stamp, stamp_from_seconds  # noqa: E402

from .test_node import NodeProcess  # noqa: E402

SCENE = Path(__file__).resolve().parents[1] / "data" / "commanded_paddle.yaml"
_BASE = int(os.environ.get("ROS_DOMAIN_ID") or random.Random().randint(1, 100))
DOMAIN = 1 + (_BASE + 4) % 100
PERIOD = 0.01                    # s: the publish period, one outer step (the scene's timeseries_interval)
SPEED = -0.1                     # m/s: the paddle's commanded vertical velocity
PADDLE_Z = 0.15                  # m: its motion_point's height as built
NS = "/sph_fsi/parts/paddle"


class Controller:
    """rclpy in this process: the pose, wrench, /clock and /diagnostics it receives, and the commands it sends."""

    def __init__(self):
        self.ctx = rclpy.Context()
        rclpy.init(context=self.ctx, domain_id=DOMAIN, signal_handler_options=SignalHandlerOptions.NO)
        self.node = rclpy.create_node("paddle_controller", context=self.ctx)
        self.lock = threading.Lock()
        self.msgs = {topic: [] for topic in (f"{NS}/pose", f"{NS}/wrench", "/clock", "/diagnostics")}
        for topic, mtype in ((f"{NS}/pose", PoseStamped), (f"{NS}/wrench", WrenchStamped), ("/clock", Clock),
                             ("/diagnostics", DiagnosticArray)):
            self.node.create_subscription(mtype, topic, self._recorder(topic), QoSProfile(depth=500))
        self.twist = self.node.create_publisher(TwistStamped, f"{NS}/twist_cmd", QoSProfile(depth=10))
        self.executor = SingleThreadedExecutor(context=self.ctx)
        self.executor.add_node(self.node)
        self._stop = threading.Event()
        self.thread = threading.Thread(target=self._spin, daemon=True)
        self.thread.start()

    def _spin(self):
        while not self._stop.is_set():
            self.executor.spin_once(timeout_sec=0.05)

    def _recorder(self, topic):
        def record(msg):
            with self.lock:
                self.msgs[topic].append(msg)
        return record

    def since(self, topic, start=0):
        with self.lock:
            return list(self.msgs[topic][start:])

    def wait_for(self, topic, predicate, timeout):
        deadline = time.monotonic() + timeout
        while time.monotonic() < deadline:
            for m in self.since(topic):
                if predicate(m):
                    return m
            time.sleep(0.02)
        raise AssertionError(f"no matching message on {topic} within {timeout} s")

    def send(self, stamp, vz, wy=0.0):
        msg = TwistStamped()
        msg.header.stamp = stamp_from_seconds(stamp)
        msg.twist.linear.z = float(vz)
        msg.twist.angular.y = float(wy)
        self.twist.publish(msg)

    def close(self):
        self._stop.set()
        self.thread.join()
        self.executor.shutdown()
        self.node.destroy_node()
        rclpy.try_shutdown(context=self.ctx)


def _at(t):
    return lambda m: abs(seconds_from_stamp(m.header.stamp) - t) < 1e-9


def _messages_of(diagnostics):
    return [(s.message, {kv.key: kv.value for kv in s.values}) for m in diagnostics for s in m.status]


def test_a_wall_driven_from_ros_in_lockstep(tmp_path):
    controller = Controller()
    mcap = tmp_path / "paddle.mcap"
    node = NodeProcess(DOMAIN, [("scene", str(SCENE)), ("lockstep", "true"), ("publish_period", PERIOD),
                                ("mcap_path", str(mcap)), ("record_interval", 0.0), ("on_end", "stay")])
    try:
        first = controller.wait_for(f"{NS}/pose", _at(0.0), timeout=400.0)
        assert first.pose.position.z == pytest.approx(PADDLE_Z) and first.pose.orientation.w == pytest.approx(1.0)
        # without a command for t = 0 the node waits and says so
        controller.wait_for("/diagnostics", lambda m: m.status[0].message == "waiting for commands", timeout=30.0)
        time.sleep(0.5)
        assert max(seconds_from_stamp(c.clock) for c in controller.since("/clock")) == 0.0
        # each frame's command, stamped at its time: the node runs one period per command
        for k in range(5):
            controller.send(k * PERIOD, SPEED)
            pose = controller.wait_for(f"{NS}/pose", _at((k + 1) * PERIOD), timeout=60.0)
            assert pose.pose.position.z == pytest.approx(PADDLE_Z + SPEED * (k + 1) * PERIOD, abs=1e-12)
        time.sleep(0.5)                          # no command for t = 0.05: no further frame
        assert max(seconds_from_stamp(c.clock) for c in controller.since("/clock")) == pytest.approx(5 * PERIOD)
        wrench = controller.wait_for(f"{NS}/wrench", _at(5 * PERIOD), timeout=10.0)
        assert wrench.wrench.force.z == 0.0        # still above the water: nothing pushes it
        # a command it cannot follow is refused on /diagnostics, and the run goes on at the last velocity
        controller.send(5 * PERIOD, 2.0)          # 2 m/s > motion_max_speed 0.5
        controller.wait_for("/diagnostics", lambda m: "refused" in {kv.key: kv.value for kv in m.status[0].values}
                            .get("last_error", ""), timeout=30.0)
        pose = controller.wait_for(f"{NS}/pose", _at(6 * PERIOD), timeout=60.0)
        assert pose.pose.position.z == pytest.approx(PADDLE_Z + SPEED * 6 * PERIOD, abs=1e-12)
        errors = [v.get("last_error", "") for _, v in _messages_of(controller.since("/diagnostics"))]
        assert any("parts.paddle: command at t = 0.05 s refused: it moves a particle at 2 m/s, faster than "
                   "motion_max_speed = 0.5 m/s" in e for e in errors), errors
        controller.send(6 * PERIOD, float("nan"))
        controller.wait_for("/diagnostics", lambda m: "not finite" in {kv.key: kv.value for kv in m.status[0].values}
                            .get("last_error", ""), timeout=30.0)
    finally:
        assert node.stop() == 0, node.stderr()
        controller.close()
    from sph_fsi.recording.commands import read_commands
    recorded = read_commands(max(tmp_path.glob("paddle*.mcap"), key=lambda p: p.stat().st_mtime))   # the last run
    assert [round(c[1], 9) for c in recorded] == [round(k * PERIOD, 9) for k in range(5)]
    assert all(c[0] == "paddle" and c[2] == "twist_cmd" and c[3] == ((0.0, 0.0, SPEED), (0.0, 0.0, 0.0))
               for c in recorded)
