"""Recordings from the command line (`sph-fsi run --mcap/--rrd`), read back by independent tools.

One short cantilever run (coarse: 2 mm spacing, 120 moving + 24 clamp particles, 0.01 s, a frame every 1 ms:
11 frames) is recorded to MCAP and .rrd by a real subprocess. The MCAP is read with three readers that share no
code with the writer or with each other: mcap-ros2-support's decoder, rosbags (AnyReader, Jazzy typestore) and
Rerun's MCAP loader (`rerun mcap convert`, then rerun.chunk.RrdReader). Each must see the same messages per
topic, and the values must equal the simulator's own outputs of the same run (timeseries.csv, the last
snapshot). The .rrd is read with RrdReader and checked by `rerun rrd verify`. SIGINT and SIGTERM mid-run must
leave both files readable with every frame up to the stop.
"""
import csv
import json
import os
import signal
import subprocess
import sys
import time
from collections import defaultdict
from pathlib import Path

import numpy as np
import pyarrow as pa
import pytest

from sph_fsi_core.numerics.tensors import von_mises

PYTHON = str(Path(sys.prefix) / "bin" / "python")
RERUN = str(Path(sys.prefix) / "bin" / "rerun")
SMALL = ["--set", "numerics.spacing=0.002", "--set", "geometry.length=0.04"]
END, INTERVAL = 0.01, 0.001
FRAMES = 11                                  # t = 0, 0.001, ..., 0.01
MOVING, CLAMP = 120, 18                      # the cantilever's at 2 mm: 3 of the clamp's 4 layers within reach
NS = "/sph_fsi"
TOPICS = {f"{NS}/particles": "sensor_msgs/msg/PointCloud2", f"{NS}/walls": "sensor_msgs/msg/PointCloud2",
          f"{NS}/tip_displacement": "geometry_msgs/msg/Vector3Stamped", f"{NS}/strain_energy": "std_msgs/msg/Float64",
          f"{NS}/probes/tip/displacement": "geometry_msgs/msg/Vector3Stamped",
          "/clock": "rosgraph_msgs/msg/Clock", "/diagnostics": "diagnostic_msgs/msg/DiagnosticArray"}
# per topic: frames, plus 1 walls message, plus the final /diagnostics (how the run ended)
COUNTS = {f"{NS}/particles": FRAMES, f"{NS}/walls": 1, f"{NS}/tip_displacement": FRAMES,
          f"{NS}/strain_energy": FRAMES, f"{NS}/probes/tip/displacement": FRAMES, "/clock": FRAMES,
          "/diagnostics": FRAMES + 1}
FIELDS = [("x", 0, 7), ("y", 4, 7), ("z", 8, 7), ("vx", 12, 7), ("vy", 16, 7), ("vz", 20, 7), ("pressure", 24, 7),
          ("von_mises", 28, 7), ("phase", 32, 2)]


def env():
    e = dict(os.environ)
    e.update(NUMBA_NUM_THREADS="1", PYTHONUNBUFFERED="1", RERUN_ANALYTICS="0")
    return e


def run_cli(args, **kw):
    return subprocess.run([PYTHON, "-m", "sph_fsi.cli"] + args, env=env(), capture_output=True, text=True, **kw)


@pytest.fixture(scope="module")
def run(tmp_path_factory):
    d = tmp_path_factory.mktemp("rec")
    mcap, rrd, out = d / "run.mcap", d / "run.rrd", d / "out"
    r = run_cli(["run", "cantilever", *SMALL, "--end-time", str(END), "--record-interval", str(INTERVAL),
                 "--mcap", str(mcap), "--rrd", str(rrd), "--out", str(out)], timeout=600)
    assert r.returncode == 0, r.stderr
    with open(out / "timeseries.csv") as fh:
        rows = list(csv.DictReader(fh))
    series = {round(float(row["time"]) * 1e9): {k: float(v) for k, v in row.items()} for row in rows}
    snaps = sorted((out / "snapshots").glob("snapshot_*.npz"))
    first, last = dict(np.load(snaps[0])), dict(np.load(snaps[-1]))
    assert abs(float(last["time"]) - END) < 1e-9
    return {"mcap": mcap, "rrd": rrd, "series": series, "first": first, "last": last, "stderr": r.stderr}


