"""The ROS 2 node, across processes: the node runs as its own process (the venv's python), this test process
subscribes and calls its services with rclpy. Each module run uses its own ROS_DOMAIN_ID (fixed offsets from
the run's random base, below), discovery on localhost only.

CPU: the node runs single-threaded (NUMBA_NUM_THREADS=1) on a small cantilever (12 x 3 x 4 mm at 1 mm: 144
moving + 96 clamp particles) with a publish period of 1 ms (4 outer steps).
"""
import json
import os
import random
import signal
import subprocess
import sys
import tempfile
import threading
import time
from pathlib import Path

import numpy as np
import pytest

os.environ["ROS_AUTOMATIC_DISCOVERY_RANGE"] = "LOCALHOST"

import rclpy  # noqa: E402
from diagnostic_msgs.msg import DiagnosticArray, DiagnosticStatus  # noqa: E402
from geometry_msgs.msg import Vector3Stamped  # noqa: E402
from rcl_interfaces.srv import GetParameters, SetParameters  # noqa: E402
from rclpy.executors import SingleThreadedExecutor  # noqa: E402
from rclpy.node import NodeNameNonExistentError  # noqa: E402
from rclpy.parameter import Parameter, parameter_value_to_python  # noqa: E402
from rclpy.qos import DurabilityPolicy, QoSProfile, ReliabilityPolicy  # noqa: E402
from rclpy.signals import SignalHandlerOptions  # noqa: E402
from rosgraph_msgs.msg import Clock  # noqa: E402
from sensor_msgs.msg import PointCloud2, PointField  # noqa: E402
from std_msgs.msg import Float64  # noqa: E402
from std_srvs.srv import SetBool, Trigger  # noqa: E402

from sph_fsi.messages import PHASE_SOLID, cloud_to_structured, seconds_from_stamp  # noqa: E402

PYTHON = str(Path(sys.prefix) / "bin" / "python")   # the venv's own python (the ROS wheels' bootstrap)
NODE_EXE = str(Path(sys.prefix) / "bin" / "sph_fsi_node")
PERIOD = 0.001                       # publish_period of the test node [s]
SMALL = {"geometry.length": 0.012, "geometry.width": 0.003, "geometry.clamp_margin": 2}
# the default scheme's mirrored clamp: 4 layers of ghosts behind the root, no margin (geometry.clamp_margin is the
# fixed clamp's; config/cantilever.yaml), the last left out: beyond the body's reach (scenes/built.py)
MOVING, CLAMP = 12 * 3 * 4, 3 * 3 * 4     # 144, 36
FIRST_CLOCK_TIMEOUT = 400.0   # a cold Numba cache: the build compiles the fit (125 s before t = 0, shared host)
LATENCY_LIMIT = 0.2

# `make test` picks a random base ROS_DOMAIN_ID per run; the modules that start nodes take fixed offsets from it
# (test_replay.py: +2, +3), so modules running at the same time in two pytest-xdist workers never share a domain.
_BASE = int(os.environ.get("ROS_DOMAIN_ID") or random.Random().randint(1, 100))
DOMAIN = 1 + (_BASE - 1) % 100
SIGNAL_DOMAIN = 1 + _BASE % 100      # the signal tests' nodes, apart from the module's node


# ---- the node process -------------------------------------------------------------------------------------
def node_env(domain):
    env = dict(os.environ)
    env.update(ROS_DOMAIN_ID=str(domain), ROS_AUTOMATIC_DISCOVERY_RANGE="LOCALHOST", NUMBA_NUM_THREADS="1",
               PYTHONUNBUFFERED="1")
    return env


class NodeProcess:
    def __init__(self, domain, params=(), params_file=None, module=True):
        self.out = tempfile.TemporaryFile()
        self.err = tempfile.TemporaryFile()
        cmd = [PYTHON, "-m", "sph_fsi"] if module else [NODE_EXE]
        cmd += ["--ros-args"]
        if params_file:
            cmd += ["--params-file", str(params_file)]
        for key, value in params:
            cmd += ["-p", f"{key}:={value}"]
        self.started = time.monotonic()
        self.proc = subprocess.Popen(cmd, env=node_env(domain), stdout=self.out, stderr=self.err,
                                     stdin=subprocess.DEVNULL)

    def stop(self, sig=signal.SIGINT, timeout=15.0):
        if self.proc.poll() is None:
            self.proc.send_signal(sig)
        try:
            return self.proc.wait(timeout)
        except subprocess.TimeoutExpired:
            self.proc.kill()
            self.proc.wait()
            raise

    def stderr(self):
        self.err.seek(0)
        return self.err.read().decode(errors="replace")


