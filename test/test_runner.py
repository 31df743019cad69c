"""The node's simulation thread without ROS (sph_fsi.runner.Runner): pause, step, reset, end time, out_dir
summaries, and its time series against run_scene's (one run loop: sph_fsi_core.run.Run), to the bit.

The runner's outputs go to a fake that keeps what would have been published. A small cantilever (12 x 3 x 4 mm
at 1 mm, output.timeseries_interval 0.25 ms) with a publish period of 1 ms (4 outer steps).
"""
import json
import threading
import time
from pathlib import Path

import pytest

from sph_fsi.parameters import node_defaults
from sph_fsi.runner import Runner, numbered
from sph_fsi_core.run import END_TOLERANCE, Run, headline, run_scene
from sph_fsi_core.scene import load_scene

SMALL = [("geometry.length", 0.012), ("geometry.width", 0.003), ("geometry.clamp_margin", 2)]
PERIOD = 0.001
OUTER = 2.5e-4


class FakeOut:
    """What the node would publish, as plain values."""

    def __init__(self):
        self.lock = threading.Lock()
        self.frames = []          # simulated times of published frames
        self.walls = []
        self.diagnostics = []     # (level, message, values)
        self.ended_with = []
        self.scenes = []
        self.restored = []

    def ok(self):
        return True

    def sync_topics(self, sim, qos):
        self.qos = qos

    def publish_walls(self, sim, frame_id):
        self.walls.append(sim.time)

    def publish_frame(self, sim, frame_id):
        with self.lock:
            self.frames.append(sim.time)
        return True

    def publish_diagnostics(self, t, level, message, values, frame_id):
        with self.lock:
            self.diagnostics.append((level, message, values))

    def scene_changed(self, spec):
        self.scenes.append(spec.name)

    def restore_parameters(self, values):
        self.restored.append(values)

    def ended(self, code):
        self.ended_with.append(code)


class Log:
    def __init__(self):
        self.lines = []

    def info(self, msg):
        self.lines.append(("info", msg))

    def warning(self, msg):
        self.lines.append(("warning", msg))

    def error(self, msg):
        self.lines.append(("error", msg))


def wait_until(predicate, timeout=120.0):
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        if predicate():
            return
        time.sleep(0.01)
    raise AssertionError("timed out")


def accumulated(n, dt=OUTER):
    """sim.time after n outer steps: the same float additions as Simulation.step."""
    t = 0.0
    for _ in range(n):
        t += dt
    return t


@pytest.fixture
def runner(tmp_path):
    settings = dict(node_defaults(), publish_period=PERIOD, out_dir=str(tmp_path / "run"))
    out, log = FakeOut(), Log()
    r = Runner(load_scene("cantilever", SMALL), settings, out, log)
    r.out_log = log
    r.pause(True)
    r.start()
    wait_until(lambda: len(out.frames) == 1)   # the t = 0 frame of the first build
    yield r
    r.stop()


def test_paused_step_reset_and_numbered_out_dir(runner, tmp_path):
    out = runner.out
    time.sleep(0.5)
    assert runner.sim.time == 0.0 and out.frames == [0.0]          # paused: no step
    assert runner.status() == ("ok", "paused")
    assert runner.request_step()[0]
    wait_until(lambda: len(out.frames) == 2)
    assert out.frames[1] == accumulated(4) and runner.sim.outer_steps == 4   # one publish period exactly
    time.sleep(0.3)
    assert len(out.frames) == 2 and runner.sim.time == accumulated(4)        # and no more
    assert not (tmp_path / "run" / "summary.json").exists()

    runner.request_reset()
    wait_until(lambda: len(out.frames) == 3)
    assert out.frames[2] == 0.0 and runner.sim.time == 0.0 and runner.status()[1] == "paused"
    first = json.loads((tmp_path / "run" / "summary.json").read_text())   # the reset run's, cut short
    assert first["status"] == "reset" and first["simulated_time_s"] == accumulated(4)
    assert first["outer_steps"] == 4 and "error" not in first

    # the next run goes to <out_dir>_1; resumed, it runs to end_time and is judged
    runner.change({"end_time": 0.003}, {}, runner.desired, set())
    runner.pause(False)
    wait_until(lambda: (tmp_path / "run_1" / "summary.json").exists())   # written after the last frame
    assert runner.status()[1] == "finished"
    assert runner.sim.time == accumulated(12) and out.frames[-3:] == [accumulated(4), accumulated(8),
                                                                      accumulated(12)]
    second = json.loads((tmp_path / "run_1" / "summary.json").read_text())
    assert second["status"] == "finished" and second["outer_steps"] == 12 and second["end_time_s"] == 0.003
    assert ("info", "finished at t = 0.003 s") in runner.out_log.lines
    assert not runner.request_step()[0]   # at its end time