def stamp_ns(stamp):
    return stamp.sec * 1_000_000_000 + stamp.nanosec


def expected_times():
    return [round(k * INTERVAL * 1e9) for k in range(FRAMES)]


def check_values(per_topic, run):
    """per_topic: {topic: [(log_time ns, stamp ns or None, value)]} in a reader-neutral form (see the readers)."""
    series, last = run["series"], run["last"]
    tips = per_topic[f"{NS}/tip_displacement"]
    assert [t for t, _, _ in tips] == expected_times()
    for t, stamp, vec in tips:
        assert stamp == t
        row = series[t]
        assert vec == (row["tip_dx"], row["tip_dy"], row["tip_dz"])
    assert max(abs(v[2]) for _, _, v in tips) > 1e-5     # the beam moves: a frozen recording would fail
    assert per_topic[f"{NS}/probes/tip/displacement"] == tips   # the probe's own topic: the same messages
    energies = per_topic[f"{NS}/strain_energy"]
    assert [t for t, _, _ in energies] == expected_times()
    for t, _, e in energies:
        assert e == series[t]["strain_energy"]
    assert [stamp for _, stamp, _ in per_topic["/clock"]] == expected_times()
    movable = last["solid_movable"]
    for t, stamp, (fields, point_step, pts) in per_topic[f"{NS}/particles"]:
        assert stamp == t and fields == FIELDS and point_step == 36 and len(pts) == MOVING
    _, _, (_, _, pts) = per_topic[f"{NS}/particles"][-1]
    pos = last["solid_position"][movable].astype(np.float32)
    np.testing.assert_array_equal(pts["x"], pos[:, 0])
    np.testing.assert_array_equal(pts["z"], pos[:, 2])
    np.testing.assert_array_equal(pts["vz"], last["solid_velocity"][movable][:, 2].astype(np.float32))
    np.testing.assert_array_equal(pts["pressure"], last["solid_pressure"][movable].astype(np.float32))
    np.testing.assert_array_equal(pts["von_mises"],
                                  von_mises(last["solid_stress_deviatoric"][movable]).astype(np.float32))
    assert (pts["phase"] == 2).all() and pts["von_mises"].max() > 0
    (t, _, (_, _, walls)), = per_topic[f"{NS}/walls"]
    assert t == 0 and len(walls) == CLAMP
    # published once, at t = 0 (the mirrored clamp's ghosts then follow the beam's root by a hair)
    np.testing.assert_array_equal(walls["y"], run["first"]["solid_position"][~movable][:, 1].astype(np.float32))
    statuses = [s for _, _, s in per_topic["/diagnostics"]]
    assert statuses == ["running"] * FRAMES + ["finished"]


def _cloud(msg):
    fields = [(f.name, f.offset, f.datatype) for f in msg.fields]
    names = {"x", "y", "z", "vx", "vy", "vz", "pressure", "von_mises"}
    dtype = np.dtype({"names": [f[0] for f in fields],
                      "formats": ["<f4" if f[0] in names else "u1" for f in fields],
                      "offsets": [f[1] for f in fields], "itemsize": msg.point_step})
    return fields, msg.point_step, np.frombuffer(bytes(msg.data), dtype=dtype, count=msg.width)


def _neutral(topic, msg):
    if topic.endswith("particles") or topic.endswith("walls"):
        return stamp_ns(msg.header.stamp), _cloud(msg)
    if topic.endswith("displacement"):    # tip_displacement, probes/tip/displacement
        return stamp_ns(msg.header.stamp), (msg.vector.x, msg.vector.y, msg.vector.z)
    if topic.endswith("strain_energy"):
        return None, msg.data
    if topic == "/clock":
        return stamp_ns(msg.clock), None
    return stamp_ns(msg.header.stamp), msg.status[0].message