# ---- this process: subscriber and client ------------------------------------------------------------------
class Peer:
    """rclpy in this process: records every message with its arrival time and calls the node's services."""

    TOPICS = {"/clock": Clock, "/diagnostics": DiagnosticArray, "/sph_fsi/particles": PointCloud2,
              "/sph_fsi/tip_displacement": Vector3Stamped, "/sph_fsi/strain_energy": Float64,
              "/sph_fsi/probes/tip/displacement": Vector3Stamped}

    def __init__(self, domain, name="sph_fsi_test_peer"):
        self.ctx = rclpy.Context()
        rclpy.init(context=self.ctx, domain_id=domain, signal_handler_options=SignalHandlerOptions.NO)
        self.node = rclpy.create_node(name, context=self.ctx)
        self.lock = threading.Lock()
        self.msgs = {name: [] for name in list(self.TOPICS) + ["/sph_fsi/walls"]}
        for name, mtype in self.TOPICS.items():
            self.node.create_subscription(mtype, name, self._recorder(name), QoSProfile(depth=200))
        latched = QoSProfile(depth=1, reliability=ReliabilityPolicy.RELIABLE,
                             durability=DurabilityPolicy.TRANSIENT_LOCAL)
        self.node.create_subscription(PointCloud2, "/sph_fsi/walls", self._recorder("/sph_fsi/walls"), latched)
        self.reset = self.node.create_client(Trigger, "/sph_fsi/reset")
        self.pause = self.node.create_client(SetBool, "/sph_fsi/pause")
        self.step = self.node.create_client(Trigger, "/sph_fsi/step")
        self.write_checkpoint = self.node.create_client(Trigger, "/sph_fsi/write_checkpoint")
        self.set_params = self.node.create_client(SetParameters, "/sph_fsi/set_parameters")
        self.get_params = self.node.create_client(GetParameters, "/sph_fsi/get_parameters")
        self.executor = SingleThreadedExecutor(context=self.ctx)
        self.executor.add_node(self.node)
        self._stop = threading.Event()
        self.thread = threading.Thread(target=self._spin, daemon=True)
        self.thread.start()

    def _spin(self):
        while not self._stop.is_set():
            self.executor.spin_once(timeout_sec=0.05)

    def _recorder(self, name):
        def record(msg):
            with self.lock:
                self.msgs[name].append((time.monotonic(), msg))
        return record

    def close(self):
        self._stop.set()
        self.thread.join()
        self.executor.shutdown()
        self.node.destroy_node()
        rclpy.try_shutdown(context=self.ctx)

    # messages
    def count(self, topic):
        with self.lock:
            return len(self.msgs[topic])

    def quiet_count(self, topic, quiet=0.5, timeout=10.0):
        """The count of `topic`'s messages once none has arrived for `quiet` s: a frame still in flight from
        before (a loaded host delivers late) is not taken for the next one."""
        deadline = time.monotonic() + timeout
        count = self.count(topic)
        while time.monotonic() < deadline:
            time.sleep(quiet)
            now = self.count(topic)
            if now == count:
                return now
            count = now
        return count

    def since(self, topic, index=0):
        with self.lock:
            return [m for _, m in self.msgs[topic][index:]]

    def clear(self):
        with self.lock:
            for v in self.msgs.values():
                v.clear()

    def wait_for(self, topic, predicate=lambda m: True, start=0, timeout=30.0):
        """The first message on `topic` from index `start` on that satisfies `predicate`."""
        deadline = time.monotonic() + timeout
        while time.monotonic() < deadline:
            for m in self.since(topic, start):
                if predicate(m):
                    return m
            time.sleep(0.02)
        raise AssertionError(f"no matching message on {topic} within {timeout} s")

    def clock_times(self, start=0):
        return [seconds_from_stamp(m.clock) for m in self.since("/clock", start)]

    def last_clock(self):
        return self.clock_times()[-1]

    # services
    def call(self, client, request, timeout=10.0):
        """(response, round-trip seconds)."""
        assert client.wait_for_service(timeout_sec=30.0), f"{client.srv_name} not available"
        done = threading.Event()
        t0 = time.perf_counter()
        future = client.call_async(request)
        future.add_done_callback(lambda _f: done.set())
        assert done.wait(timeout), f"{client.srv_name}: no answer within {timeout} s"
        return future.result(), time.perf_counter() - t0

    def set_param(self, name, value):
        """(SetParametersResult, seconds)."""
        req = SetParameters.Request(parameters=[Parameter(name, value=value).to_parameter_msg()])
        response, dt = self.call(self.set_params, req)
        return response.results[0], dt

    def get_param(self, name):
        response, _ = self.call(self.get_params, GetParameters.Request(names=[name]))
        return parameter_value_to_python(response.values[0])

    def diagnostics(self, start=0):
        out = []
        for m in self.since("/diagnostics", start):
            for s in m.status:
                if s.name == "sph_fsi":
                    out.append((s.level, s.message, {kv.key: kv.value for kv in s.values}))
        return out


