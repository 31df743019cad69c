"""The probes in the recordings: the geometry_probes scene (test/data/geometry_probes.yaml: a probe of every kind;
~9,000 particles at 10 mm) recorded in-process with sph_fsi.recording.Recorder at t = 0 and after each of three
outer steps, every frame's Simulation.probe_readings() kept to compare with.

MCAP: one channel per probe quantity, with the node's topic names and types and a ros2msg schema holding every
dependency; read back by mcap-ros2-support, by rosbags (Jazzy typestore) and by Rerun's MCAP loader (which
decodes with the file's schema text), each message equal to the reading at its stamp (float64: to the bit), log
time = stamp = simulated time. Rerun (.rrd): a scalar entity per probe scalar and per vector component, at each
frame's simulated time. Pure functions: the Rerun entity paths of each kind, the message dicts' fields.
"""
import copy
import subprocess
from collections import defaultdict
from pathlib import Path

import pytest

from test_recording import RERUN, _chunks, _ns, env, rrd_contents

SCENE = Path(__file__).resolve().parent / "data" / "geometry_probes.yaml"
FRAMES = 4                                   # t = 0 and three outer steps (2 ms each)
TIMES = [round(k * 2e6) for k in range(FRAMES)]
NS = "/sph_fsi/probes"
V3, PRESSURE = "geometry_msgs/msg/Vector3Stamped", "sensor_msgs/msg/FluidPressure"
POINT, WRENCH = "geometry_msgs/msg/PointStamped", "geometry_msgs/msg/WrenchStamped"
PROBE_TOPICS = {f"{NS}/tip/displacement": V3, f"{NS}/tip/velocity": V3, f"{NS}/wall_p/pressure": PRESSURE,
                f"{NS}/level/surface": POINT, f"{NS}/plate_force/force": WRENCH,
                f"{NS}/floor_force/force": WRENCH}
# the schema's dependencies, in the order rosbag2 writes them (depth first)
DEPENDENCIES = {V3: ["std_msgs/Header", "builtin_interfaces/Time", "geometry_msgs/Vector3"],
                PRESSURE: ["std_msgs/Header", "builtin_interfaces/Time"],
                POINT: ["std_msgs/Header", "builtin_interfaces/Time", "geometry_msgs/Point"],
                WRENCH: ["std_msgs/Header", "builtin_interfaces/Time", "geometry_msgs/Wrench",
                         "geometry_msgs/Vector3"]}


pytestmark = pytest.mark.usefixtures("one_numba_thread")   # their simulations on one thread


@pytest.fixture(scope="module")
def recorded(tmp_path_factory):
    from sph_fsi.recording import Recorder
    from sph_fsi_core.scene import load_scene
    from sph_fsi_core.simulation import Simulation
    d = tmp_path_factory.mktemp("probes")
    sim = Simulation(load_scene(str(SCENE)))
    rec = Recorder(sim, mcap_path=d / "p.mcap", rrd_path=d / "p.rrd", interval=0.0)
    readings = {}
    for k in range(FRAMES):
        if k:
            sim.step()
        assert rec.maybe_record(sim)
        readings[round(sim.time * 1e9)] = copy.deepcopy(sim.probe_readings())
    assert rec.close(sim)["errors"] == []
    assert sorted(readings) == TIMES
    # not a comparison of zeros: by the last frame the plate moves, the water presses on the wall and the floor
    tip, wall_p, floor = (readings[TIMES[-1]][n][1] for n in ("tip", "wall_p", "floor_force"))
    assert abs(tip["velocity"][2]) > 1e-4 and wall_p["pressure"] > 0.0 and floor["force"][2] < 0.0
    return {"mcap": d / "p.mcap", "rrd": d / "p.rrd", "readings": readings}


def expected_value(readings, topic):
    """What a message on /sph_fsi/probes/<name>/<quantity> must carry: the reading at its stamp."""
    name, quantity = topic[len(NS) + 1:].split("/")
    return readings[name][1][quantity]


def neutral(msg):
    """(stamp ns, frame_id, value) of a decoded probe message (mcap-ros2-support's or rosbags' objects)."""
    stamp = msg.header.stamp.sec * 1_000_000_000 + msg.header.stamp.nanosec
    if hasattr(msg, "vector"):
        value = (msg.vector.x, msg.vector.y, msg.vector.z)
    elif hasattr(msg, "fluid_pressure"):
        assert msg.variance == 0.0
        value = msg.fluid_pressure
    elif hasattr(msg, "point"):
        value = (msg.point.x, msg.point.y, msg.point.z)
    else:
        t = msg.wrench.torque
        assert (t.x, t.y, t.z) == (0.0, 0.0, 0.0)
        value = (msg.wrench.force.x, msg.wrench.force.y, msg.wrench.force.z)
    return stamp, msg.header.frame_id, value