def test_mcap_read_by_mcap_ros2_support(run):
    from mcap.reader import make_reader
    from mcap_ros2.decoder import DecoderFactory
    per_topic = defaultdict(list)
    with open(run["mcap"], "rb") as fh:
        reader = make_reader(fh, decoder_factories=[DecoderFactory()])
        assert reader.get_header().profile == "ros2"
        summary = reader.get_summary()
        channels = {c.topic: c for c in summary.channels.values()}
        assert {t: summary.schemas[c.schema_id].name for t, c in channels.items()} == TOPICS
        for c in channels.values():
            schema = summary.schemas[c.schema_id]
            assert c.message_encoding == "cdr" and schema.encoding == "ros2msg"
        assert "MSG: std_msgs/Header" in summary.schemas[channels[f"{NS}/particles"].schema_id].data.decode()
        assert "durability: 1" in channels[f"{NS}/walls"].metadata["offered_qos_profiles"]   # transient local
        assert {t: summary.statistics.channel_message_counts[c.id] for t, c in channels.items()} == COUNTS
        assert {ci.compression for ci in summary.chunk_indexes} == {"zstd"}
        for _schema, channel, message, msg in reader.iter_decoded_messages(log_time_order=True):
            stamp, value = _neutral(channel.topic, msg)
            per_topic[channel.topic].append((message.log_time, stamp, value))
    assert {t: len(v) for t, v in per_topic.items()} == COUNTS
    check_values(per_topic, run)


def test_mcap_read_by_rosbags_jazzy(run):
    from rosbags.highlevel import AnyReader
    from rosbags.typesys import Stores, get_typestore
    per_topic = defaultdict(list)
    with AnyReader([Path(run["mcap"])], default_typestore=get_typestore(Stores.ROS2_JAZZY)) as reader:
        assert {c.topic: c.msgtype for c in reader.connections} == TOPICS
        for conn, log_time, raw in reader.messages():
            msg = reader.deserialize(raw, conn.msgtype)
            stamp, value = _neutral(conn.topic, msg)
            per_topic[conn.topic].append((log_time, stamp, value))
    assert {t: len(v) for t, v in per_topic.items()} == COUNTS
    check_values(per_topic, run)


def _chunks(path):
    from rerun.chunk import RrdReader
    return RrdReader(str(path)).stream().to_chunks()


def _ns(column):
    return column.cast(pa.int64()).to_pylist()


