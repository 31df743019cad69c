"""Recorder parts in-process: the bounded queue, a failing sink, schemas, and phases a scene has or lacks.

A stand-in simulation (plain arrays, no Numba) gives the recorder a fluid, a solid and walls, or only some of them.
"""
import threading
import time
from types import SimpleNamespace

import numpy as np
import pytest

from sph_fsi.recording import Recorder
from sph_fsi.recording.msgdefs import SEPARATOR, msgdef_text
from sph_fsi.recording.writer import BackgroundWriter
from sph_fsi_core.numerics.tensors import von_mises


class FakeSim:
    def __init__(self, fluid=True, solid=True, walls=True, n=50):
        rng = np.random.default_rng(1)
        self.time = 0.0
        self.spec = SimpleNamespace(name="fake")
        self.spacing = 0.01
        self.solid_phase = SimpleNamespace(steps=0, last_dt=1e-6) if solid else None
        self.fluid_phase = SimpleNamespace(steps=0, last_iterations=3, last_error_max=0.004) if fluid else None
        self.particle_count = n
        self.fluid = SimpleNamespace(pos=rng.random((n, 3)), vel=rng.random((n, 3)),
                                     pressure=rng.random(n) * 1e3 - 100, rho=np.full(n, 1000.0)) if fluid else None
        self.solid = SimpleNamespace(pos=rng.random((n, 3)), vel=rng.random((n, 3)), pressure=rng.random(n),
                                     stress=rng.random((n, 6)) * 1e4, movable=np.arange(n) >= 10) if solid else None
        self.walls = SimpleNamespace(pos=rng.random((20, 3))) if walls else None
        self.probes = [SimpleNamespace(name="tip")] if solid else []

    def probe_displacements(self):
        return {"tip": np.array([self.time, 2 * self.time, 3 * self.time])} if self.solid is not None else {}

    def energies(self):
        return {"kinetic_energy": self.time, "strain_energy": 2 * self.time} if self.solid is not None else {}

    def step(self, dt=0.001):
        self.time += dt
        if self.solid_phase is not None:
            self.solid_phase.steps += 1
        for s in (self.fluid, self.solid):
            if s is not None:
                s.pos += dt


def test_schema_text_has_dependencies_in_short_form():
    text = msgdef_text("sensor_msgs/msg/PointCloud2")
    assert text.startswith("# This message holds a collection of N-dimensional points")
    deps = [line for line in text.splitlines() if line.startswith("MSG: ")]
    assert deps == ["MSG: std_msgs/Header", "MSG: builtin_interfaces/Time", "MSG: sensor_msgs/PointField"]
    assert text.count(SEPARATOR + "\nMSG: ") == 3 and "/msg/" not in "".join(deps)
    assert "MSG: geometry_msgs/Vector3" in msgdef_text("geometry_msgs/msg/Vector3Stamped")


def test_full_queue_waits_and_warns_once_with_counts():
    release = threading.Event()
    written = []

    class SlowSink:
        def write(self, item):
            release.wait()
            written.append(item)

        def close(self):
            written.append("closed")

    logs = []
    w = BackgroundWriter([SlowSink()], max_queue=2, log=logs.append)
    w.submit(0)                 # taken by the thread, which then waits in the sink
    time.sleep(0.2)
    w.submit(1)                 # two queued: no wait yet
    w.submit(2)
    assert w.waits == 0 and not logs
    threading.Timer(0.3, release.set).start()
    t0 = time.perf_counter()
    w.submit(3)                 # full: waits for the sink
    w.submit(4)
    assert time.perf_counter() - t0 > 0.2
    assert w.waits >= 1 and len(logs) == 1 and "queue full (2 frames waiting" in logs[0] and "of 3 written" in logs[0]
    stats = w.close()
    assert written == [0, 1, 2, 3, 4, "closed"] and stats["written"] == 5 and stats["submitted"] == 5


def test_failing_sink_is_dropped_and_the_others_go_on():
    class Bad:
        closed = False

        def write(self, item):
            if item == 1:
                raise OSError("disk full")

        def close(self):
            Bad.closed = True

    class Good:
        items = []

        def write(self, item):
            Good.items.append(item)

        def close(self):
            Good.items.append("closed")

    logs = []
    w = BackgroundWriter([Bad(), Good()], log=logs.append)
    for i in range(4):
        w.submit(i)
    stats = w.close()
    assert Good.items == [0, 1, 2, 3, "closed"] and Bad.closed
    assert stats["errors"] == ["Bad: OSError: disk full"] and "Bad stopped" in logs[0]


@pytest.mark.parametrize("phases", [("fluid", "solid", "walls"), ("fluid",), ("solid",)])
def test_only_what_the_scene_has(phases, tmp_path):
    from mcap.reader import make_reader
    from mcap_ros2.decoder import DecoderFactory
    from rerun.chunk import RrdReader
    sim = FakeSim(**{p: p in phases for p in ("fluid", "solid", "walls")})
    rec = Recorder(sim, mcap_path=tmp_path / "f.mcap", rrd_path=tmp_path / "f.rrd", interval=0.002)
    rec.maybe_record(sim)
    for _ in range(4):
        sim.step()
        rec.maybe_record(sim)
    assert rec.close(sim)["errors"] == []
    with open(tmp_path / "f.mcap", "rb") as fh:
        reader = make_reader(fh, decoder_factories=[DecoderFactory()])
        topics = {c.topic for c in reader.get_summary().channels.values()}
        clouds = [msg for _s, ch, _m, msg in reader.iter_decoded_messages() if ch.topic == "/sph_fsi/particles"]
    expected = {"/sph_fsi/particles", "/clock", "/diagnostics"}
    if "solid" in phases:
        expected |= {"/sph_fsi/tip_displacement", "/sph_fsi/probes/tip/displacement", "/sph_fsi/strain_energy"}
    if "walls" in phases or "solid" in phases:    # the clamp is a wall too
        expected.add("/sph_fsi/walls")
    assert topics == expected
    assert len(clouds) == 3                       # t = 0, 0.002, 0.004
    n_fluid = 50 if "fluid" in phases else 0
    n_solid = 40 if "solid" in phases else 0
    last = clouds[-1]
    assert last.width == n_fluid + n_solid
    pts = np.frombuffer(bytes(last.data), dtype=np.dtype({"names": ["pressure", "von_mises", "phase"],
                                                          "formats": ["<f4", "<f4", "u1"],
                                                          "offsets": [24, 28, 32], "itemsize": 36}))
    assert list(np.bincount(pts["phase"], minlength=3)[1:]) == [n_fluid, n_solid]
    if n_fluid:
        np.testing.assert_array_equal(pts["pressure"][:n_fluid], sim.fluid.pressure.astype(np.float32))
    if n_solid:
        np.testing.assert_array_equal(pts["von_mises"][n_fluid:],
                                      von_mises(sim.solid.stress[sim.solid.movable]).astype(np.float32))
    entities = {c.entity_path for c in RrdReader(str(tmp_path / "f.rrd")).stream().to_chunks()}
    assert ("/world/fluid" in entities) == ("fluid" in phases)
    assert ("/world/solid" in entities) == ("solid" in phases)
    assert ("/world/walls" in entities) == ("walls" in phases or "solid" in phases)
    assert ("/energy/strain" in entities) == ("solid" in phases)