def _params_file(tmp_path):
    """Part of the overrides through --params-file (flat dotted keys next to the `scene` leaf)."""
    path = tmp_path / "params.yaml"
    path.write_text("sph_fsi:\n  ros__parameters:\n    scene: cantilever\n"
                    "    geometry.length: 0.012\n    geometry:\n      width: 0.003\n")
    return path


@pytest.fixture(scope="module")
def peer():
    p = Peer(DOMAIN)
    yield p
    p.close()


@pytest.fixture(scope="module")
def node(peer, tmp_path_factory):
    run_log = tmp_path_factory.mktemp("node_runs") / "run"
    params = [("geometry.clamp_margin", 2), ("publish_period", PERIOD), ("end_time", 0.05), ("out_dir", run_log)]
    proc = NodeProcess(DOMAIN, params, params_file=_params_file(tmp_path_factory.mktemp("node")))
    proc.run_log = run_log
    try:
        _wait_for_first_clock(peer)
    except AssertionError as exc:
        proc.stop()
        raise AssertionError(f"{exc}; the node's stderr:\n" + proc.stderr())
    yield proc
    code = proc.stop()
    err = proc.stderr()
    assert code == 0, err
    assert "terminate called" not in err and "Traceback" not in err, err


def _wait_for_first_clock(peer):
    """The module node's first /clock. Its run (0.05 s simulated) can end before discovery has matched this process's
    subscription, and then no /clock comes (seen once on a loaded host): once the node's 1 s diagnostics say the run
    is at its end with no /clock heard, ~/reset runs it again, matched now."""
    deadline = time.monotonic() + FIRST_CLOCK_TIMEOUT
    while time.monotonic() < deadline:
        if peer.count("/clock"):
            return
        ended = [v for _, _, v in peer.diagnostics()
                 if "end_time" in v and float(v["sim_time"]) >= float(v["end_time"]) * (1.0 - 1e-9)]
        if ended:
            response, _ = peer.call(peer.reset, Trigger.Request())
            assert response.success, response.message
            peer.wait_for("/clock", timeout=max(deadline - time.monotonic(), 1.0))
            return
        time.sleep(0.05)
    raise AssertionError(f"the node published no /clock within {FIRST_CLOCK_TIMEOUT:.0f} s")


def _run_log_summaries(node):
    """The module node's out_dir summaries, oldest run first (<out_dir>, then <out_dir>_1, _2, ...)."""
    dirs = {0 if p.name == "run" else int(p.name.split("_")[1]): p for p in node.run_log.parent.glob("run*")
            if (p / "summary.json").exists()}
    return [json.loads((dirs[k] / "summary.json").read_text()) for k in sorted(dirs)]


def _reset_and_wait(peer):
    """~/reset, then wait for the node's t = 0 frame; returns the index of that /clock message."""
    start = peer.count("/clock")
    response, _ = peer.call(peer.reset, Trigger.Request())
    assert response.success, response.message
    peer.wait_for("/clock", lambda m: seconds_from_stamp(m.clock) == 0.0, start=start)
    return start + peer.clock_times(start).index(0.0)


# ---- tests ------------------------------------------------------------------------------------------------
def test_topics_and_services_exist_only_for_what_the_scene_has(node, peer):
    expected = {"/sph_fsi/particles": "sensor_msgs/msg/PointCloud2", "/sph_fsi/walls": "sensor_msgs/msg/PointCloud2",
                "/sph_fsi/tip_displacement": "geometry_msgs/msg/Vector3Stamped",
                "/sph_fsi/probes/tip/displacement": "geometry_msgs/msg/Vector3Stamped",
                "/sph_fsi/strain_energy": "std_msgs/msg/Float64", "/clock": "rosgraph_msgs/msg/Clock",
                "/diagnostics": "diagnostic_msgs/msg/DiagnosticArray"}
    deadline = time.monotonic() + 15.0
    while True:
        try:
            published = dict(peer.node.get_publisher_names_and_types_by_node("sph_fsi", "/"))
        except NodeNameNonExistentError:   # not discovered yet (a clean clone's CI compiles on both cores)
            if time.monotonic() > deadline:
                raise
            published = {}
        if set(expected) <= set(published) or time.monotonic() > deadline:
            break
        time.sleep(0.1)
    for name, mtype in expected.items():
        assert published.get(name) == [mtype], (name, published)
    assert set(published) - set(expected) <= {"/parameter_events", "/rosout"}, published
    all_topics = dict(peer.node.get_topic_names_and_types())
    assert not [t for t in all_topics if "fluid" in t], all_topics   # the cantilever has no fluid
    services = dict(peer.node.get_service_names_and_types_by_node("sph_fsi", "/"))
    assert services["/sph_fsi/reset"] == ["std_srvs/srv/Trigger"]
    assert services["/sph_fsi/pause"] == ["std_srvs/srv/SetBool"]
    assert services["/sph_fsi/step"] == ["std_srvs/srv/Trigger"]
    assert services["/sph_fsi/write_checkpoint"] == ["std_srvs/srv/Trigger"]


