"""A closed loop through the node's topics: damp a tank's sloshing with a paddle driven from ROS.

    .venv/bin/python examples/slosh_controller.py [--gain 1.0] [--spacing 0.02] [--end-time 2.0] [--out runs/slosh]

runs the node on config/examples/sloshing_tank.yaml twice, in lockstep (the node waits each publish period for the
paddle's command, so the loop runs the same whatever the host's speed): once with the controller's gain 0 (the
paddle still) and once with `--gain`, each recorded to MCAP (OUT/gain_<g>.mcap), and prints the sloshing's amplitude
over each half second of both.

The controller reads the water's height next to the paddle (~/probes/left/surface) and the paddle's pose
(~/parts/paddle/pose) at each frame and answers with a velocity stamped at that frame's time
(~/parts/paddle/twist_cmd):

    u = -gain sqrt(g / d) (h - h0) - x / tau

the absorbing piston's law (water higher than at rest pushes the paddle back, so the water does work on it and its
sloshing loses that energy), with a slow pull back to where the paddle was built (tau = 2 s) so it does not drift.
"""
import argparse
import math
import os
import subprocess
import sys
import threading
import time
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]
SCENE = REPO / "config" / "examples" / "sloshing_tank.yaml"
PERIOD = 0.01          # s: the node's publish period, the controller's
DEPTH = 0.2            # m: the scene's geometry.depth
TAU = 2.0              # s: the paddle's pull back to its built place
MAX_SPEED = 0.45       # m/s: within the paddle's motion_max_speed (0.5)


class Controller:
    """An rclpy node: the left probe's height and the paddle's pose per stamp, a twist command for each frame."""

    def __init__(self, gain, domain):
        import rclpy
        from geometry_msgs.msg import PointStamped, PoseStamped, TwistStamped
        from rclpy.executors import SingleThreadedExecutor
        from rclpy.qos import QoSProfile
        from rclpy.signals import SignalHandlerOptions
        self.gain = gain
        self.ctx = rclpy.Context()
        rclpy.init(context=self.ctx, domain_id=domain, signal_handler_options=SignalHandlerOptions.NO)
        self.node = rclpy.create_node("slosh_controller", context=self.ctx)
        self.twist_type = TwistStamped
        self.lock = threading.Lock()
        self.heights, self.right, self.poses, self.rows = {}, {}, {}, []
        self.rest = None
        qos = QoSProfile(depth=100)
        self.node.create_subscription(PointStamped, "/sph_fsi/probes/left/surface", self._on_left, qos)
        self.node.create_subscription(PointStamped, "/sph_fsi/probes/right/surface", self._on_right, qos)
        self.node.create_subscription(PoseStamped, "/sph_fsi/parts/paddle/pose", self._on_pose, qos)
        self.command = self.node.create_publisher(TwistStamped, "/sph_fsi/parts/paddle/twist_cmd", qos)
        self.executor = SingleThreadedExecutor(context=self.ctx)
        self.executor.add_node(self.node)
        self._stop = threading.Event()
        self.thread = threading.Thread(target=self._spin, daemon=True)
        self.thread.start()

    @staticmethod
    def _ns(stamp):
        return stamp.sec * 1_000_000_000 + stamp.nanosec

    def _on_left(self, msg):
        with self.lock:
            self.heights[self._ns(msg.header.stamp)] = msg.point.z
            self._answer(msg.header.stamp)

    def _on_right(self, msg):
        with self.lock:
            self.right[self._ns(msg.header.stamp)] = msg.point.z

    def _on_pose(self, msg):
        with self.lock:
            self.poses[self._ns(msg.header.stamp)] = msg.pose.position.x
            self._answer(msg.header.stamp)

    def _answer(self, stamp):
        """Once a frame's height and pose are both in: its command, stamped at the frame's time."""
        ns = self._ns(stamp)
        if ns not in self.heights or ns not in self.poses:
            return
        height, x = self.heights.pop(ns), self.poses.pop(ns)
        if self.rest is None:
            self.rest = height
        u = -self.gain * math.sqrt(9.81 / DEPTH) * (height - self.rest) - x / TAU
        u = max(-MAX_SPEED, min(MAX_SPEED, u))
        msg = self.twist_type()
        msg.header.stamp = stamp
        msg.twist.linear.x = u
        self.command.publish(msg)
        self.rows.append((ns * 1e-9, height, x, u))

    def _spin(self):
        while not self._stop.is_set():
            self.executor.spin_once(timeout_sec=0.02)

    def close(self):
        import rclpy
        self._stop.set()
        self.thread.join()
        self.executor.shutdown()
        self.node.destroy_node()
        rclpy.try_shutdown(context=self.ctx)


def run(gain, spacing, end_time, out_dir, timeout=900.0):
    """One closed-loop run: the node (lockstep, its MCAP into out_dir) and the controller at `gain`. Returns
    {'times', 'left', 'right' (m, the probes' heights per frame), 'paddle' (m), 'mcap'}."""
    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    domain = int(os.environ.get("ROS_DOMAIN_ID") or 0)
    mcap = out_dir / f"gain_{gain:g}.mcap"
    env = dict(os.environ, ROS_AUTOMATIC_DISCOVERY_RANGE="LOCALHOST")
    controller = Controller(gain, domain)
    node = subprocess.Popen([sys.executable, "-m", "sph_fsi", "--ros-args", "-p", f"scene:={SCENE}",
                             "-p", "lockstep:=true", "-p", f"publish_period:={PERIOD}",
                             "-p", f"numerics.spacing:={spacing}", "-p", f"end_time:={end_time}",
                             "-p", "on_end:=exit", "-p", f"mcap_path:={mcap}", "-p", "record_interval:=0.0"],
                            env=env, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
    try:
        _, err = node.communicate(timeout=timeout)
        if node.returncode != 0:
            raise RuntimeError(f"the node ended with status {node.returncode}: {err[-2000:]}")
    finally:
        if node.poll() is None:
            node.kill()
        time.sleep(0.2)             # the last frames' messages
        controller.close()
    rows = sorted(controller.rows)
    right = controller.right
    return {"times": [r[0] for r in rows], "left": [r[1] for r in rows], "paddle": [r[2] for r in rows],
            "right": [right.get(round(r[0] * 1e9)) for r in rows], "mcap": mcap}


def amplitudes(result, window=0.5):
    """The sloshing's amplitude, half the range of (left - right) / 2 [m], over each `window` s: [(from, amplitude)]."""
    t, left, right = result["times"], result["left"], result["right"]
    slosh = [(a - b) / 2 for a, b in zip(left, right) if b is not None]
    times = [ti for ti, b in zip(t, right) if b is not None]
    out = []
    start = 0.0
    while start < times[-1]:
        values = [s for ti, s in zip(times, slosh) if start < ti <= start + window]
        if values:
            out.append((start, (max(values) - min(values)) / 2))
        start += window
    return out


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--gain", type=float, default=1.0)
    p.add_argument("--spacing", type=float, default=0.02)
    p.add_argument("--end-time", type=float, default=2.0)
    p.add_argument("--out", default="runs/slosh")
    args = p.parse_args(argv)
    still = run(0.0, args.spacing, args.end_time, args.out)
    driven = run(args.gain, args.spacing, args.end_time, args.out)
    print(f"sloshing amplitude (mm), paddle still / driven at gain {args.gain:g}; recordings in {args.out}/")
    for (start, a), (_, b) in zip(amplitudes(still), amplitudes(driven)):
        print(f"  {start:4.1f}-{start + 0.5:4.1f} s: {1e3 * a:6.2f} / {1e3 * b:6.2f}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