def test_a_change_made_on_seeing_a_resets_first_frame_is_kept(runner):
    """Whoever sees the rebuilt run's first frame may change a key at once (the node's test does: solid.scheme
    right after a reset); the reset has made its values the desired ones before that frame, so it does not undo
    the change when it ends. The change is made here inside the frame's publication, as late as it can come."""
    out = runner.out
    later = runner.desired.with_overrides({"numerics.spacing": 0.0005})
    publish = out.publish_frame

    def publish_then_change(sim, frame_id):
        done = publish(sim, frame_id)
        if len(out.frames) == 2:
            runner.change({}, {"numerics.spacing": 0.0005}, later, {"numerics.spacing"})
        return done

    out.publish_frame = publish_then_change
    runner.request_reset()
    wait_until(lambda: len(out.frames) == 2)
    time.sleep(0.3)
    assert runner.desired is later and runner.pending() == ["numerics.spacing"]
    assert runner.sim.spec.values["numerics.spacing"] == 0.001
    runner.request_reset()
    wait_until(lambda: len(out.frames) == 3)
    assert runner.sim.spec.values["numerics.spacing"] == 0.0005 and runner.pending() == []


def test_runner_time_series_equals_run_scenes_to_the_bit(runner, tmp_path):
    """One loop: the node's runner and run_scene (the CLI) give the same time series and summary numbers."""
    end = 0.005
    runner.change({"end_time": end}, {}, runner.desired, set())
    runner.pause(False)
    wait_until(lambda: (tmp_path / "run" / "summary.json").exists())
    assert runner.status()[1] == "finished"
    node_csv = (tmp_path / "run" / "timeseries.csv").read_bytes()
    node_summary = json.loads((tmp_path / "run" / "summary.json").read_text())

    spec = load_scene("cantilever", SMALL + [("scene.end_time", end), ("output.snapshot_interval", 0.0)])
    cli = run_scene(spec, tmp_path / "cli", progress=False)
    assert (tmp_path / "cli" / "timeseries.csv").read_bytes() == node_csv
    assert cli["snapshots"] == 0 and not (tmp_path / "cli" / "snapshots").exists()   # none asked for, no folder
    assert len(node_csv.splitlines()) == 1 + 1 + round(end / OUTER)   # header, t = 0, 20 outer steps
    for key in ("simulated_time_s", "outer_steps", "solid_steps", "solid_dt_s", "particle_steps", "status"):
        assert cli[key] == node_summary[key], key
    for key in [k for k in cli if k.startswith(("frequency", "check_", "error", "peak"))]:
        if key == "error_metric":   # names where the FE reference came from: the first of the two runs computes it
            assert cli[key].replace(", cached", "") == node_summary[key].replace(", cached", ""), key
        else:
            assert cli[key] == node_summary[key], key


def test_run_end_rule_and_numbered_paths():
    run = Run(load_scene("cantilever", SMALL), end_time=accumulated(3))
    steps = 0
    while not run.at_end:
        assert run.advance()
        steps += 1
    assert steps == 3 and run.sim.time == accumulated(3) and len(run.log.rows) == 4
    run.end_time = accumulated(3) + 2 * END_TOLERANCE   # past the tolerance: one more outer step
    assert not run.at_end
    run.end_time = accumulated(3) + 0.5 * END_TOLERANCE
    assert run.at_end
    summary = run.finish("finished")
    assert summary["status"] == "finished" and summary["stepping_time_s"] > 0
    assert numbered("runs/x.mcap", 0) == "runs/x.mcap" and numbered("runs/x.mcap", 2) == "runs/x_2.mcap"
    assert numbered("runs/out", 1) == "runs/out_1"


def test_a_coupled_runs_summary_splits_its_stepping_time_between_the_solid_and_the_rest():
    """summary.json's solid_stepping_time_s is the part of stepping_time_s inside the solid's sub-steps: more than
    nothing, less than the whole (the water's steps take the rest), and the headline gives the share."""
    from test_coupling import COARSE
    run = Run(load_scene("elastic_gate", COARSE + [("output.snapshot_interval", 0.0)]), end_time=0.004)
    while not run.at_end:
        assert run.advance()
    summary = run.finish("interrupted")
    solid, stepping = summary["solid_stepping_time_s"], summary["stepping_time_s"]
    assert 0.0 < solid < stepping and summary["solid_steps"] > summary["fluid_steps"] > 0
    assert f"the solid's steps {100 * solid / stepping:.0f} % of the stepping" in headline(summary)
    fluid_only = Run(load_scene("dam_break", [("numerics.spacing", 0.05715 / 10)]), end_time=0.002)
    fluid_only.advance()
    assert "solid_stepping_time_s" not in fluid_only.finish("interrupted")


