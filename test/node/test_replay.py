"""`sph-fsi replay` as a real subprocess, and the node's recording parameters.

Replay: a recording made by `sph-fsi run --mcap` is republished with rclpy; a subscriber in this process must
receive every recorded message, per topic in the recorded order, with the recorded header stamps (and /clock
values), paced by the recorded (simulated) time scaled by --rate.
Node: a node run with mcap_path/rrd_path ends (on_end exit, and SIGINT mid-run) with both files whole.
"""
import csv
import json
import os
import random
import signal
import subprocess
import sys
import threading
import time
from collections import defaultdict
from pathlib import Path

import pytest

os.environ["ROS_AUTOMATIC_DISCOVERY_RANGE"] = "LOCALHOST"

import rclpy  # noqa: E402
from rclpy.executors import SingleThreadedExecutor  # noqa: E402
from rclpy.qos import DurabilityPolicy, QoSProfile, ReliabilityPolicy  # noqa: E402
from rclpy.signals import SignalHandlerOptions  # noqa: E402

from sph_fsi.replay import message_class  # noqa: E402

PYTHON = str(Path(sys.prefix) / "bin" / "python")
RERUN = str(Path(sys.prefix) / "bin" / "rerun")
_BASE = int(os.environ.get("ROS_DOMAIN_ID") or random.Random().randint(1, 100))
DOMAIN = 1 + (_BASE + 1) % 100       # test_node.py takes the base and base + 1 (see there)
NODE_DOMAIN = 1 + (_BASE + 2) % 100
SMALL = ["--set", "numerics.spacing=0.002"]
TOPICS = {"/sph_fsi/particles": "sensor_msgs/msg/PointCloud2", "/sph_fsi/walls": "sensor_msgs/msg/PointCloud2",
          "/sph_fsi/tip_displacement": "geometry_msgs/msg/Vector3Stamped",
          "/sph_fsi/probes/tip/displacement": "geometry_msgs/msg/Vector3Stamped",
          "/sph_fsi/strain_energy": "std_msgs/msg/Float64", "/clock": "rosgraph_msgs/msg/Clock",
          "/diagnostics": "diagnostic_msgs/msg/DiagnosticArray"}


def env(domain=DOMAIN):
    e = dict(os.environ)
    e.update(ROS_DOMAIN_ID=str(domain), ROS_AUTOMATIC_DISCOVERY_RANGE="LOCALHOST", NUMBA_NUM_THREADS="1",
             PYTHONUNBUFFERED="1", RERUN_ANALYTICS="0")
    return e


def _key(topic, msg):
    """What identifies a message in order: its stamp (ns), and a value."""
    if topic == "/clock":
        return msg.clock.sec * 10**9 + msg.clock.nanosec, None
    if topic.endswith("strain_energy"):
        return None, msg.data
    stamp = msg.header.stamp.sec * 10**9 + msg.header.stamp.nanosec
    if topic.endswith("displacement"):    # tip_displacement, probes/tip/displacement
        return stamp, (msg.vector.x, msg.vector.y, msg.vector.z)
    if topic == "/diagnostics":
        return stamp, msg.status[0].message
    return stamp, (msg.width, bytes(msg.data[:64]))


def recorded(path):
    """{topic: [(log time ns, key)]} from the MCAP, decoded by mcap-ros2-support."""
    from mcap.reader import make_reader
    from mcap_ros2.decoder import DecoderFactory
    out = defaultdict(list)
    with open(path, "rb") as fh:
        for _s, ch, m, msg in make_reader(fh, decoder_factories=[DecoderFactory()]).iter_decoded_messages(
                log_time_order=True):
            out[ch.topic].append((m.log_time, _key(ch.topic, msg)))
    return out


class Subscriber:
    def __init__(self, domain):
        self.ctx = rclpy.Context()
        rclpy.init(context=self.ctx, domain_id=domain, signal_handler_options=SignalHandlerOptions.NO)
        self.node = rclpy.create_node("sph_fsi_replay_test", context=self.ctx)
        self.lock = threading.Lock()
        self.msgs = defaultdict(list)
        for topic, typ in TOPICS.items():
            qos = (QoSProfile(depth=1, reliability=ReliabilityPolicy.RELIABLE,
                              durability=DurabilityPolicy.TRANSIENT_LOCAL) if topic.endswith("walls")
                   else QoSProfile(depth=500, reliability=ReliabilityPolicy.RELIABLE))
            self.node.create_subscription(message_class(typ), topic, self._cb(topic), qos)
        self.executor = SingleThreadedExecutor(context=self.ctx)
        self.executor.add_node(self.node)
        self._stop = threading.Event()
        self.thread = threading.Thread(target=self._spin, daemon=True)
        self.thread.start()

    def _cb(self, topic):
        def cb(msg):
            with self.lock:
                self.msgs[topic].append((time.monotonic(), _key(topic, msg)))
        return cb

    def _spin(self):
        while not self._stop.is_set():
            self.executor.spin_once(timeout_sec=0.05)

    def close(self):
        self._stop.set()
        self.thread.join()
        self.executor.shutdown()
        self.node.destroy_node()
        rclpy.try_shutdown(context=self.ctx)


@pytest.fixture(scope="module")
def recording(tmp_path_factory):
    d = tmp_path_factory.mktemp("replay")
    path = d / "run.mcap"
    r = subprocess.run([PYTHON, "-m", "sph_fsi.cli", "run", "cantilever", *SMALL, "--end-time", "0.02",
                        "--record-interval", "0.001", "--mcap", str(path), "--out", str(d / "out")],
                       env=env(), capture_output=True, text=True, timeout=600)
    assert r.returncode == 0, r.stderr
    return path