def check(per_topic, recorded):
    """per_topic: {probe topic: [(log time ns, decoded message)]}."""
    assert set(per_topic) == set(PROBE_TOPICS)
    for topic, msgs in per_topic.items():
        assert [t for t, _ in msgs] == TIMES, topic
        for t, msg in msgs:
            stamp, frame_id, value = neutral(msg)
            assert stamp == t and frame_id == "map"
            assert value == expected_value(recorded["readings"][t], topic), (topic, t)


def test_mcap_probe_channels_read_by_mcap_ros2_support(recorded):
    from mcap.reader import make_reader
    from mcap_ros2.decoder import DecoderFactory
    per_topic = defaultdict(list)
    with open(recorded["mcap"], "rb") as fh:
        reader = make_reader(fh, decoder_factories=[DecoderFactory()])
        summary = reader.get_summary()
        channels = {c.topic: c for c in summary.channels.values()}
        # the scene's topics: its probes', the kept ~/tip_displacement (a probe named tip), a solid's and fluid's
        assert set(channels) == set(PROBE_TOPICS) | {"/sph_fsi/tip_displacement", "/sph_fsi/particles",
                                                     "/sph_fsi/walls", "/sph_fsi/strain_energy", "/clock",
                                                     "/diagnostics"}
        for topic, type_name in PROBE_TOPICS.items():
            schema = summary.schemas[channels[topic].schema_id]
            assert (schema.name, schema.encoding, channels[topic].message_encoding) == (type_name, "ros2msg", "cdr")
            text = schema.data.decode()
            assert [line for line in text.splitlines() if line.startswith("MSG: ")] == [
                f"MSG: {dep}" for dep in DEPENDENCIES[type_name]]
            assert text.count("=" * 80 + "\nMSG: ") == len(DEPENDENCIES[type_name])
            assert summary.statistics.channel_message_counts[channels[topic].id] == FRAMES
        for _schema, channel, message, msg in reader.iter_decoded_messages(log_time_order=True):
            if channel.topic in PROBE_TOPICS:
                assert message.publish_time == message.log_time
                per_topic[channel.topic].append((message.log_time, msg))
            elif channel.topic == "/sph_fsi/tip_displacement":   # the point probe's displacement, too
                assert neutral(msg)[2] == recorded["readings"][message.log_time]["tip"][1]["displacement"]
    check(per_topic, recorded)


def test_mcap_probe_channels_read_by_rosbags_jazzy(recorded):
    from rosbags.highlevel import AnyReader
    from rosbags.typesys import Stores, get_typestore
    per_topic = defaultdict(list)
    with AnyReader([Path(recorded["mcap"])], default_typestore=get_typestore(Stores.ROS2_JAZZY)) as reader:
        types = {c.topic: c.msgtype for c in reader.connections}
        assert {t: types[t] for t in PROBE_TOPICS} == PROBE_TOPICS
        for conn, log_time, raw in reader.messages():
            if conn.topic in PROBE_TOPICS:
                per_topic[conn.topic].append((log_time, reader.deserialize(raw, conn.msgtype)))
    check(per_topic, recorded)


def test_mcap_probe_channels_read_by_rerun_loader(recorded, tmp_path):
    """Rerun's MCAP loader decodes each message with the file's schema text (FluidPressure it turns into
    Measurements)."""
    conv = tmp_path / "converted.rrd"
    r = subprocess.run([RERUN, "mcap", "convert", str(recorded["mcap"]), "-o", str(conv)], env=env(),
                       capture_output=True, text=True, timeout=120)
    assert r.returncode == 0, r.stderr
    rows = defaultdict(list)
    for chunk in _chunks(conv):
        topic = chunk.entity_path
        if chunk.is_static or topic not in PROBE_TOPICS:
            continue
        rb = chunk.to_record_batch()
        name = PROBE_TOPICS[topic].replace("/", ".") + ":message"
        if name in rb.schema.names:
            rows[topic] += list(zip(_ns(rb.column("message_log_time")), rb.column(name).to_pylist()))
        elif "Measurements:values" in rb.schema.names:
            rows[topic] += list(zip(_ns(rb.column("message_log_time")), rb.column("Measurements:values").to_pylist(),
                                    rb.column("Measurements:variances").to_pylist()))
    readings = recorded["readings"]
    assert set(rows) == set(PROBE_TOPICS)
    for topic, got in rows.items():
        got.sort(key=lambda row: row[0])
        assert [row[0] for row in got] == TIMES, topic
        for t, *value in got:
            want = expected_value(readings[t], topic)
            if PROBE_TOPICS[topic] == PRESSURE:
                assert value == [[want], [0.0]], topic
                continue
            m = value[0][0]
            assert m["header"] == {"stamp": {"sec": 0, "nanosec": t}, "frame_id": "map"}
            field = {V3: "vector", POINT: "point"}.get(PROBE_TOPICS[topic])
            xyz = m[field] if field else m["wrench"]["force"]
            assert (xyz["x"], xyz["y"], xyz["z"]) == want, topic
            if not field:
                assert m["wrench"]["torque"] == {"x": 0.0, "y": 0.0, "z": 0.0}