def test_runner_imports_without_ros():
    from test_core_is_ros_free import import_without_ros
    repo = Path(__file__).resolve().parents[1]
    result = import_without_ros(repo, "sph_fsi_core", "sph_fsi.runner", "sph_fsi.parameters", "sph_fsi.ament")
    assert result.returncode == 0, result.stdout + result.stderr


def test_cold_cache_says_compiling_and_keeps_it_out_of_the_rate(tmp_path, monkeypatch):
    """With Numba's cache cold (here: said so) the runner logs that it compiles before the build, then how long the
    build and first step took, and starts its progress (rate, ETA) after that step."""
    import sph_fsi.runner as runner_module
    from sph_fsi_core.jit_cache import COMPILING_LINE
    monkeypatch.setattr(runner_module, "scene_kernels_cached", lambda spec: False)
    settings = dict(node_defaults(), publish_period=PERIOD, out_dir=str(tmp_path / "run"))
    out, log = FakeOut(), Log()
    r = Runner(load_scene("cantilever", SMALL), settings, out, log)
    r.pause(True)
    r.start()
    try:
        wait_until(lambda: len(out.frames) == 1)
        assert log.lines[0] == ("info", COMPILING_LINE)
        r.request_step()
        wait_until(lambda: any("compiled and took the first step in" in m for _, m in log.lines))
        assert r.progress.stepping_s == 0.0 and r.progress.start_time == pytest.approx(r.sim.time)
        assert r.sim.time > 0.0
        r.request_step()
        wait_until(lambda: r.progress.stepping_s > 0.0)
        assert sum("compiled and took" in m for _, m in log.lines) == 1
    finally:
        r.stop()


def test_progress_in_the_log_and_on_diagnostics(runner, monkeypatch):
    """Every PROGRESS_LOG_INTERVAL of wall time the log says how far the run is (simulated time, percent, ETA,
    particle-steps/s), and /diagnostics carries the same numbers; pauses do not count towards the rate."""
    import sph_fsi.runner as runner_module
    monkeypatch.setattr(runner_module, "PROGRESS_LOG_INTERVAL", 0.0)
    out = runner.out
    runner.change({"end_time": 0.004}, {}, runner.desired, set())
    runner.pause(False)
    wait_until(lambda: runner.status()[1] == "finished")
    lines = [m for level, m in runner.out_log.lines if level == "info" and "particle-steps/s" in m]
    assert lines, runner.out_log.lines
    first = lines[0]       # after the first publish period: t = 1 ms of 4 ms
    assert first.startswith(f"t = {accumulated(4):.6g} of 0.004 s (25.0 %), ETA ")
    progress = runner.progress.numbers(0.004)
    assert progress["percent"] == pytest.approx(100.0)
    steps = runner.sim.solid.count * runner.sim.solid_phase.steps
    assert progress["particle_steps_per_second"] == pytest.approx(steps / runner.progress.stepping_s)
    running = [v for level, message, v in out.diagnostics if message == "running"]
    assert running and all({"progress_percent", "eta_s", "particle_steps_per_second"} <= set(v) for v in running)
    assert any(float(v["progress_percent"]) == pytest.approx(25.0) for v in running)


def _paused_runner(settings_extra, tmp_path):
    settings = dict(node_defaults(), publish_period=PERIOD, out_dir="", **settings_extra)
    out, log = FakeOut(), Log()
    r = Runner(load_scene("cantilever"), settings, out, log)
    r.pause(True)
    r.start()
    wait_until(lambda: len(out.frames) == 1)
    return r, out, log


def _reset_and_wait(r, out):
    n = len(out.frames)
    r.request_reset()
    wait_until(lambda: len(out.frames) == n + 1)   # the rebuilt scene's t = 0 frame


def test_resets_do_not_grow_the_resident_memory(tmp_path):
    """100 resets of the cantilever (paused: the rebuild only): resident memory from the 20th to the 100th within
    5 %. Without handing the freed heap back (runner.return_freed_memory) it rose from 278 to 510 MB over 200, about
    1.2 MB a reset: 35 % over these 80."""
    import psutil
    proc = psutil.Process()
    r, out, _ = _paused_runner({}, tmp_path)
    try:
        rss = {}
        for i in range(1, 101):
            _reset_and_wait(r, out)
            if i in (20, 100):
                rss[i] = proc.memory_info().rss
    finally:
        r.stop()
    assert abs(rss[100] / rss[20] - 1.0) < 0.05, {k: v / 2 ** 20 for k, v in rss.items()}


