"""The node's simulation, without ROS: a thread that runs a scene one publish period at a time, with pause,
step, reset, end time, divergence, the out_dir summaries and the recorders. sph_fsi.node wires it to rclpy;
tests drive it directly (test/node/test_runner.py).

Threads: the simulation thread (`start()`) owns the Run (sph_fsi_core.run) and is the only one that steps,
publishes and records. Other threads (the node's services and parameter callbacks) call `pause`, `request_step`,
`request_reset`, `change` and `settings` updates; those take a short lock (`lock`), enqueue a command or set a
flag, and return at once: they never wait for a step. The thread takes commands between outer steps.

What it shows goes through `out`, an object with
    ok() -> bool                                     may publish (False once the node shuts down)
    sync_topics(sim, qos)                            the topics this scene has, with this QoS
    publish_walls(sim, frame_id)
    publish_frame(sim, frame_id) -> bool             particles, probes, energies, /clock (False: shut down)
    publish_diagnostics(time, level, message, values, frame_id)   level 'ok' | 'warn' | 'error'
    scene_changed(spec)                              after every reset: the rebuilt scene's keys and values
    restore_parameters({key: value})                 a live value the simulation refused: the value kept
    ended(code)                                      on_end 'exit' reached, a startup error or a failure
and `log`, with info, warning and error (an rclpy logger).
"""
import math
import os
import threading
import time
import traceback
from collections import deque

from sph_fsi_core.jit_cache import COMPILING_LINE, scene_kernels_cached
from sph_fsi_core.precompile import compile_cold_scene
from sph_fsi_core.run import Progress, Run, headline, make_writable_dir, step_counts
from sph_fsi_core.scene import load_scene
from sph_fsi_core.schema import SceneError

from .points import moving_particles

__all__ = ["Runner", "numbered", "EXIT_BAD_INPUT", "EXIT_DIVERGED", "EXIT_WATER_LOST"]

EXIT_BAD_INPUT = 2
EXIT_DIVERGED = 3
EXIT_WATER_LOST = 4     # more water left the domain than the scene's watchdog.max_fluid_lost allows
PROGRESS_LOG_INTERVAL = 10.0   # s of wall time between progress lines in the log
# the watchdog's stops (diagnostics.Stopped.outcome), as a message says them
_STOPPED = {"diverged": "diverged", "water_lost": "stopped: more water left the domain than watchdog.max_fluid_lost"}


def return_freed_memory():
    """Hand the memory of a dropped run back to the system. A rebuilt scene frees its particle arrays and
    neighbour lists, but glibc keeps freed heap pages in the simulation thread's malloc arena: the node's resident
    memory rose by about 140 MB over its first 80 resets and stayed there, with no object left alive (after
    malloc_trim it is flat; test_runner.py measures 200 resets). Elsewhere than glibc: only the collection."""
    import ctypes
    import gc
    gc.collect()
    try:
        ctypes.CDLL("libc.so.6").malloc_trim(0)
    except (OSError, AttributeError):
        pass


def numbered(path, n):
    """The n-th file or directory of a path: the path itself, then <stem>_<n><suffix> after each reset."""
    if n == 0:
        return path
    root, ext = os.path.splitext(path)
    return f"{root}_{n}{ext}"


def _steps(sim):
    """Solid plus fluid steps taken so far (the diagnostics' steps/s)."""
    return sum(step_counts(sim))