def test_mcap_read_by_rerun_loader(run, tmp_path):
    conv = tmp_path / "converted.rrd"
    r = subprocess.run([RERUN, "mcap", "convert", str(run["mcap"]), "-o", str(conv)], env=env(),
                       capture_output=True, text=True, timeout=120)
    assert r.returncode == 0, r.stderr
    rows = defaultdict(list)   # topic -> [(log time ns, decoded row)]
    column = {"sensor_msgs/msg/PointCloud2": "sensor_msgs.msg.PointCloud2:width"}
    for chunk in _chunks(conv):
        topic = chunk.entity_path
        if chunk.is_static or topic not in TOPICS:
            continue
        rb = chunk.to_record_batch()
        name = column.get(TOPICS[topic], TOPICS[topic].replace("/", ".") + ":message")
        if name not in rb.schema.names:
            continue   # Rerun's own views of a message (e.g. Points3D from a PointCloud2) come in other chunks
        for t, value in zip(_ns(rb.column("message_log_time")), rb.column(name).to_pylist()):
            rows[topic].append((t, value[0]))
    for v in rows.values():
        v.sort(key=lambda x: x[0])
    assert {t: len(v) for t, v in rows.items()} == COUNTS
    series = run["series"]
    tips = rows[f"{NS}/tip_displacement"]
    assert [t for t, _ in tips] == expected_times()
    for t, m in tips:
        row = series[t]
        assert (m["vector"]["x"], m["vector"]["y"], m["vector"]["z"]) == (row["tip_dx"], row["tip_dy"], row["tip_dz"])
        assert m["header"]["stamp"] == {"sec": 0, "nanosec": t}
    assert [m["data"] for _, m in rows[f"{NS}/strain_energy"]] == [series[t]["strain_energy"]
                                                                    for t in expected_times()]
    assert [w for _, w in rows[f"{NS}/particles"]] == [MOVING] * FRAMES
    # Rerun's loader also turns the clouds into Points3D with our fields: the last frame's von Mises stress
    last = run["last"]
    vm = {}
    for chunk in _chunks(conv):
        if chunk.entity_path == f"{NS}/particles" and not chunk.is_static:
            rb = chunk.to_record_batch()
            if "Points3D:von_mises" in rb.schema.names:
                for t, v in zip(_ns(rb.column("message_log_time")), rb.column("Points3D:von_mises").to_pylist()):
                    vm[t] = np.array(v, dtype=np.float32)
    m = last["solid_movable"]
    np.testing.assert_array_equal(vm[expected_times()[-1]],
                                  von_mises(last["solid_stress_deviatoric"][m]).astype(np.float32))


def rrd_contents(path):
    """{entity: {sim_time ns: row values}} and the static entities of an .rrd, via rerun.chunk.RrdReader."""
    data, static = defaultdict(dict), {}
    for chunk in _chunks(path):
        rb = chunk.to_record_batch()
        comps = [n for n in rb.schema.names if ":" in n]
        if chunk.is_static:
            static[chunk.entity_path] = {n: rb.column(n).to_pylist() for n in comps}
            continue
        times = _ns(rb.column("sim_time"))
        for n in comps:
            for t, v in zip(times, rb.column(n).to_pylist()):
                data[chunk.entity_path].setdefault(t, {})[n] = v
    return data, static


def test_rrd_read_back_and_verified(run):
    r = subprocess.run([RERUN, "rrd", "verify", str(run["rrd"])], env=env(), capture_output=True, text=True,
                       timeout=120)
    assert r.returncode == 0, r.stdout + r.stderr
    data, static = rrd_contents(run["rrd"])
    assert {"/world/walls", "/world", "/legend"} <= set(static)
    assert "/world/fluid" not in data and "/world/fluid" not in static      # the scene has no fluid
    assert len(static["/world/walls"]["Points3D:positions"][0]) == CLAMP
    expected = {"/world/solid", "/probes/tip/dx", "/probes/tip/dy", "/probes/tip/dz", "/energy/kinetic",
                "/energy/strain", "/legend/solid/min", "/legend/solid/max", "/status"}
    assert set(data) == expected
    for entity in expected - {"/status"}:
        assert sorted(data[entity]) == expected_times(), entity
    series = run["series"]
    for t in expected_times():
        row = series[t]
        assert data["/probes/tip/dz"][t]["Scalars:scalars"] == [row["tip_dz"]]
        assert data["/energy/strain"][t]["Scalars:scalars"] == [row["strain_energy"]]
        assert data["/energy/kinetic"][t]["Scalars:scalars"] == [row["kinetic_energy"]]
    last = run["last"]
    m = last["solid_movable"]
    solid = data["/world/solid"][expected_times()[-1]]
    np.testing.assert_array_equal(np.array(solid["Points3D:positions"], dtype=np.float32),
                                  last["solid_position"][m].astype(np.float32))
    assert len(set(solid["Points3D:colors"])) > 10          # coloured by stress, not one flat colour
    vm = von_mises(last["solid_stress_deviatoric"][m])
    highs = [data["/legend/solid/max"][t]["Scalars:scalars"][0] for t in expected_times()]
    assert highs == sorted(highs) and highs[0] < highs[-1]    # the range only widens (from 0 at rest)
    assert 0 < highs[-1] and vm.max() > 0
    assert data["/status"][expected_times()[-1]]["TextLog:text"] == ["finished at t = 0.01 s"]