def test_particles_and_walls_layout(node, peer):
    msg = peer.wait_for("/sph_fsi/particles")
    assert [(f.name, f.offset, f.datatype, f.count) for f in msg.fields] == (
        [(n, 4 * i, PointField.FLOAT32, 1) for i, n in enumerate(["x", "y", "z", "vx", "vy", "vz", "pressure",
                                                                   "von_mises"])]
        + [("phase", 32, PointField.UINT8, 1)])
    assert msg.point_step == 36 and msg.point_step % 4 == 0
    assert msg.height == 1 and msg.width == MOVING and msg.row_step == 36 * MOVING
    assert msg.is_dense and not msg.is_bigendian and msg.header.frame_id == "map"
    pts = cloud_to_structured(msg)
    assert (pts["phase"] == PHASE_SOLID).all()
    for name in ("x", "y", "z", "vx", "vy", "vz", "pressure", "von_mises"):
        assert np.isfinite(pts[name]).all()
    assert (pts["x"] > 0).all() and (pts["x"] < 0.012).all()   # the beam; the clamp is at x < 0
    walls = peer.wait_for("/sph_fsi/walls")
    assert [f.name for f in walls.fields] == ["x", "y", "z"] and walls.point_step == 12
    assert walls.width == CLAMP and seconds_from_stamp(walls.header.stamp) == 0.0
    assert (cloud_to_structured(walls)["x"] < 0).all()
    energy = peer.wait_for("/sph_fsi/strain_energy")
    assert np.isfinite(energy.data) and energy.data >= 0.0


def test_tip_displacement_equals_the_simulators_own(node, peer):
    msg = peer.wait_for("/sph_fsi/tip_displacement", lambda m: seconds_from_stamp(m.header.stamp) >= 2 * PERIOD,
                        timeout=60.0)
    t = seconds_from_stamp(msg.header.stamp)
    assert msg.header.frame_id == "map"
    import numba
    from sph_fsi_core.scene import load_scene
    from sph_fsi_core.simulation import Simulation
    threads = numba.get_num_threads()
    numba.set_num_threads(1)   # the node's (NUMBA_NUM_THREADS=1); then back, for the tests after this one
    try:
        sim = Simulation(load_scene("cantilever", list(SMALL.items())))
        while sim.time < t - 1e-9:
            sim.step()
    finally:
        numba.set_num_threads(threads)
    assert abs(sim.time - t) < 1e-9
    d = sim.probe_displacements()["tip"]
    got = np.array([msg.vector.x, msg.vector.y, msg.vector.z])
    np.testing.assert_allclose(got, d, rtol=0, atol=1e-9)
    assert abs(got[2]) > 1e-7   # the tip has moved (Vf = 10 mm/s along z): not a trivial comparison
    # the probe's own topic carries the same vector with the same stamp
    same = peer.wait_for("/sph_fsi/probes/tip/displacement", lambda m: m.header.stamp == msg.header.stamp)
    assert (same.vector.x, same.vector.y, same.vector.z) == tuple(got) and same.header.frame_id == "map"


def test_clock_increases(node, peer):
    start = _reset_and_wait(peer)
    peer.wait_for("/clock", start=start + 6, timeout=30.0)
    times = peer.clock_times(start)
    assert times[0] == 0.0 and len(times) >= 6
    steps = np.diff(times)
    assert (steps > 0).all(), times
    np.testing.assert_allclose(steps, PERIOD, rtol=0, atol=1e-9)
    status = peer.diagnostics()[-1]
    assert status[1] == "running" and float(status[2]["steps_per_second"]) > 0, status
    assert int(status[2]["particles"]) == MOVING + CLAMP


