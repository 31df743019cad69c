"""`sph-fsi replay FILE.mcap`: republish a recording onto ROS 2 topics with rclpy (no ros2 bag needed).

Messages go out in log-time order, as the recorded CDR bytes (Publisher.publish accepts serialized bytes), so
every header stamp is the recorded one. Pacing follows log time (for sph_fsi recordings: simulated time), scaled
by `rate` (2 = twice as fast; 0 = as fast as possible). QoS per topic follows the recording's
`offered_qos_profiles` metadata where present: transient-local topics (the walls) stay transient-local;
everything else is reliable, depth 100. SIGINT/SIGTERM stop playback cleanly (exit status 130).
"""
import importlib
import os
import signal
import sys
import threading
import time

__all__ = ["replay", "message_class"]


def message_class(type_name):
    """'sensor_msgs/msg/PointCloud2' -> the rclpy message class."""
    parts = type_name.split("/")
    if len(parts) == 2:
        parts = [parts[0], "msg", parts[1]]
    if len(parts) != 3:
        raise ValueError(f"not a ROS 2 message type: {type_name!r}")
    return getattr(importlib.import_module(f"{parts[0]}.{parts[1]}"), parts[2])


def _qos(metadata):
    from rclpy.qos import DurabilityPolicy, HistoryPolicy, QoSProfile, ReliabilityPolicy
    text = (metadata or {}).get("offered_qos_profiles", "")
    if "durability: 1" in text:
        return QoSProfile(depth=1, history=HistoryPolicy.KEEP_LAST, reliability=ReliabilityPolicy.RELIABLE,
                          durability=DurabilityPolicy.TRANSIENT_LOCAL)
    return QoSProfile(depth=100, reliability=ReliabilityPolicy.RELIABLE)


def replay(path, rate=1.0, wait_for_subscribers=0, wait_timeout=30.0, node_name="sph_fsi_replay"):
    if rate < 0:
        raise ValueError(f"--rate {rate:g}: allowed: >= 0 (0 = as fast as possible)")
    if not os.path.isfile(path):
        raise ValueError(f"{path!r}: no such file; allowed: an .mcap recording")
    from mcap.reader import make_reader
    stop = threading.Event()
    state = {"signum": None}

    def on_signal(signum, _frame):
        state["signum"] = signum
        stop.set()

    old = {s: signal.signal(s, on_signal) for s in (signal.SIGINT, signal.SIGTERM)}
    from .ament import ensure_ament_prefix
    ensure_ament_prefix()
    import rclpy
    from rclpy.signals import SignalHandlerOptions
    ctx = rclpy.Context()
    rclpy.init(context=ctx, signal_handler_options=SignalHandlerOptions.NO)
    node = None
    sent = 0
    try:
        node = rclpy.create_node(node_name, context=ctx)
        with open(path, "rb") as fh:
            reader = make_reader(fh)
            summary = reader.get_summary()
            if summary is None:
                raise ValueError(f"{path!r}: no MCAP summary (an unfinished recording?)")
            pubs = {}
            for cid, ch in summary.channels.items():
                schema = summary.schemas[ch.schema_id]
                if ch.message_encoding != "cdr":
                    continue
                pubs[cid] = node.create_publisher(message_class(schema.name), ch.topic, _qos(ch.metadata))
            if wait_for_subscribers > 0:
                deadline = time.monotonic() + wait_timeout
                while not stop.is_set() and any(p.get_subscription_count() < wait_for_subscribers
                                                for p in pubs.values()):
                    if time.monotonic() > deadline:
                        missing = [p.topic_name for p in pubs.values()
                                   if p.get_subscription_count() < wait_for_subscribers]
                        sys.stderr.write(f"sph-fsi replay: no subscribers on {', '.join(missing)} after "
                                         f"{wait_timeout:g} s; playing anyway\n")
                        break
                    stop.wait(0.05)
                stop.wait(0.3)   # matched on our side: give the subscribers a moment to match us too
            t0_log = wall0 = None
            for _schema, channel, message in reader.iter_messages(log_time_order=True):
                if stop.is_set():
                    break
                pub = pubs.get(channel.id)
                if pub is None:
                    continue
                if t0_log is None:
                    t0_log, wall0 = message.log_time, time.monotonic()
                if rate > 0:
                    wait = wall0 + (message.log_time - t0_log) * 1e-9 / rate - time.monotonic()
                    if wait > 0 and stop.wait(wait):
                        break
                pub.publish(bytes(message.data))
                sent += 1
        if not stop.is_set():
            stop.wait(0.5)   # let reliable subscribers take the last messages
        sys.stderr.write(f"sph-fsi replay: {sent} messages from {path}\n")
    finally:
        if node is not None:
            node.destroy_node()
        rclpy.try_shutdown(context=ctx)
        for s, h in old.items():
            signal.signal(s, h)
    return 130 if state["signum"] is not None else 0