def test_rrd_probe_scalars(recorded):
    r = subprocess.run([RERUN, "rrd", "verify", str(recorded["rrd"])], env=env(), capture_output=True, text=True,
                       timeout=120)
    assert r.returncode == 0, r.stdout + r.stderr
    data, _ = rrd_contents(recorded["rrd"])
    scalars = {"/probes/wall_p/pressure": ("wall_p", "pressure", None),
               "/probes/level/height": ("level", "height", None)}
    for name, quantity in (("tip", "displacement"), ("tip", "velocity"), ("level", "surface"),
                           ("plate_force", "force"), ("floor_force", "force")):
        for i, axis in enumerate("xyz"):
            scalars[f"/probes/{name}/{quantity}/{axis}"] = (name, quantity, i)
    assert {e for e in data if e.startswith("/probes/")} == set(scalars)
    for entity, (name, quantity, i) in scalars.items():
        assert sorted(data[entity]) == TIMES, entity
        for t in TIMES:
            value = recorded["readings"][t][name][1][quantity]
            assert data[entity][t]["Scalars:scalars"] == [value if i is None else value[i]], (entity, t)


def test_rerun_paths_and_message_dicts_of_each_kind():
    """The entity paths of each kind (a displacement probe keeps {dx,dy,dz}), and the MCAP dicts' fields."""
    from sph_fsi.recording.mcap_sink import probe_dict
    from sph_fsi.recording.rerun_sink import probe_scalars
    readings = {"tip": ("displacement", {"displacement": (1.0, 2.0, 3.0)}),
                "P1": ("pressure", {"pressure": 5.5}),
                "H2": ("water_height", {"height": 0.25, "surface": (0.5, 0.0, 0.25)}),
                "pt": ("point", {"displacement": (0.1, 0.2, 0.3), "velocity": (-1.0, 0.0, 1.0)}),
                "F": ("force", {"force": (7.0, 8.0, 9.0)})}
    assert probe_scalars(readings) == [
        ("probes/tip/dx", 1.0), ("probes/tip/dy", 2.0), ("probes/tip/dz", 3.0), ("probes/P1/pressure", 5.5),
        ("probes/H2/height", 0.25), ("probes/H2/surface/x", 0.5), ("probes/H2/surface/y", 0.0),
        ("probes/H2/surface/z", 0.25), ("probes/pt/displacement/x", 0.1), ("probes/pt/displacement/y", 0.2),
        ("probes/pt/displacement/z", 0.3), ("probes/pt/velocity/x", -1.0), ("probes/pt/velocity/y", 0.0),
        ("probes/pt/velocity/z", 1.0), ("probes/F/force/x", 7.0), ("probes/F/force/y", 8.0),
        ("probes/F/force/z", 9.0)]
    header = {"stamp": {"sec": 1, "nanosec": 5}, "frame_id": "map"}
    assert probe_dict("pressure", 5.5, header) == {"header": header, "fluid_pressure": 5.5, "variance": 0.0}
    assert probe_dict("surface", (0.5, 0.0, 0.25), header) == {"header": header,
                                                               "point": {"x": 0.5, "y": 0.0, "z": 0.25}}
    assert probe_dict("force", (7, 8, 9), header)["wrench"] == {"force": {"x": 7.0, "y": 8.0, "z": 9.0},
                                                                 "torque": {"x": 0.0, "y": 0.0, "z": 0.0}}
    with pytest.raises(ValueError, match="height"):
        probe_dict("height", 0.25, header)    # a scalar that has an entity in Rerun but no topic