def test_services_answer_promptly_while_computing(node, peer):
    start = _reset_and_wait(peer)
    # one untimed round first: a client's first call can wait for the server to discover its response reader
    # (rmw_fastrtps holds a response until it has: ros2/rmw_fastrtps#390), which is discovery, not the node
    peer.call(peer.step, Trigger.Request())
    peer.call(peer.pause, SetBool.Request(data=False))
    peer.set_param("realtime_factor", 0.0)
    t_begin = peer.last_clock()
    latencies = {"step": [], "pause false": [], "set_parameters": []}
    # at least 15 rounds, and on until the simulation has advanced two periods (a period costs 0.2-0.7 s of one
    # thread, more when the other test worker loads the host)
    deadline = time.monotonic() + 60.0
    rounds = 0
    while rounds < 15 or (peer.last_clock() < t_begin + 2 * PERIOD - 1e-9 and time.monotonic() < deadline):
        rounds += 1
        response, dt = peer.call(peer.step, Trigger.Request())
        assert not response.success and "paused" in response.message   # refused at once: not paused
        latencies["step"].append(dt)
        response, dt = peer.call(peer.pause, SetBool.Request(data=False))   # resume: already running
        assert response.success
        latencies["pause false"].append(dt)
        result, dt = peer.set_param("realtime_factor", 0.0)
        assert result.successful, result.reason
        latencies["set_parameters"].append(dt)
        time.sleep(0.1)
    t_end = peer.last_clock()
    assert t_end >= t_begin + 2 * PERIOD - 1e-9, "the simulation did not advance while the services were called"
    status = peer.diagnostics(start)[-1]
    assert status[1] == "running", status
    worst = {k: max(v) for k, v in latencies.items()}
    print(f"\nservice round trips while computing (sim {t_begin:.4f} -> {t_end:.4f} s): "
          + ", ".join(f"{k}: median {1e3 * np.median(v):.1f} ms, max {1e3 * max(v):.1f} ms"
                      for k, v in latencies.items()))
    assert max(worst.values()) < LATENCY_LIMIT, worst


def _wait_until_quiet(peer, quiet=0.5, timeout=5.0):
    """Wait until no /clock arrives for `quiet` s; return the clock count. Fails after `timeout` s."""
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        n = peer.count("/clock")
        time.sleep(quiet)
        if peer.count("/clock") == n:
            return n
    raise AssertionError(f"/clock still published {timeout} s after the pause")


def test_pause_stops_clock_and_step_advances_one_period(node, peer):
    _reset_and_wait(peer)
    peer.wait_for("/clock", lambda m: seconds_from_stamp(m.clock) >= 2 * PERIOD)
    response, dt = peer.call(peer.pause, SetBool.Request(data=True))
    assert response.success and dt < LATENCY_LIMIT
    n = _wait_until_quiet(peer, quiet=0.5)
    paused_at = peer.last_clock()
    diag = peer.wait_for("/diagnostics", lambda m: m.status[0].message == "paused", timeout=5.0)
    assert diag.status[0].level == DiagnosticStatus.OK
    for k in range(1, 3):
        response, _ = peer.call(peer.step, Trigger.Request())
        assert response.success, response.message
        peer.wait_for("/clock", start=n + k - 1, timeout=30.0)
        time.sleep(0.3)
        times = peer.clock_times(n)
        assert len(times) == k, times   # one frame per step
        assert abs(times[-1] - (paused_at + k * PERIOD)) < 1e-9, (paused_at, times)
    assert _wait_until_quiet(peer) == n + 2


def test_reset_returns_to_zero_and_keeps_the_pause(node, peer):
    # paused from the previous test
    t_reset = peer.last_clock()
    assert t_reset > 0.0
    start = peer.count("/clock")
    response, dt = peer.call(peer.reset, Trigger.Request())
    assert response.success and dt < LATENCY_LIMIT
    peer.wait_for("/clock", lambda m: seconds_from_stamp(m.clock) == 0.0, start=start)
    # the run that was reset left its summary (out_dir, numbered after each reset: the newest), cut short: not
    # judged. It is written before the t = 0 frame of the next run goes out.
    newest = _run_log_summaries(node)[-1]
    assert newest["status"] == "reset" and newest["simulated_time_s"] == pytest.approx(t_reset), newest
    assert "error" not in newest and newest["stepping_time_s"] > 0
    msg = peer.wait_for("/sph_fsi/tip_displacement", lambda m: seconds_from_stamp(m.header.stamp) == 0.0)
    assert (msg.vector.x, msg.vector.y, msg.vector.z) == (0.0, 0.0, 0.0)
    n = _wait_until_quiet(peer)
    response, _ = peer.call(peer.pause, SetBool.Request(data=False))
    assert response.success
    peer.wait_for("/clock", start=n + 2)
    assert peer.clock_times(n)[:3] == pytest.approx([PERIOD, 2 * PERIOD, 3 * PERIOD], abs=1e-9)
    response, _ = peer.call(peer.pause, SetBool.Request(data=True))
    assert response.success
    _wait_until_quiet(peer)