def test_replay_delivers_recorded_messages_in_order_with_recorded_stamps(recording):
    expected = recorded(recording)
    assert {t: len(v) for t, v in expected.items()} == {
        "/sph_fsi/particles": 21, "/sph_fsi/walls": 1, "/sph_fsi/tip_displacement": 21,
        "/sph_fsi/probes/tip/displacement": 21, "/sph_fsi/strain_energy": 21, "/clock": 21, "/diagnostics": 22}
    sub = Subscriber(DOMAIN)
    try:
        rate = 0.04      # 0.02 s of simulated time over 0.5 s
        r = subprocess.run([PYTHON, "-m", "sph_fsi.cli", "replay", str(recording), "--rate", str(rate),
                            "--wait-for-subscribers", "1"], env=env(), capture_output=True, text=True, timeout=120)
        assert r.returncode == 0, r.stderr
        deadline = time.monotonic() + 10
        while time.monotonic() < deadline:
            with sub.lock:
                if all(len(sub.msgs[t]) >= len(v) for t, v in expected.items()):
                    break
            time.sleep(0.05)
        with sub.lock:
            got = {t: list(v) for t, v in sub.msgs.items()}
    finally:
        sub.close()
    for topic, msgs in expected.items():
        assert [k for _, k in got.get(topic, [])] == [k for _, k in msgs], topic
    # paced by simulated time: /clock arrivals span the recording's 0.02 s divided by the rate
    arrivals = [a for a, _ in got["/clock"]]
    span = arrivals[-1] - arrivals[0]
    assert 0.8 * 0.02 / rate < span < 0.02 / rate + 2.0, span


def test_replay_bad_input():
    r = subprocess.run([PYTHON, "-m", "sph_fsi.cli", "replay", "/nonexistent.mcap"], env=env(),
                       capture_output=True, text=True, timeout=60)
    assert r.returncode == 2 and "/nonexistent.mcap" in r.stderr


def _node(params, domain):
    cmd = [PYTHON, "-m", "sph_fsi", "--ros-args"]
    for k, v in params.items():
        cmd += ["-p", f"{k}:={v}"]
    return subprocess.Popen(cmd, env=env(domain), stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)


@pytest.mark.parametrize("ending", ["end_time", "SIGINT"])
def test_node_records_mcap_and_rrd(ending, tmp_path):
    from mcap.reader import make_reader
    mcap, rrd, out = tmp_path / "node.mcap", tmp_path / "node.rrd", tmp_path / "out"
    params = {"numerics.spacing": 0.002, "publish_period": 0.001, "record_interval": 0.002,
              "mcap_path": str(mcap), "rrd_path": str(rrd), "mcap_compression": "lz4", "out_dir": str(out)}
    params.update({"end_time": 0.01, "on_end": "exit"} if ending == "end_time" else {"end_time": 5.0})
    proc = _node(params, NODE_DOMAIN)
    try:
        if ending == "SIGINT":
            deadline = time.monotonic() + 300
            while time.monotonic() < deadline and proc.poll() is None:
                if rrd.exists() and rrd.stat().st_size > 20_000:
                    break
                time.sleep(0.1)
            proc.send_signal(signal.SIGINT)
        _, err = proc.communicate(timeout=300)
    finally:
        if proc.poll() is None:
            proc.kill()
    assert proc.returncode == 0, err
    assert "recording closed" in err, err
    with open(mcap, "rb") as fh:
        summary = make_reader(fh).get_summary()
    counts = {c.topic: summary.statistics.channel_message_counts[c.id] for c in summary.channels.values()}
    assert set(counts) == set(TOPICS)
    assert {ci.compression for ci in summary.chunk_indexes} == {"lz4"}
    frames = counts["/clock"]
    if ending == "end_time":
        assert frames == 6                      # t = 0, 0.002, ..., 0.01
    else:
        assert frames >= 3
    assert counts["/sph_fsi/particles"] == counts["/sph_fsi/tip_displacement"] == frames
    assert counts["/sph_fsi/probes/tip/displacement"] == frames
    assert counts["/diagnostics"] == frames + 1
    r = subprocess.run([RERUN, "rrd", "verify", str(rrd)], env=env(), capture_output=True, text=True, timeout=120)
    assert r.returncode == 0, r.stdout + r.stderr
    messages = recorded(mcap)
    status = messages["/diagnostics"][-1][1][1]
    assert status == ("finished" if ending == "end_time" else "interrupted")
    # out_dir: the run's time series and summary, as `sph-fsi run` writes them, and a log line with its cost
    summary = json.loads((out / "summary.json").read_text())
    assert summary["status"] == status and summary["stable"]
    assert summary["wall_time_s"] >= summary["stepping_time_s"] > 0 and summary["particle_steps_per_second"] > 0
    assert f"run {status} at t = " in err and "wall time" in err, err
    if ending == "end_time":
        assert summary["simulated_time_s"] == pytest.approx(0.01) and "error_metric" in summary   # judged
    else:
        assert "error" not in summary
    with open(out / "timeseries.csv", newline="") as fh:
        rows = list(csv.DictReader(fh))
    assert len(rows) == summary["outer_steps"] + 1
    # the recorded tip displacement is the time series' own at every recorded stamp, to the bit
    by_stamp = {round(float(r["time"]) * 1e9): tuple(float(r[f"tip_d{c}"]) for c in "xyz") for r in rows}
    tips = messages["/sph_fsi/tip_displacement"]
    assert len(tips) == frames and all(by_stamp[stamp] == value for _t, (stamp, value) in tips)