def test_compressions_and_bad_paths(tmp_path):
    for comp in ("lz4", "none"):
        path = tmp_path / f"{comp}.mcap"
        r = run_cli(["run", "cantilever", *SMALL, "--end-time", "0.002", "--record-interval", "0.001",
                     "--mcap", str(path), "--mcap-compression", comp, "--out", str(tmp_path / comp)], timeout=600)
        assert r.returncode == 0, r.stderr
        from mcap.reader import make_reader
        with open(path, "rb") as fh:
            summary = make_reader(fh).get_summary()
        assert {ci.compression for ci in summary.chunk_indexes} == {"" if comp == "none" else comp}
        assert summary.statistics.message_count == 3 * 5 + 1 + 4   # 3 frames x 5 topics, walls, diagnostics
    r = run_cli(["run", "cantilever", "--mcap", str(tmp_path / "missing" / "x.mcap")], timeout=120)
    assert r.returncode == 2 and "--mcap" in r.stderr and "does not exist" in r.stderr
    r = run_cli(["run", "cantilever", "--mcap", str(tmp_path / "x.mcap"), "--mcap-compression", "gzip"],
                timeout=120)
    assert r.returncode == 2 and "gzip" in r.stderr


@pytest.mark.parametrize("sig", [signal.SIGINT, signal.SIGTERM])
def test_signal_mid_recording_leaves_whole_files(sig, tmp_path):
    mcap, rrd = tmp_path / "run.mcap", tmp_path / "run.rrd"
    proc = subprocess.Popen([PYTHON, "-m", "sph_fsi.cli", "run", "cantilever", *SMALL, "--end-time", "5",
                             "--record-interval", str(INTERVAL), "--mcap", str(mcap), "--rrd", str(rrd),
                             "--out", str(tmp_path / "out")], env=env(), stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE, text=True)
    try:
        deadline = time.monotonic() + 300
        while time.monotonic() < deadline and proc.poll() is None:
            if rrd.exists() and rrd.stat().st_size > 40_000:   # several frames are through
                break
            time.sleep(0.1)
        assert proc.poll() is None, proc.communicate()[1]
        proc.send_signal(sig)
        _, err = proc.communicate(timeout=60)
    finally:
        if proc.poll() is None:
            proc.kill()
    assert proc.returncode == 130, err
    stop_line = [line for line in err.splitlines() if f"stopped by {sig.name}" in line]
    assert stop_line, err
    t_stop = round(float(stop_line[0].split("t = ")[1].split()[0]) * 1e9)
    from mcap.reader import make_reader
    from mcap_ros2.decoder import DecoderFactory
    with open(mcap, "rb") as fh:
        reader = make_reader(fh, decoder_factories=[DecoderFactory()])
        assert reader.get_summary() is not None            # finished: summary and footer written
        clocks, statuses = [], []
        for _s, channel, _m, msg in reader.iter_decoded_messages(log_time_order=True):
            if channel.topic == "/clock":
                clocks.append(stamp_ns(msg.clock))
            elif channel.topic == "/diagnostics":
                statuses.append(msg.status[0].message)
    n = len(clocks)
    assert n >= 4, clocks
    # every frame from t = 0 to the stop, none missing; the state at the stop is the last frame
    assert clocks[:-1] == [round(k * INTERVAL * 1e9) for k in range(n - 1)]
    assert clocks[-1] == t_stop and 0 < clocks[-1] - clocks[-2] <= round(INTERVAL * 1e9) + 1
    # the frame at the stop says "interrupted" unless it was a regular frame already; then the final status
    assert set(statuses[:n - 1]) == {"running"} and statuses[-1] == "interrupted" and len(statuses) == n + 1
    r = subprocess.run([RERUN, "rrd", "verify", str(rrd)], env=env(), capture_output=True, text=True, timeout=120)
    assert r.returncode == 0, r.stdout + r.stderr
    data, _ = rrd_contents(rrd)
    assert sorted(data["/world/solid"]) == clocks
    assert data["/status"][t_stop]["TextLog:text"] == [f"interrupted at t = {t_stop * 1e-9:.6g} s"]
    # the headless outputs too: the time series up to the stop and a summary that says it was cut short
    summary = json.loads((tmp_path / "out" / "summary.json").read_text())
    assert summary["status"] == "interrupted" and "error" not in summary
    assert round(summary["simulated_time_s"] * 1e9) == t_stop and summary["stepping_time_s"] > 0
    times = np.loadtxt(tmp_path / "out" / "timeseries.csv", delimiter=",", skiprows=1, usecols=0)
    assert round(times[-1] * 1e9) == t_stop and len(times) == summary["outer_steps"] + 1