def test_end_time_stay_and_realtime_factor(node, peer):
    """on_end 'stay': at end_time the node stays up and reports finished; raising end_time runs on.
    realtime_factor paces the publishes in wall time."""
    t0 = peer.last_clock()
    end = round(t0 + 3 * PERIOD, 9)
    assert peer.set_param("end_time", end)[0].successful
    assert peer.set_param("realtime_factor", 0.01)[0].successful   # 1 ms of simulated time per 0.1 s
    start = peer.count("/clock")
    diag_start = peer.count("/diagnostics")
    peer.call(peer.pause, SetBool.Request(data=False))
    peer.wait_for("/diagnostics", lambda m: m.status[0].message == "finished", start=diag_start, timeout=30.0)
    n = _wait_until_quiet(peer)
    assert abs(peer.last_clock() - end) < 1e-9
    with peer.lock:
        arrivals = [t for t, _ in peer.msgs["/clock"][start:n]]
    gaps = np.diff(arrivals)
    assert len(gaps) >= 2 and np.median(gaps) > 0.07, gaps     # paced (unpaced: a few ms per frame here)
    response, _ = peer.call(peer.step, Trigger.Request())
    assert not response.success   # running is over; step refuses, reset would start again
    response, _ = peer.call(peer.pause, SetBool.Request(data=True))
    assert response.success
    response, _ = peer.call(peer.step, Trigger.Request())
    assert not response.success and "end time" in response.message, response.message
    assert peer.set_param("realtime_factor", 0.0)[0].successful
    # relative to the end just reached: how far earlier tests ran depends on the machine's speed
    assert peer.set_param("end_time", round(end + 10 * PERIOD, 9))[0].successful
    response, _ = peer.call(peer.step, Trigger.Request())   # no longer at the end: one period further
    assert response.success, response.message
    peer.wait_for("/clock", lambda m: abs(seconds_from_stamp(m.clock) - (end + PERIOD)) < 1e-9, start=n)


def test_divergence_is_reported_and_reset_recovers(node, peer):
    assert peer.set_param("watchdog.max_speed", 1e-6)[0].successful   # the beam moves at ~10 mm/s
    diag_start = peer.count("/diagnostics")
    peer.call(peer.pause, SetBool.Request(data=False))
    msg = peer.wait_for("/diagnostics", lambda m: m.status[0].message == "diverged", start=diag_start)
    status = msg.status[0]
    values = {kv.key: kv.value for kv in status.values}
    assert status.level == DiagnosticStatus.ERROR
    assert values["check"] == "speed" and "watchdog.max_speed" in values["detail"] and float(values["time"]) > 0
    n = _wait_until_quiet(peer)   # nothing but diagnostics after a divergence
    diverged = _run_log_summaries(node)[-1]   # written before the diverged diagnostics go out
    assert diverged["status"] == "diverged" and not diverged["stable"] and diverged["diverged"]["check"] == "speed"
    assert diverged["diverged"]["time"] == pytest.approx(float(values["time"])) and "error" not in diverged
    response, _ = peer.call(peer.step, Trigger.Request())
    assert not response.success and "diverged" in response.message
    assert peer.set_param("watchdog.max_speed", 100.0)[0].successful
    response, _ = peer.call(peer.pause, SetBool.Request(data=True))
    _reset_and_wait(peer)
    peer.wait_for("/diagnostics", lambda m: m.status[0].message == "paused", start=peer.count("/diagnostics"))
    assert peer.count("/clock") > n