def test_recordings_after_a_reset_are_whole_and_their_rerun_process_ends(tmp_path):
    """The node's recordings after its first are written by a child process (recording/rerun_process.py, so that
    rerun-sdk's per-stream memory leaves with it): each numbered .rrd passes `rerun rrd verify` and holds its run's
    t = 0 frame and its end; every child has exited once its recording closed."""
    import subprocess
    import sys
    import psutil
    from test_recording import RERUN, env, rrd_contents
    r, out, log = _paused_runner({"mcap_path": str(tmp_path / "r.mcap"), "rrd_path": str(tmp_path / "r.rrd"),
                                  "record_interval": 0.0}, tmp_path)
    try:
        for _ in range(3):
            assert r.request_step()[0]
            wait_until(lambda: len(out.frames) >= 2 and out.frames[-1] > 0.0)
            _reset_and_wait(r, out)
    finally:
        r.stop()
    assert psutil.Process().children() == [], "a Rerun recorder process outlived its recording"
    files = [tmp_path / "r.rrd"] + [tmp_path / f"r_{n}.rrd" for n in (1, 2, 3)]
    for f in files:
        check = subprocess.run([RERUN, "rrd", "verify", str(f)], env=env(), capture_output=True, text=True,
                               timeout=120)
        assert check.returncode == 0, (f, check.stdout + check.stderr)
        data, static = rrd_contents(f)
        assert {"/world/walls", "/world", "/legend"} <= set(static), f
        times = sorted(data["/probes/tip/dz"])
        assert times[0] == 0 and len(times) >= (5 if f != files[-1] else 1), (f, times)   # t = 0 and one period
    for f in files[:-1]:   # the recordings that a reset closed say so
        data, _ = rrd_contents(f)
        assert list(data["/status"].values())[-1]["TextLog:text"][0].startswith("reset at t = "), f
    assert not [line for level, line in log.lines if level == "warning" and "recording" in line], log.lines


def test_the_node_reports_water_that_leaves_and_stops_only_at_the_scenes_fraction(tmp_path):
    """Water with no tank falls out of its domain box. By default the runner goes on and /diagnostics counts the
    water lost; with watchdog.max_fluid_lost = 0.1 it stops at the step that loses more, as its own outcome: a
    warning (not an error), status water_lost in the summary, exit status 4 with on_end exit."""
    from sph_fsi.runner import EXIT_WATER_LOST
    scene = tmp_path / "falling.yaml"
    scene.write_text("scene: {builder: geometry, end_time: 0.04}\nnumerics: {spacing: 0.01}\n"
                     "geometry: {domain_margin: 0.005}\noutput: {timeseries_interval: 0.001, snapshot_interval: 0}\n"
                     "parts:\n  - {name: water, role: water, shape: box, size: [0.05, 0.05, 0.05], "
                     "position: [0.025, 0.025, 0.025]}\n")
    for limit, status, code in ((1.0, "finished", 0), (0.1, "water_lost", EXIT_WATER_LOST)):
        settings = dict(node_defaults(), publish_period=0.005, on_end="exit", out_dir=str(tmp_path / status))
        out, log = FakeOut(), Log()
        r = Runner(load_scene(str(scene), [("watchdog.max_fluid_lost", limit)]), settings, out, log)
        r.start()
        try:
            wait_until(lambda: out.ended_with)
            assert out.ended_with == [code] and r.status() == (("ok", "finished") if code == 0 else
                                                               ("warn", "water_lost"))
            summary = json.loads((tmp_path / status / "summary.json").read_text())
            assert summary["status"] == status and summary["stable"] and summary["fluid_lost"]["particles"] >= 25
            level, message, values = out.diagnostics[-1]
            assert (level, message) == r.status() and int(values["fluid_particles_lost"]) >= 25
            assert "-z" in values["fluid_lost_faces"] and float(values["fluid_lost_since"]) >= 0.0319
            if code:
                assert values["check"] == "left the domain" and "watchdog.max_fluid_lost = 0.1" in values["detail"]
                assert any(kind == "warning" and msg.startswith("water lost: left the domain")
                           for kind, msg in log.lines)
                assert not any(kind == "error" for kind, _ in log.lines)
                assert not r.request_step()[0] and "call ~/reset" in r.request_step()[1]
            assert ("warning", summary["warnings"][0]) in log.lines        # the falling water, said at the build
        finally:
            r.stop()