def test_fluid_scene_records_fluid_and_walls_only(tmp_path):
    """A scene with water and walls but no solid: the fluid as phase 1 coloured by pressure, no solid topics."""
    from mcap.reader import make_reader
    from mcap_ros2.decoder import DecoderFactory
    mcap, rrd, out = tmp_path / "h.mcap", tmp_path / "h.rrd", tmp_path / "out"
    r = run_cli(["run", "hydrostatic", "--set", "numerics.spacing=0.005", "--end-time", "0.02",
                 "--record-interval", "0.005", "--mcap", str(mcap), "--rrd", str(rrd), "--out", str(out)],
                timeout=600)
    assert r.returncode == 0, r.stderr
    snaps = sorted((out / "snapshots").glob("snapshot_*.npz"))
    first, last = np.load(snaps[0]), np.load(snaps[-1])
    assert abs(float(last["time"]) - 0.02) < 1e-9
    clouds = {}
    with open(mcap, "rb") as fh:
        reader = make_reader(fh, decoder_factories=[DecoderFactory()])
        topics = {c.topic for c in reader.get_summary().channels.values()}
        for _s, ch, _m, msg in reader.iter_decoded_messages(log_time_order=True):
            if ch.topic in (f"{NS}/particles", f"{NS}/walls"):
                clouds.setdefault(ch.topic, []).append(_cloud(msg)[2])
    assert topics == {f"{NS}/particles", f"{NS}/walls", "/clock", "/diagnostics"}
    assert len(clouds[f"{NS}/particles"]) == 5 and len(clouds[f"{NS}/walls"]) == 1
    pts = clouds[f"{NS}/particles"][-1]
    assert (pts["phase"] == 1).all() and len(pts) == len(last["fluid_position"])
    np.testing.assert_array_equal(pts["pressure"], last["fluid_pressure"].astype(np.float32))
    np.testing.assert_array_equal(pts["z"], last["fluid_position"][:, 2].astype(np.float32))
    assert pts["pressure"].max() > 100.0          # hydrostatic pressure builds up: rho g H ~ 981 Pa at the floor
    np.testing.assert_array_equal(clouds[f"{NS}/walls"][0]["x"], first["wall_position"][:, 0].astype(np.float32))
    assert subprocess.run([RERUN, "rrd", "verify", str(rrd)], env=env(), capture_output=True,
                          timeout=120).returncode == 0
    data, static = rrd_contents(rrd)
    assert "/world/fluid" in data and "/world/solid" not in data and "/world/walls" in static
    assert "/energy/fluid_kinetic" in data and "/energy/strain" not in data
    assert sorted(data["/world/fluid"]) == [round(k * 0.005e9) for k in range(5)]
    assert len(data["/world/fluid"][round(0.02e9)]["Points3D:positions"]) == len(last["fluid_position"])
    assert data["/legend/fluid/max"][round(0.02e9)]["Scalars:scalars"][0] > 100.0