class Runner:
    """spec: the scene to build first; settings: the node parameters' values (sph_fsi.parameters.NODE_PARAMS),
    kept and updated here; namespace: the recordings' topic prefix."""

    def __init__(self, spec, settings, out, log, namespace="/sph_fsi"):
        self.out = out
        self.log = log
        self.namespace = namespace
        self.exit_code = 0
        self.lock = self._cv = threading.Condition()   # guards the state below up to the thread-only state
        self.settings = dict(settings)          # node parameters in effect (those applied at reset: as built)
        self._restored = self.settings.pop("_restored", None)   # a checkpoint's state to start from (restart_from)
        self._checkpoints = []                  # (path or None, error or None) of each ~/write_checkpoint done
        self.desired = spec                     # every accepted scene-key value, live and deferred
        self._first_spec = spec
        self._commands = deque()
        self._part_commands = deque()           # (part, stamp s, kind, values) for the walls driven by commands
        self._received = {}                     # part -> the latest stamp of a command received (lockstep)
        self._paused = False
        self._stopping = False
        self._finished = False
        self._stopped = None                    # the watchdog's Stopped (Diverged, WaterLost) once it tripped
        self._pending_keys = set()              # rebuild keys changed since the running simulation was built
        self._pending_settings = {}             # node parameters (scene, qos, recording) for the next reset
        self._last_error = ""
        self._sim_time = 0.0

        # simulation-thread-only state
        self.run = None                         # the running sph_fsi_core.run.Run
        self.sim = None
        self.progress = None                    # sph_fsi_core.run.Progress of the running simulation
        self._recordings = 0                    # recorders opened so far (numbers the files after a reset)
        self._runs = 0                          # runs built so far (numbers out_dir after a reset)
        self._out_dir = None                    # this run's out_dir, or None
        self._summary_steps = 0                 # the run's outer steps when its summary was last written
        self._last_diag_wall = 0.0
        self._refused_seen = 0                  # the boundary's refused commands already reported
        self._thread = threading.Thread(target=self._run, name="simulation", daemon=True)

    # ---- called from other threads: answer at once ---------------------------------------------------------
    def start(self):
        self._thread.start()

    def pause(self, flag):
        """(was paused, simulated time)."""
        with self._cv:
            was = self._paused
            self._paused = bool(flag)
            self._cv.notify_all()
            return was, self._sim_time

    def request_step(self):
        """(accepted, message): one publish period while paused."""
        self._check_end_time()   # end_time may have been raised a moment ago, before the sim thread looked
        with self._cv:
            if self._stopped is not None:
                return False, f"the run {_STOPPED[self._stopped.outcome]}; call ~/reset"
            if self._finished:
                return False, "the run is at its end time; call ~/reset (or raise end_time)"
            if not self._paused:
                return False, "~/step works while paused; call ~/pause true first"
            self._commands.append(("step",))
            self._cv.notify_all()
            return True, f"stepping one publish period from t = {self._sim_time:.6g} s"

    def request_reset(self):
        """Rebuild from the desired values at t = 0 (on the simulation thread); returns what it will apply."""
        with self._cv:
            self._commands.append(("reset",))
            self._cv.notify_all()
            return self.pending()

    def request_checkpoint(self, timeout=5.0):
        """Write a checkpoint of the run between its next two outer steps (on the simulation thread), to
        checkpoint_path or <out_dir>/checkpoint.ckpt; waits up to `timeout` s. Returns (success, message)."""
        path = self.settings["checkpoint_path"] or (os.path.join(self.settings["out_dir"], "checkpoint.ckpt")
                                                    if self.settings["out_dir"] else "")
        if not path:
            return False, "no place to write it: set checkpoint_path (or out_dir)"
        with self._cv:
            ticket = len(self._checkpoints) + sum(1 for c in self._commands if c[0] == "checkpoint")
            self._commands.append(("checkpoint", path))
            self._cv.notify_all()
            done = self._cv.wait_for(lambda: len(self._checkpoints) > ticket, timeout)
            if not done:
                return True, f"queued: a checkpoint goes to {path} after the current outer step"
            written, error = self._checkpoints[ticket]
        return (True, written) if error is None else (False, error)

    def _write_checkpoint(self, path):
        from sph_fsi_core.checkpoint import write_checkpoint
        try:
            write_checkpoint(self.run, path)
            result = (f"checkpoint of t = {self.sim.time:.6g} s written to {path}; continue it with the node's "
                      f"restart_from or sph-fsi run --restart {path}", None)
            self.log.info(result[0])
        except OSError as exc:
            result = (None, f"checkpoint not written to {path}: {exc.strerror or exc}")
            self.log.error(result[1])
        with self._cv:
            self._checkpoints.append(result)
            self._cv.notify_all()

    def part_command(self, name, stamp, kind, values, source=None):
        """A command for the commanded wall `name` (the node's ~/parts/<name>/pose_cmd or twist_cmd), stamped
        `stamp` s of simulated time; kind, values and source as sph_fsi_core.boundary.Boundary.command. The
        simulation thread hands it to the boundary before its next outer step."""
        with self._cv:
            self._part_commands.append((name, float(stamp), kind, values, source))
            self._received[name] = max(self._received.get(name, -math.inf), float(stamp))
            self._cv.notify_all()

    def lockstep_waiting(self):
        """With lockstep on: the commanded walls whose latest command is stamped before the simulated time now
        (the run waits for them); [] otherwise."""
        sim = self.sim
        if not self.settings["lockstep"] or sim is None or sim.boundary is None:
            return []
        with self._cv:
            return [name for name in sim.boundary.commanded()
                    if self._received.get(name, -math.inf) < sim.time - 0.5e-9]

    def _take_part_commands(self):
        """Queued commands into the boundary; those it refuses (a part that takes none) reported."""
        with self._cv:
            commands = list(self._part_commands)
            self._part_commands.clear()
        for name, stamp, kind, values, source in commands:
            if kind == "unreadable":
                self._refuse(stamp, name, values)
                continue
            try:
                self.sim.boundary.command(name, stamp, kind, values, source)
            except (ValueError, AttributeError) as exc:
                self._refuse(stamp, name, str(exc))

    def _report_refusals(self):
        """The commands the boundary refused since the last report: a warning each, on the log and /diagnostics."""
        refused = self.sim.boundary.refused if self.sim.boundary is not None else []
        for t, name, why in refused[self._refused_seen:]:
            self._refuse(t, name, why)
        self._refused_seen = len(refused)

    def _refuse(self, t, name, why):
        message = f"parts.{name}: command at t = {t:.9g} s refused: {why}"
        self.log.warning(message)
        with self._cv:
            self._last_error = message
        self._publish_diagnostics()

    def pending(self):
        """Keys accepted but waiting for the next reset, sorted."""
        with self._cv:
            return sorted(self._pending_keys | set(self._pending_settings))

    def change(self, node_changes, scene_changes, desired, rebuild_keys):
        """Accepted changes (sph_fsi.parameters.check_changes): live scene keys go to the simulation between
        outer steps, keys in `rebuild_keys` and node parameters applied at reset wait for ~/reset, the other node
        parameters apply at once. Returns (keys applied now, keys waiting for the reset)."""
        from .parameters import AT_RESET
        now, later = [], []
        with self._cv:
            self.desired = desired
            live = {}
            for key, value in scene_changes.items():
                if key in rebuild_keys:
                    self._pending_keys.add(key)
                    later.append(key)
                else:
                    live[key] = value
                    now.append(key)
            if live:
                self._commands.append(("apply", live))
            for key, value in node_changes.items():
                if key in AT_RESET:
                    self._pending_settings[key] = value
                    later.append(key)
                else:
                    self.settings[key] = value
                    now.append(key)
            self._cv.notify_all()
        return now, later

    def stop(self):
        """Stop the simulation thread (after its current outer step), join it, close the recordings and write
        the run's summary ('interrupted')."""
        with self._cv:
            self._stopping = True
            self._cv.notify_all()
        if self._thread.is_alive():
            self._thread.join()
        self._close_recorders("interrupted")
        self._write_summary("interrupted")

    def status(self):
        """(level 'ok' | 'warn' | 'error', 'running' | 'paused' | 'finished' | 'diverged' | 'water_lost' | 'waiting
        for commands': lockstep, a commanded wall's command for the time now not yet received)."""
        with self._cv:
            if self._stopped is not None:
                return ("error" if self._stopped.outcome == "diverged" else "warn"), self._stopped.outcome
            if self._finished:
                return "ok", "finished"
            if self._paused:
                return "ok", "paused"
        if self.lockstep_waiting():
            return "ok", "waiting for commands"
        with self._cv:
            return ("warn" if self._last_error else "ok"), "running"

    # ---- the simulation thread ---------------------------------------------------------------------------
    def _run(self):
        try:
            self._loop()
        except Exception as exc:   # a bug, not a divergence: report it and end the process non-zero
            self.log.error(f"simulation thread failed: {type(exc).__name__}: {exc}")
            traceback.print_exc()
            self._end(1)

    def _end(self, code):
        self.exit_code = code
        self.out.ended(code)

    def _loop(self):
        try:
            self._build(self._first_spec, restored=self._restored)
            self._restored = None
        except SceneError as exc:
            self.log.error(str(exc))
            self._end(EXIT_BAD_INPUT)
            return
        self._last_diag_wall = 0.0
        while True:
            with self._cv:
                if self._stopping:
                    return
                cmds = list(self._commands)
                self._commands.clear()
            for cmd in cmds:
                self._handle(cmd)
            if self._stopping:
                return
            self._take_part_commands()       # into the boundary as they come, paused or waiting too
            self._check_end_time()
            if self._can_run():
                wait = self._realtime_wait()
                if wait > 0.0:
                    self._wait(wait)
                else:
                    self.advance(interruptible=True)
                continue
            if time.monotonic() - self._last_diag_wall >= 1.0:
                if self.lockstep_waiting():    # the frame it waits on again: a controller that joined late gets it
                    self._publish_frame()
                else:
                    self._publish_diagnostics()
            self._wait(1.0)

    def _wait(self, seconds):
        with self._cv:
            if not self._commands and not self._part_commands and not self._stopping and (seconds > 0.0):
                self._cv.wait(min(seconds, 1.0))

    def _can_run(self):
        with self._cv:
            if self._paused or self._finished or self._stopped is not None or self._stopping:
                return False
        return not self.lockstep_waiting()

    def _sync_end(self):
        """The run's end: the end_time parameter, or (0) the scene's scene.end_time."""
        run = self.run
        run.end_time = self.settings["end_time"] or None
        return run.end

    def _check_end_time(self):
        """end_time (or scene.end_time) raised past a finished run's time: it runs on."""
        if self.run is None:
            return
        with self._cv:
            self._sync_end()
            again = self._finished and not self.run.at_end
            if again:
                self._finished = False
        if again:
            self.log.info(f"end time raised to {self.run.end:g} s: running on")
            self._publish_diagnostics()

    def _handle(self, cmd):
        kind = cmd[0]
        if kind == "apply":
            try:
                self.sim.apply(cmd[1])
            except SceneError as exc:   # a live value the running state cannot take (e.g. an unstable dt)
                effective = {k: self.sim.spec.values[k] for k in cmd[1]}
                with self._cv:
                    self.desired = self.desired.with_overrides(effective)
                    self._last_error = str(exc)
                self.out.restore_parameters(effective)
                self.log.error(f"{exc}; kept {effective}")
                self._publish_diagnostics()
        elif kind == "reset":
            self._reset()
        elif kind == "checkpoint":
            self._write_checkpoint(cmd[1])
        elif kind == "step":
            with self._cv:
                ok = self._paused and not self._finished and self._stopped is None
            if ok:
                self.advance(interruptible=False)

    def _reset(self):
        with self._cv:
            scene = self._pending_settings.pop("scene", None)
            asked = desired = self.desired
        old_run, old_sim = self.run, self.sim

        def commit():
            """The rebuilt run's values become the desired ones before its first frame goes out, so a change
            made by whoever saw that frame is not undone; one made during the build (same scene) stays, pending.
            Returns the desired values, which the parameters show."""
            with self._cv:
                if scene is not None or self.desired is asked:
                    self.desired = desired
                    self._pending_keys.clear()
                else:   # still pending: the keys whose desired value is not the built one
                    self._pending_keys = {k for k in self._pending_keys
                                          if self.desired.values.get(k) != desired.values.get(k)}
                self._last_error = ""
                return self.desired

        try:
            if scene is not None:
                desired = load_scene(scene or None)
                self.settings["scene"] = scene
            self._build(desired, show_parameters=True, built=commit)
        except SceneError as exc:
            with self._cv:
                self._last_error = f"reset refused: {exc}"
            self.log.error(f"reset refused: {exc}")
            self.run, self.sim = old_run, old_sim
            self._publish_diagnostics()
            return
        del old_run, old_sim
        return_freed_memory()

    def _build(self, spec, restored=None, show_parameters=False, built=None):
        """Build the run for `spec` and publish its first frame. show_parameters (a reset): first set the node's
        parameters to the rebuilt scene's values (a new scene's keys, or the detailed keys a changed solid.scheme
        expanded to), so that whoever sees the new run's first frame reads its parameters. built(): called once
        the run is built, before its first frame goes out; returns the values the parameters show."""
        started = time.monotonic()
        cold = scene_kernels_cached(spec) is False
        if cold:
            self.log.info(COMPILING_LINE)
            compile_cold_scene(spec, self.log.info, self.log.warning)
        run = Run(spec, restored=restored)
        if restored is not None:
            self.log.info(f"continuing '{spec.name}' from its checkpoint at t = {run.sim.time:.6g} s "
                          f"({self.settings['restart_from']})")
        else:     # what the build says (a part that took the water's sites, a free body), and its warnings
            for note in run.sim.notes:
                self.log.info(note)
            for warning in run.sim.warnings:
                self.log.warning(warning)
        self._close_recorders("reset")
        self._write_summary("reset")
        self.run, self.sim = run, run.sim
        self._outer_dt = run.sim.outer_step_duration()
        with self._cv:
            self._finished = False
            self._stopped = None
            self._sim_time = 0.0
            qos = self._pending_settings.pop("qos", None)
        if qos is not None:
            self.settings["qos"] = qos
        self._rate = 0.0
        self._rate_mark = None
        self._anchor = None
        self.progress = Progress(run.sim)
        self._progress_logged = time.monotonic()
        self._compiling_since = started if cold else None   # until the first outer step is done
        shown = built() if built is not None else spec
        if show_parameters:
            self.out.scene_changed(shown)
        self.out.sync_topics(run.sim, self.settings["qos"])
        self.out.publish_walls(run.sim, self.settings["frame_id"])
        self._publish_frame()
        self._open_recorder()
        self._out_dir = numbered(self.settings["out_dir"], self._runs) if self.settings["out_dir"] else None
        if self._out_dir:
            try:
                make_writable_dir(self._out_dir)
            except OSError as exc:
                why = f"out_dir {self._out_dir!r}: not writable ({exc.strerror})"
                if self._runs == 0:
                    raise SceneError(f"{why}; allowed: a writable directory") from None
                self.log.error(f"{why}; this run's summary goes to the log only")
                self._out_dir = None
        self._runs += 1
        self._summary_steps = 0

    def _realtime_wait(self):
        rtf = self.settings["realtime_factor"]
        now = time.monotonic()
        if rtf <= 0.0:
            self._anchor = None
            return 0.0
        if self._anchor is None or self._anchor[2] != rtf:
            self._anchor = (now, self.sim.time, rtf)
            return 0.0
        target = self._anchor[0] + (self.sim.time - self._anchor[1]) / rtf
        if now > target + 0.5:   # fell behind (slow steps, or a pause): do not catch up in a burst
            self._anchor = (now, self.sim.time, rtf)
            return 0.0
        return max(0.0, target - now)

    def _interrupted(self):
        with self._cv:
            return self._stopping or self._paused or any(c[0] == "reset" for c in self._commands)

    def _take_applies(self):
        with self._cv:
            applies = [c for c in self._commands if c[0] == "apply"]
            for c in applies:
                self._commands.remove(c)
        for c in applies:
            self._handle(c)

    def advance(self, interruptible):
        """One publish period (whole outer steps), or less at the end time or on an interruption; then publish.
        Simulation thread only."""
        run, sim = self.run, self.sim
        n = max(1, math.ceil(self.settings["publish_period"] / self._outer_dt - 1e-9))
        self._sync_end()
        if self._rate_mark is None:
            self._rate_mark = (time.monotonic(), _steps(sim))
        done = 0
        started = time.monotonic()
        while done < n and not run.at_end:
            if interruptible and self._interrupted():
                break
            self._take_part_commands()
            if done == 0 and self.lockstep_waiting():      # lockstep: a command for each publish period
                break
            if not run.advance():
                self._on_stopped()
                return
            done += 1
            self._take_applies()
            if sim.boundary is not None and sim.boundary.refused:
                self._report_refusals()
        now = time.monotonic()
        if self._compiling_since is not None and done:
            # the first step carried the compilation: say how long it took, and keep it out of the rate and ETA
            self.log.info(f"compiled and took the first step in {now - self._compiling_since:.0f} s")
            self._compiling_since = None
            self.progress = Progress(sim)
            self._progress_logged = now
        else:
            self.progress.add(now - started)
        if now - self._progress_logged >= PROGRESS_LOG_INTERVAL and not run.at_end:
            self._progress_logged = now
            self.log.info(self.progress.line(run.end))
        if now > self._rate_mark[0]:
            self._rate = (_steps(sim) - self._rate_mark[1]) / (now - self._rate_mark[0])
        self._rate_mark = (now, _steps(sim))
        reached_end = run.at_end
        with self._cv:
            self._sim_time = sim.time
            if reached_end:
                self._finished = True
            if self._paused or not interruptible:
                self._rate_mark = None
        if done:
            self._publish_frame()
        elif reached_end:
            self._publish_diagnostics()
        else:
            return   # interrupted before the first step: nothing new to publish
        if reached_end:
            self.log.info(f"finished at t = {sim.time:.6g} s")
            self._write_summary("finished")
            if self.settings["on_end"] == "exit":
                self._end(0)

    def _on_stopped(self):
        exc = self.run.stopped
        with self._cv:
            self._stopped = exc
            self._sim_time = self.sim.time
        if exc.outcome == "diverged":   # rclpy: one severity per call site
            self.log.error(str(exc))
        else:
            self.log.warning(str(exc))
        self._write_summary(exc.outcome)
        self._publish_diagnostics()
        if self.settings["on_end"] == "exit":
            self._end(EXIT_DIVERGED if exc.outcome == "diverged" else EXIT_WATER_LOST)

    # ---- the run's time series and summary (the last one written by stop()) ------------------------------
    def _write_summary(self, status):
        """Summary (error against the reference, wall time) to the log and, with out_dir, to disk; once per
        state: not again while the run has not stepped since (a reset or stop after the end or a divergence),
        nor for a run that never stepped. The watchdog's stop always writes."""
        run = self.run
        if run is None or (status not in _STOPPED and run.sim.outer_steps == self._summary_steps):
            return
        self._summary_steps = run.sim.outer_steps
        self._sync_end()
        summary = run.finish(status)
        where = ""
        if self._out_dir:
            try:
                run.log.write(self._out_dir, summary)
                where = f" (written to {self._out_dir}/)"
            except OSError as exc:
                where = f" (not written to {self._out_dir}/: {exc})"
                with self._cv:
                    self._last_error = f"out_dir: {exc}"
        line = f"run {headline(summary)}{where}"
        if status == "diverged":   # rclpy: one severity per call site
            self.log.error(line)
        else:
            self.log.info(line)

    # ---- recordings (closed by stop() after the thread has ended) -----------------------------------------
    def _open_recorder(self):
        with self._cv:
            for key in [k for k in self._pending_settings if k != "scene"]:
                self.settings[key] = self._pending_settings.pop(key)
        st = self.settings
        if not (st["mcap_path"] or st["rrd_path"] or st["rerun_connect"]):
            return
        n = self._recordings
        paths = {key: numbered(st[key], n) if st[key] else None for key in ("mcap_path", "rrd_path")}
        from .recording import Recorder
        try:
            rec = Recorder(self.sim, mcap_path=paths["mcap_path"], mcap_compression=st["mcap_compression"],
                           rrd_path=paths["rrd_path"], rerun_connect=st["rerun_connect"] or None,
                           interval=st["record_interval"], frame_id=st["frame_id"], namespace=self.namespace,
                           log=self.log.warning, rerun_process=n > 0)
        except (OSError, ValueError) as exc:
            if n == 0:
                raise SceneError(f"recording: {exc}") from None
            self.log.error(f"recording not restarted: {exc}")
            with self._cv:
                self._last_error = f"recording not restarted: {exc}"
            return
        self._recordings += 1
        self.run.add_recorder(rec)
        self.log.info("recording to " + ", ".join(p for p in [paths["mcap_path"], paths["rrd_path"],
                                                              st["rerun_connect"]] if p))

    def _close_recorders(self, reason):
        if self.run is None or not self.run.recorders:
            return
        with self._cv:
            status = (self._stopped.outcome if self._stopped is not None else "finished" if self._finished
                      else reason)
        for rec, stats in self.run.close(status):
            self.log.info(f"recording closed ({status}): {rec.frames} frames"
                          + (f"; the simulation waited {stats['waits']} times for the recorder"
                             if stats["waits"] else ""))

    # ---- publishing ----------------------------------------------------------------------------------------
    def _publish_frame(self):
        """Particles, probes and energies at the current simulated time, then /clock and /diagnostics."""
        if self.out.ok() and self.out.publish_frame(self.sim, self.settings["frame_id"]):
            self._publish_diagnostics()

    def diagnostics(self):
        """(level, message, {key: str}) of the running simulation, for /diagnostics."""
        sim = self.sim
        level, message = self.status()
        running = message == "running"
        values = {"scene": sim.spec.name, "sim_time": f"{sim.time:.9g}", "end_time": f"{self._sync_end():.9g}",
                  "steps_per_second": f"{self._rate if running else 0.0:.6g}", "particles": str(sim.particle_count),
                  "moving_particles": str(sum(len(p[1]) for p in moving_particles(sim))),
                  "solid_steps": str(step_counts(sim)[0]),
                  "solid_dt": f"{sim.solid_phase.last_dt if sim.solid_phase is not None else 0.0:.6g}"}
        progress = self.progress.numbers(self._sync_end())
        values.update(progress_percent=f"{progress['percent']:.3g}",
                      eta_s=f"{progress['eta_s']:.4g}" if running and progress["eta_s"] is not None else "",
                      particle_steps_per_second=f"{progress['particle_steps_per_second'] or 0.0:.6g}")
        water = sim.fluid_phase
        if water is not None:   # the density correction's last step
            values.update(iterations=f"{water.last_iterations:d}", density_error=f"{water.last_error_max:.6g}",
                          fluid_steps=str(water.steps), fluid_dt=f"{water.last_dt:.6g}",
                          capped_steps=str(water.capped_steps), fluid_particles_lost=str(int(water.lost.sum())))
            lost = water.lost_water.summary()
            if lost["particles"]:
                values.update(fluid_lost_fraction=f"{lost['fraction']:.6g}",
                              fluid_lost_since=f"{lost['first_time_s']:.9g}",
                              fluid_lost_faces=", ".join(f"{k} {n}" for k, n in lost["faces"].items()),
                              fluid_lost_nearest=", ".join(f"{k} {n}" for k, n in
                                                           lost.get("nearest_walls", {}).items()))
        pending = self.pending()
        with self._cv:
            stopped = self._stopped
            last_error = self._last_error
        if pending:
            values["pending_reset"] = ", ".join(pending)
        if last_error:
            values["last_error"] = last_error
        if sim.warnings:
            values["warning"] = sim.warnings[-1]
        if stopped is not None:
            values.update({"check": stopped.check, "time": f"{stopped.time:.9g}", "detail": stopped.detail,
                           "particles_involved": ", ".join(str(i) for i in stopped.particles)})
            values["sim_time"] = f"{stopped.time:.9g}"
        return level, message, values

    def _publish_diagnostics(self):
        self._last_diag_wall = time.monotonic()
        if not self.out.ok() or self.sim is None:
            return
        level, message, values = self.diagnostics()
        self.out.publish_diagnostics(self.sim.time, level, message, values, self.settings["frame_id"])