def test_parameters_refused_applied_and_deferred(node, peer):
    peer.call(peer.pause, SetBool.Request(data=True))   # frames of the old beam stop before its reset
    # refused, with a reason naming the parameter (and the allowed range)
    for bad in (-1.0, "abc", 0.0, True):
        result, dt = peer.set_param("solid.young_modulus", bad)
        assert not result.successful, bad
        assert "solid.young_modulus" in result.reason, result.reason
        assert dt < LATENCY_LIMIT
    assert "(0, 1e+13]" in peer.set_param("solid.young_modulus", 0.0)[0].reason
    result, _ = peer.set_param("numerics.spacing", 0.0007)   # not a whole number of layers of the beam
    assert not result.successful and "spacing" in result.reason, result.reason
    # too fine for this machine's memory: refused at once, naming the spacing, the particles and the memory
    result, _ = peer.set_param("numerics.spacing", 1.0e-5)
    assert not result.successful and "numerics.spacing = 1e-05" in result.reason, result.reason
    assert "144,480,000 particles" in result.reason and "GiB of memory is available" in result.reason, result.reason
    result, _ = peer.set_param("qos", "fast")
    assert not result.successful and "qos" in result.reason
    assert peer.get_param("solid.young_modulus") == 1.859e6

    # a live change applies at once
    result, _ = peer.set_param("solid.young_modulus", 2.0e6)
    assert result.successful, result.reason
    assert "applied now" in result.reason
    assert peer.get_param("solid.young_modulus") == 2.0e6
    result, _ = peer.set_param("solid.young_modulus", 2000000)   # an integer stands for the double
    assert result.successful, result.reason

    # a rebuild key is accepted, says so, and changes the particles at the next reset only
    result, _ = peer.set_param("numerics.spacing", 0.0005)
    assert result.successful, result.reason
    assert "numerics.spacing" in result.reason and "next ~/reset" in result.reason, result.reason
    assert peer.get_param("numerics.spacing") == 0.0005
    start = peer.count("/sph_fsi/particles")
    walls_start = peer.count("/sph_fsi/walls")
    response, _ = peer.call(peer.reset, Trigger.Request())
    assert response.success and "numerics.spacing" in response.message, response.message
    fine = peer.wait_for("/sph_fsi/particles", start=start, timeout=60.0)
    assert fine.width == 8 * MOVING
    walls = peer.wait_for("/sph_fsi/walls", start=walls_start, timeout=10.0)
    assert walls.width == 3 * 6 * 8   # the clamp counts layers: at 0.5 mm, 3 of 4 behind a root 6 x 8 layers
    status = peer.wait_for("/diagnostics", lambda m: int({kv.key: kv.value for kv in m.status[0].values}
                                                         ["particles"]) > MOVING + CLAMP)
    assert status.status[0].message == "paused"

    # services while the 8x finer beam computes (an outer step takes ~10x longer than on the coarse one)
    peer.call(peer.pause, SetBool.Request(data=False))
    time.sleep(0.3)
    latencies = []
    for _ in range(5):
        latencies.append(peer.call(peer.step, Trigger.Request())[1])
        latencies.append(peer.set_param("realtime_factor", 0.0)[1])
        time.sleep(0.1)
    peer.call(peer.pause, SetBool.Request(data=True))
    print(f"\nservice round trips while the {8 * MOVING}-particle beam computes: "
          f"median {1e3 * np.median(latencies):.1f} ms, max {1e3 * max(latencies):.1f} ms")
    assert max(latencies) < LATENCY_LIMIT, latencies

    # back to the coarse beam
    result, _ = peer.set_param("numerics.spacing", 0.001)
    assert result.successful
    start = peer.count("/sph_fsi/particles")
    peer.call(peer.reset, Trigger.Request())
    peer.wait_for("/sph_fsi/particles", lambda m: m.width == MOVING and seconds_from_stamp(m.header.stamp) == 0.0,
                  start=start, timeout=60.0)

    # a solid scheme waits for the reset, which shows the detailed keys it expands to as parameters
    result, _ = peer.set_param("solid.scheme", "gray2001")
    assert result.successful and "next ~/reset" in result.reason, result.reason
    assert peer.get_param("solid.velocity_gradient") == "quadratic"
    start = peer.quiet_count("/sph_fsi/particles")
    peer.call(peer.reset, Trigger.Request())
    peer.wait_for("/sph_fsi/particles", start=start, timeout=60.0)   # the rebuild (on the simulation thread)
    # the parameters are the rebuilt scene's before its first frame goes out
    assert peer.get_param("solid.velocity_gradient") == "sph"
    assert peer.get_param("solid.artificial_stress_epsilon") == 0.15 and peer.get_param("solid.cfl") == 0.5
    assert peer.get_param("solid.young_modulus") == 2.0e6     # an explicitly set key stays
    result, _ = peer.set_param("solid.scheme", "quadratic_gradient")
    assert result.successful
    start = peer.quiet_count("/sph_fsi/particles")
    peer.call(peer.reset, Trigger.Request())
    peer.wait_for("/sph_fsi/particles", start=start, timeout=60.0)
    assert peer.get_param("solid.velocity_gradient") == "quadratic"
    assert peer.get_param("solid.nodal_integration") == "gradient"