def test_gate_scene_mcap_three_readers(tmp_path):
    """The gate (water, gate, walls; coarse: 2 mm, 4 ms): all three MCAP readers agree with each other and with the
    simulator: per-topic counts, the tip displacement at every frame, both phases' points at the end."""
    from mcap.reader import make_reader
    from mcap_ros2.decoder import DecoderFactory
    from rosbags.highlevel import AnyReader
    from rosbags.typesys import Stores, get_typestore
    mcap, out, conv = tmp_path / "g.mcap", tmp_path / "out", tmp_path / "g.rrd"
    r = run_cli(["run", "elastic_gate", "--set", "numerics.spacing=0.002", "--set", "solid.scheme=gray2001",
                 "--end-time", "0.004",
                 "--record-interval", "0.001", "--mcap", str(mcap), "--out", str(out)], timeout=600)
    assert r.returncode == 0, r.stderr
    with open(out / "timeseries.csv") as fh:
        series = {round(float(row["time"]) * 1e9): row for row in csv.DictReader(fh)}
    last = np.load(sorted((out / "snapshots").glob("snapshot_*.npz"))[-1])
    times = [round(k * 1e6) for k in range(5)]
    counts = {t: 5 for t in TOPICS if t not in (f"{NS}/walls", "/diagnostics")}
    counts.update({f"{NS}/walls": 1, "/diagnostics": 6})

    a = defaultdict(list)
    with open(mcap, "rb") as fh:
        for _s, ch, m, msg in make_reader(fh, decoder_factories=[DecoderFactory()]).iter_decoded_messages(
                log_time_order=True):
            a[ch.topic].append((m.log_time, _neutral(ch.topic, msg)))
    b = defaultdict(list)
    with AnyReader([Path(mcap)], default_typestore=get_typestore(Stores.ROS2_JAZZY)) as reader:
        for conn, t, raw in reader.messages():
            b[conn.topic].append((t, _neutral(conn.topic, reader.deserialize(raw, conn.msgtype))))
    assert subprocess.run([RERUN, "mcap", "convert", str(mcap), "-o", str(conv)], env=env(), capture_output=True,
                          timeout=120).returncode == 0
    c = defaultdict(list)
    for chunk in _chunks(conv):
        if chunk.is_static or chunk.entity_path not in TOPICS:
            continue
        rb = chunk.to_record_batch()
        typ = TOPICS[chunk.entity_path]
        name = "sensor_msgs.msg.PointCloud2:width" if typ.endswith("PointCloud2") else typ.replace("/", ".") + ":message"
        if name in rb.schema.names:
            c[chunk.entity_path] += list(zip(_ns(rb.column("message_log_time")), rb.column(name).to_pylist()))
    for counted in (a, b, c):
        assert {t: len(v) for t, v in counted.items()} == counts
    for readers_tips in (a[f"{NS}/tip_displacement"], b[f"{NS}/tip_displacement"]):
        assert [t for t, _ in readers_tips] == times
        assert [v for _, (_, v) in readers_tips] == [
            (float(series[t]["tip_dx"]), float(series[t]["tip_dy"]), float(series[t]["tip_dz"])) for t in times]
    assert [(m[0]["vector"]["x"], m[0]["vector"]["z"]) for _, m in sorted(c[f"{NS}/tip_displacement"])] == [
        (float(series[t]["tip_dx"]), float(series[t]["tip_dz"])) for t in times]
    n_fluid, m = len(last["fluid_position"]), last["solid_movable"]
    for readers_clouds in (a[f"{NS}/particles"], b[f"{NS}/particles"]):
        _, (_, (fields, _, pts)) = readers_clouds[-1]
        assert fields == FIELDS and len(pts) == n_fluid + int(m.sum())
        assert (pts["phase"][:n_fluid] == 1).all() and (pts["phase"][n_fluid:] == 2).all()
        np.testing.assert_array_equal(pts["pressure"][:n_fluid], last["fluid_pressure"].astype(np.float32))
        np.testing.assert_array_equal(pts["x"][:n_fluid], last["fluid_position"][:, 0].astype(np.float32))
        np.testing.assert_array_equal(pts["von_mises"][n_fluid:],
                                      von_mises(last["solid_stress_deviatoric"][m]).astype(np.float32))
    assert [w[0] for _, w in sorted(c[f"{NS}/particles"])] == [n_fluid + int(m.sum())] * 5