def test_write_checkpoint_then_a_node_restarts_from_it(node, peer, tmp_path):
    """~/write_checkpoint writes the running state (paused here, so its time is known); a second node started with
    restart_from continues from that time and ends at its end_time; restart_from is read at startup only, and
    with a scene key, or a file that is not a checkpoint, the node refuses to start (exit 2, one line)."""
    peer.call(peer.pause, SetBool.Request(data=True))
    _wait_until_quiet(peer)
    t = peer.last_clock()
    response, _ = peer.call(peer.write_checkpoint, Trigger.Request())
    assert response.success, response.message
    path = str(node.run_log / "checkpoint.ckpt")
    assert f"checkpoint of t = {t:.6g} s written to {path}" in response.message, response.message
    result, _ = peer.set_param("restart_from", path)
    assert not result.successful and "startup only" in result.reason, result.reason
    proc = NodeProcess(SIGNAL_DOMAIN, [("restart_from", path), ("end_time", round(t + 0.002, 9)),
                                       ("on_end", "exit")], module=False)
    assert proc.proc.wait(FIRST_CLOCK_TIMEOUT) == 0, proc.stderr()
    err = proc.stderr()
    assert f"continuing 'cantilever' from its checkpoint at t = {t:.6g} s" in err, err
    assert f"finished at t = {t + 0.002:.6g} s" in err, err
    refused = NodeProcess(SIGNAL_DOMAIN, [("restart_from", path), ("solid.young_modulus", 2.0e6)], module=False)
    assert refused.proc.wait(60.0) == 2
    line = refused.stderr().strip().splitlines()[-1]
    assert "restart_from" in line and "solid.young_modulus" in line, line
    (tmp_path / "not.ckpt").write_text("hello\n")
    refused = NodeProcess(SIGNAL_DOMAIN, [("restart_from", str(tmp_path / "not.ckpt"))], module=False)
    assert refused.proc.wait(60.0) == 2
    assert "not an sph_fsi checkpoint" in refused.stderr().strip().splitlines()[-1]


def test_end_of_run_exits_with_status_0():
    """on_end exit: the node ends by itself at end_time, exit status 0."""
    proc = NodeProcess(SIGNAL_DOMAIN, [(k, v) for k, v in SMALL.items()]
                       + [("end_time", 0.003), ("publish_period", PERIOD), ("on_end", "exit")], module=False)
    try:
        code = proc.proc.wait(FIRST_CLOCK_TIMEOUT)
    except subprocess.TimeoutExpired:
        proc.stop()
        raise
    err = proc.stderr()
    assert code == 0, err
    assert "finished at t = 0.003 s" in err and "terminate called" not in err, err


def test_bad_startup_parameter_exits_2_with_reason():
    proc = NodeProcess(SIGNAL_DOMAIN, [("solid.young_modulus", -1.0)], module=False)
    assert proc.proc.wait(60.0) == 2
    err = proc.stderr().strip().splitlines()
    assert err and "solid.young_modulus" in err[-1] and "(0, 1e+13]" in err[-1], err


def test_a_scene_too_large_for_the_memory_exits_2_naming_the_spacing():
    proc = NodeProcess(SIGNAL_DOMAIN, [("numerics.spacing", 1.0e-5)], module=False)
    assert proc.proc.wait(60.0) == 2
    err = proc.stderr().strip().splitlines()
    assert err and "numerics.spacing = 1e-05" in err[-1] and "particles" in err[-1] and "GiB" in err[-1], err


def test_unwritable_out_dir_exits_2_before_running(tmp_path):
    """Found out at startup, not after a long run."""
    blocker = tmp_path / "a_file"
    blocker.write_text("")
    proc = NodeProcess(SIGNAL_DOMAIN, [(k, v) for k, v in SMALL.items()]
                       + [("end_time", 0.003), ("out_dir", str(blocker / "out"))], module=False)
    assert proc.proc.wait(FIRST_CLOCK_TIMEOUT) == 2
    err = proc.stderr()
    assert "out_dir" in err and str(blocker / "out") in err and "writable directory" in err, err
    assert "finished" not in err, err


@pytest.mark.slow
def test_sigint_ten_times_then_sigterm():
    peer = Peer(SIGNAL_DOMAIN, name="sph_fsi_signal_peer")
    try:
        timings = []
        for i in range(11):
            sig = signal.SIGINT if i < 10 else signal.SIGTERM
            peer.clear()
            proc = NodeProcess(SIGNAL_DOMAIN, [(k, v) for k, v in SMALL.items()]
                               + [("end_time", 1.0), ("publish_period", PERIOD)], module=bool(i % 2))
            try:
                peer.wait_for("/clock", timeout=FIRST_CLOCK_TIMEOUT)
            except AssertionError:
                proc.stop(signal.SIGKILL)
                raise AssertionError(f"run {i}: no /clock; stderr:\n{proc.stderr()}")
            t0 = time.monotonic()
            code = proc.stop(sig, timeout=10.0)
            timings.append(time.monotonic() - t0)
            err = proc.stderr()
            assert code == 0, f"run {i} ({sig.name}): exit status {code}\n{err}"
            assert "terminate called" not in err and "Traceback" not in err, f"run {i}:\n{err}"
        print(f"\nshutdown after a signal: max {max(timings):.2f} s, median {np.median(timings):.2f} s")
        assert max(timings) < 5.0, timings
    finally:
        peer.close()