def test_divergence_closes_whole_files_saying_so(tmp_path):
    """A run that diverges (the watchdog's speed limit below the beam's initial tip speed, 0.01 m/s): exit 3, both
    files whole, frames up to the last good state, the final status 'diverged'."""
    from mcap.reader import make_reader
    from mcap_ros2.decoder import DecoderFactory
    mcap, rrd = tmp_path / "d.mcap", tmp_path / "d.rrd"
    r = run_cli(["run", "cantilever", *SMALL, "--set", "watchdog.max_speed=0.005", "--end-time", "0.01",
                 "--record-interval", "0", "--mcap", str(mcap), "--rrd", str(rrd), "--out", str(tmp_path / "o")],
                timeout=600)
    assert r.returncode == 3, r.stderr
    statuses = []
    with open(mcap, "rb") as fh:
        reader = make_reader(fh, decoder_factories=[DecoderFactory()])
        assert reader.get_summary() is not None
        for _s, ch, _m, msg in reader.iter_decoded_messages(log_time_order=True):
            if ch.topic == "/diagnostics":
                statuses.append(msg.status[0].message)
    assert statuses == ["running", "diverged"]        # the t = 0 frame, then the end; nothing from the bad state
    assert subprocess.run([RERUN, "rrd", "verify", str(rrd)], env=env(), capture_output=True,
                          timeout=120).returncode == 0
    data, _ = rrd_contents(rrd)
    assert sorted(data["/world/solid"]) == [0]
    (status,) = data["/status"].values()
    assert status["TextLog:text"][0].startswith("diverged at t = ")


def test_rerun_connect_streams_live(tmp_path):
    """--rerun-connect: a Rerun gRPC server (`rerun --port P --save FILE`, headless) receives every frame."""
    import socket
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        port = s.getsockname()[1]
    saved = tmp_path / "live.rrd"
    # `rerun` is a Python launcher that starts the viewer binary as its child: its own session, so that the
    # signals below reach the binary too (otherwise the binary outlives the test and leaves live.rrd unfinished)
    server = subprocess.Popen([RERUN, "--port", str(port), "--save", str(saved)], env=env(),
                              stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True, start_new_session=True)
    try:
        deadline = time.monotonic() + 60
        while time.monotonic() < deadline:
            with socket.socket() as s:
                if s.connect_ex(("127.0.0.1", port)) == 0:
                    break
            time.sleep(0.1)
        r = run_cli(["run", "cantilever", *SMALL, "--end-time", "0.005", "--record-interval", "0.001",
                     "--rerun-connect", f"127.0.0.1:{port}", "--out", str(tmp_path / "o")], timeout=600)
        assert r.returncode == 0, r.stderr
        time.sleep(1.0)
    finally:
        os.killpg(server.pid, signal.SIGINT)
        deadline = time.monotonic() + 30
        while time.monotonic() < deadline:       # the launcher and the binary, which finishes the file first
            server.poll()
            try:
                os.killpg(server.pid, 0)
            except ProcessLookupError:
                break
            time.sleep(0.1)
        else:
            os.killpg(server.pid, signal.SIGKILL)
    data, static = rrd_contents(saved)
    assert sorted(data["/world/solid"]) == [round(k * 1e6) for k in range(6)]
    assert len(static["/world/walls"]["Points3D:positions"][0]) == CLAMP
    assert data["/status"][round(5e6)]["TextLog:text"] == ["finished at t = 0.005 s"]
