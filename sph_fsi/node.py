"""The ROS 2 node `sph_fsi`: runs a scene and publishes it, stamped with simulated time.

    sph_fsi_node [--ros-args -p scene:=cantilever -p solid.young_modulus:=2e6 --params-file FILE]
    python -m sph_fsi [--ros-args ...]

Threads:
- main thread: starts everything, then waits for a signal (SIGINT/SIGTERM) or the end of the run
  (on_end 'exit'); then stops the simulation thread, shuts the executor down and joins both. Exit status 0
  (2: bad startup parameters; 3: the run diverged with on_end 'exit'). A second signal while the current outer
  step finishes exits at once (status 130).
- executor thread: services (~/reset, ~/pause, ~/step) and parameter callbacks. They validate, enqueue a
  command or set a flag under a short lock and answer at once; they never wait for a step.
- simulation thread: owns the Simulation. Builds it, advances it one publish period at a time (whole outer
  steps of output.timeseries_interval), publishes after each period, and takes commands between outer steps.

Parameters: the node's own (scene, end_time, publish_period, realtime_factor, frame_id, qos, on_end) and one per
scene key, named by its dotted key (solid.young_modulus, numerics.spacing, ...), declared from the scene schema
with description, unit and range. Keys that need a rebuild (Param.rebuild, plus scene and qos) are accepted and
take effect at the next ~/reset; the others apply at once. A bad value is refused with a reason naming the key
and the allowed range. Changing `scene` reloads the new scene's own values at the next ~/reset.

Topics exist only for what the scene has (see INTERFACE.md): ~/particles (moving particles of every phase),
~/walls (fixed particles; transient-local, after every build), ~/tip_displacement (a probe named 'tip'),
~/strain_energy (a solid), /clock and /diagnostics (always). Nothing is published from a diverged state.
"""
import math
import os
import signal
import sys
import threading
import time
from collections import deque

EXIT_BAD_INPUT = 2
EXIT_DIVERGED = 3


def _ensure_ament_prefix():
    """ament_index_python needs the venv prefix on AMENT_PREFIX_PATH (the wheels install share/<pkg> there)."""
    prefix = sys.prefix
    if os.path.isdir(os.path.join(prefix, "share", "ament_index")):
        parts = [p for p in os.environ.get("AMENT_PREFIX_PATH", "").split(os.pathsep) if p]
        if prefix not in parts:
            os.environ["AMENT_PREFIX_PATH"] = os.pathsep.join([prefix] + parts)


def main(args=None):
    # Signals first: a Ctrl-C during the (slow) imports below must also end cleanly.
    stop = threading.Event()
    state = {"signal": None}

    def _on_signal(signum, _frame):
        if state["signal"] is not None:
            # A second signal while an outer step (or the first Numba compile) is still finishing: leave now.
            os.write(2, b"sph_fsi_node: second signal: exiting without waiting for the current step\n")
            os._exit(130)
        state["signal"] = signum
        stop.set()

    signal.signal(signal.SIGINT, _on_signal)
    signal.signal(signal.SIGTERM, _on_signal)
    _ensure_ament_prefix()

    import rclpy
    from rclpy.executors import SingleThreadedExecutor
    from rclpy.signals import SignalHandlerOptions

    rclpy.init(args=args, signal_handler_options=SignalHandlerOptions.NO)
    node = executor = spin_thread = None
    spin_stop = threading.Event()
    code = 0
    try:
        try:
            node = SphFsiNode(stop_event=stop)
        except StartupError as exc:
            sys.stderr.write(f"sph_fsi_node: {exc}\n")
            return EXIT_BAD_INPUT
        if stop.is_set():
            return 0
        executor = SingleThreadedExecutor(context=node.context)
        executor.add_node(node)
        spin_thread = threading.Thread(target=_spin, args=(executor, node.context, spin_stop),
                                       name="ros-executor", daemon=True)
        spin_thread.start()
        node.start()
        while not stop.wait(0.2):
            pass
        code = 0 if state["signal"] is not None else node.exit_code
        if state["signal"] is None:
            time.sleep(0.3)   # the run ended by itself: let reliable subscribers take the last frame
    finally:
        # Order matters: the simulation thread publishes, so it stops first; then the executor thread ends its
        # spin_once loop and is joined; only then is the executor shut down and the node destroyed.
        if node is not None:
            node.stop()
        spin_stop.set()
        if spin_thread is not None:
            spin_thread.join()
        if executor is not None:
            executor.shutdown(timeout_sec=5.0)
        if node is not None:
            node.destroy_node()
        rclpy.try_shutdown()
    return code


def _numbered(path, n):
    """The n-th recording file of a path: the path itself, then <stem>_<n><suffix> after each reset."""
    if n == 0:
        return path
    root, ext = os.path.splitext(path)
    return f"{root}_{n}{ext}"


def _spin(executor, context, spin_stop):
    """The executor loop, ended by `spin_stop` (checked every 0.1 s) rather than by shutting the executor down
    under a spinning thread."""
    while not spin_stop.is_set() and context.ok():
        try:
            executor.spin_once(timeout_sec=0.1)
        except Exception as exc:
            if not context.ok() or spin_stop.is_set():
                break   # shutting down: a handle went away mid-wait
            sys.stderr.write(f"sph_fsi_node: executor: {type(exc).__name__}: {exc}\n")


class StartupError(Exception):
    """Bad startup parameters: one line naming the parameter and the allowed values."""


# ---- the node ---------------------------------------------------------------------------------------------
# Imports below are module level for the node class; `main` imports rclpy itself after installing handlers.
import numpy as np  # noqa: E402
from diagnostic_msgs.msg import DiagnosticArray, DiagnosticStatus, KeyValue  # noqa: E402
from geometry_msgs.msg import Vector3, Vector3Stamped  # noqa: E402
from rcl_interfaces.msg import (FloatingPointRange, IntegerRange, ParameterDescriptor,  # noqa: E402
                                ParameterType, SetParametersResult)
from rclpy.node import Node  # noqa: E402
from rclpy.parameter import Parameter  # noqa: E402
from rclpy.qos import (DurabilityPolicy, HistoryPolicy, QoSProfile, ReliabilityPolicy,  # noqa: E402
                       qos_profile_sensor_data)
from rosgraph_msgs.msg import Clock  # noqa: E402
from sensor_msgs.msg import PointCloud2  # noqa: E402
from std_msgs.msg import Float64, Header  # noqa: E402
from std_srvs.srv import SetBool, Trigger  # noqa: E402

from sph_fsi_core.run import RunLog, headline, make_writable_dir  # noqa: E402
from sph_fsi_core.scene import load_scene  # noqa: E402
from sph_fsi_core.schema import Param, SceneError  # noqa: E402
from sph_fsi_core.simulation import Diverged, Simulation  # noqa: E402

from .messages import stamp_from_seconds, structured_to_cloud, walls_to_cloud  # noqa: E402
from .points import (PHASE_CODES, moving_particles, particle_points, topic_plan,  # noqa: E402,F401
                     wall_positions)

# The node's own parameters, described like scene keys (validated with Param.coerce).
NODE_PARAMS = {p.key: p for p in [
    Param("scene", "", "", "Scene: a built-in name or a YAML path ('' = the default scene)", kind="str"),
    Param("end_time", 0.0, "s", "Simulated time at which the run ends (0 = the scene's scene.end_time)",
          low=0.0, high=1.0e3, rebuild=False),
    Param("publish_period", 0.005, "s", "Simulated time between publishes (rounded up to whole outer steps "
          "of output.timeseries_interval)", low=0.0, low_inclusive=False, high=10.0, rebuild=False),
    Param("realtime_factor", 0.0, "1", "Simulated seconds per wall second (0 = as fast as possible)", low=0.0,
          high=1.0e6, rebuild=False),
    Param("frame_id", "map", "", "frame_id of every stamped message", kind="str", rebuild=False),
    Param("qos", "reliable", "", "QoS of the streamed topics (~/walls is always reliable, transient-local)",
          kind="str", choices=("reliable", "sensor_data")),
    Param("on_end", "stay", "", "At end_time: 'stay' (keep serving, report finished) or 'exit' (exit status 0)",
          kind="str", choices=("stay", "exit"), rebuild=False),
    # Recordings (sph_fsi.recording): opened when the simulation is built; each ~/reset closes the files and
    # starts new ones named <stem>_<n><suffix> (n = 1, 2, ...).
    Param("mcap_path", "", "", "Record the node's topics to this MCAP file ('' = no MCAP recording)", kind="str"),
    Param("mcap_compression", "zstd", "", "MCAP chunk compression", kind="str", choices=("zstd", "lz4", "none")),
    Param("rrd_path", "", "", "Record to this Rerun .rrd file ('' = no Rerun recording)", kind="str"),
    Param("rerun_connect", "", "", "Stream live to a Rerun viewer at host:port or rerun+http://host:port/proxy "
          "('' = off)", kind="str"),
    Param("record_interval", 0.005, "s", "Simulated time between recorded frames, independent of publish_period "
          "(whole outer steps; 0 = every outer step)", low=0.0, high=10.0),
    Param("out_dir", "", "", "Write timeseries.csv and summary.json (error against the scene's reference, wall "
          "time) here when the run ends, diverges, is reset or stopped ('' = off; <dir>_<n> after each reset)",
          kind="str"),
]}
RECORDING_PARAMS = ("mcap_path", "mcap_compression", "rrd_path", "rerun_connect", "record_interval", "out_dir")
# Scene keys not exposed as parameters: the builder follows from the scene.
HIDDEN_SCENE_KEYS = {"scene.builder"}
# Parameters rclpy declares itself, and prefixes of ROS-level overrides we leave alone.
FOREIGN_PARAMS = {"use_sim_time", "start_type_description_service"}
FOREIGN_PREFIXES = ("qos_overrides.",)

_DBL_MAX = sys.float_info.max
_INT64 = 2 ** 63 - 1
_ROS_TYPES = {"float": ParameterType.PARAMETER_DOUBLE, "int": ParameterType.PARAMETER_INTEGER,
              "bool": ParameterType.PARAMETER_BOOL, "str": ParameterType.PARAMETER_STRING,
              "vec3": ParameterType.PARAMETER_DOUBLE_ARRAY}


def _steps(sim):
    """Solid plus fluid steps taken so far (the diagnostics' steps/s)."""
    return getattr(sim, "solid_steps", 0) + getattr(sim, "fluid_steps", 0)


def descriptor_for(p, rebuild_note=True):
    """ParameterDescriptor for a schema Param: description with unit and range, ROS range where bounded.

    ROS ranges are inclusive (step 0 = continuous); exclusive bounds are enforced by Param.coerce in the
    callback. dynamic_typing lets 2000000 (an integer) stand for a double; the callback coerces and refuses
    wrong types with a reason of its own.
    """
    unit = f" [{p.unit}]" if p.unit and p.unit != "1" else ""
    when = ("applies at the next ~/reset" if p.rebuild else "applies at once") if rebuild_note else ""
    d = ParameterDescriptor(name=p.key, type=_ROS_TYPES[p.kind],
                            description=f"{p.description}{unit}; {p.range_text()}" + (f"; {when}" if when else ""),
                            additional_constraints=p.range_text(), dynamic_typing=True)
    if p.low is not None or p.high is not None:
        if p.kind == "float":
            d.floating_point_range = [FloatingPointRange(
                from_value=float(p.low) if p.low is not None else -_DBL_MAX,
                to_value=float(p.high) if p.high is not None else _DBL_MAX, step=0.0)]
        elif p.kind == "int":
            d.integer_range = [IntegerRange(from_value=int(p.low) if p.low is not None else -_INT64,
                                            to_value=int(p.high) if p.high is not None else _INT64, step=0)]
    return d


def to_ros_value(value):
    return list(value) if isinstance(value, tuple) else value


def from_ros_value(value):
    """rclpy values -> plain Python (arrays -> lists) for Param.coerce."""
    if value is None or isinstance(value, (bool, int, float, str)):
        return value
    try:
        return [v.item() if hasattr(v, "item") else v for v in value]
    except TypeError:
        return value


_TOPIC_TYPES = {"particles": PointCloud2, "walls": PointCloud2, "tip_displacement": Vector3Stamped,
                "strain_energy": Float64}


class SphFsiNode(Node):
    def __init__(self, stop_event=None, **kwargs):
        super().__init__("sph_fsi", **kwargs)
        self._stop_event = stop_event or threading.Event()
        self.exit_code = 0
        self._tls = threading.local()
        self._cv = threading.Condition()        # guards everything below up to the simulation-thread-only state
        self._commands = deque()
        self._paused = False
        self._stopping = False
        self._finished = False
        self._diverged = None                   # Diverged exception while diverged
        self._pending_keys = set()              # rebuild keys changed since the running simulation was built
        self._pending_scene = None              # new `scene` value, applied at the next reset
        self._pending_qos = None
        self._pending_recording = {}           # recording parameters changed, applied at the next reset
        self._last_error = ""
        self._sim_time = 0.0

        self._declare_all()
        self.add_on_set_parameters_callback(self._on_set_parameters)

        self._pubs = {}
        self._clock_pub = self.create_publisher(Clock, "/clock", QoSProfile(depth=10))
        self._diag_pub = self.create_publisher(DiagnosticArray, "/diagnostics", QoSProfile(depth=10))
        self.create_service(Trigger, "~/reset", self._srv_reset)
        self.create_service(SetBool, "~/pause", self._srv_pause)
        self.create_service(Trigger, "~/step", self._srv_step)

        # simulation-thread-only state
        self.sim = None
        self._recorder = None
        self._recordings = 0                    # recorders opened so far (numbers the files after a reset)
        self._run_log = None                    # the running simulation's RunLog
        self._run_logs = 0                      # runs built so far (numbers out_dir after a reset)
        self._run_log_steps = 0                 # the run's outer steps when its summary was last written
        self._thread = threading.Thread(target=self._run, name="simulation", daemon=True)

    # ---- parameters ---------------------------------------------------------------------------------------
    def _declare_all(self):
        overrides = {k: from_ros_value(p.value) for k, p in getattr(self, "_parameter_overrides", {}).items()}
        node_values = {}
        for key, p in NODE_PARAMS.items():
            value = p.default
            if key in overrides:
                try:
                    value = p.coerce(overrides[key])
                except SceneError as exc:
                    raise StartupError(str(exc)) from None
            node_values[key] = value
        try:
            base = load_scene(node_values["scene"] or None)
        except SceneError as exc:
            raise StartupError(str(exc)) from None
        self._scene_params = {k: p for k, p in base.schema.params.items() if k not in HIDDEN_SCENE_KEYS}
        unknown = [k for k in overrides if k not in NODE_PARAMS and k not in self._scene_params
                   and k not in FOREIGN_PARAMS and not k.startswith(FOREIGN_PREFIXES)]
        for key in unknown:
            try:
                base.schema.check_key(key, set(base.schema.sections()) | {"fluid", "solid", "walls", "coupling"})
                why = f"{key}: not a parameter of this node"
            except SceneError as exc:
                why = str(exc)
            raise StartupError(f"{why} (parameters: {', '.join(NODE_PARAMS)}, and the scene's keys: "
                               f"see `sph-fsi keys {base.name}`)")
        scene_overrides = {}
        for key, p in self._scene_params.items():
            if key in overrides:
                try:
                    scene_overrides[key] = p.coerce(overrides[key])
                except SceneError as exc:
                    raise StartupError(str(exc)) from None
        try:
            spec = base.with_overrides(scene_overrides) if scene_overrides else base
        except SceneError as exc:
            raise StartupError(str(exc)) from None
        self._settings = node_values             # node parameters in effect (qos/scene: as at startup)
        self._desired = spec                     # every accepted scene-key value, live and deferred
        self._first_spec = spec
        for key, p in NODE_PARAMS.items():
            self.declare_parameter(key, to_ros_value(node_values[key]), descriptor_for(p))
        for key, p in self._scene_params.items():
            self.declare_parameter(key, to_ros_value(spec.values[key]), descriptor_for(p))

    def _validate(self, params):
        """(reason if refused else None, plan) for a list of rclpy Parameters. No side effects."""
        node_changes, scene_changes = {}, {}
        for param in params:
            name = param.name
            value = from_ros_value(param.value)
            if name in NODE_PARAMS:
                try:
                    value = NODE_PARAMS[name].coerce(value)
                    if name == "scene":
                        load_scene(value or None)
                except SceneError as exc:
                    msg = str(exc)
                    return (msg if msg.startswith(name) else f"{name} = {value!r}: {msg}"), None
                node_changes[name] = value
            elif name in self._scene_params:
                try:
                    scene_changes[name] = self._scene_params[name].coerce(value)
                except SceneError as exc:
                    return str(exc), None
            elif name in FOREIGN_PARAMS or name.startswith(FOREIGN_PREFIXES):
                continue
            else:
                return f"{name}: not a parameter of this node", None
        candidate = self._desired
        if scene_changes:
            try:
                candidate = self._desired.with_overrides(scene_changes)
            except SceneError as exc:
                return str(exc), None
        return None, (node_changes, scene_changes, candidate)

    def _on_set_parameters(self, params):
        if getattr(self._tls, "bypass", False):
            return SetParametersResult(successful=True)
        with self._cv:
            refused, plan = self._validate(params)
            if refused:
                return SetParametersResult(successful=False, reason=refused)
            node_changes, scene_changes, candidate = plan
            now, later = [], []
            self._desired = candidate
            live = {}
            for key, value in scene_changes.items():
                if self._scene_params[key].rebuild:
                    self._pending_keys.add(key)
                    later.append(key)
                else:
                    live[key] = value
                    now.append(key)
            if live:
                self._commands.append(("apply", live))
            for key, value in node_changes.items():
                if key == "scene":
                    self._pending_scene = value
                    later.append(key)
                elif key == "qos":
                    self._pending_qos = value
                    later.append(key)
                elif key in RECORDING_PARAMS:
                    self._pending_recording[key] = value
                    later.append(key)
                else:
                    self._settings[key] = value
                    now.append(key)
            self._cv.notify_all()
        parts = []
        if now:
            parts.append(f"{', '.join(now)}: applied now")
        if later:
            parts.append(f"{', '.join(later)}: accepted, applies at the next ~/reset")
        if "scene" in node_changes:
            parts.append("the new scene's keys are loaded from it at that reset")
        reason = "; ".join(parts)
        self._tls.reason = reason
        return SetParametersResult(successful=True, reason=reason)

    # rclpy (7.1) replaces a successful callback result by a bare SetParametersResult(successful=True); keep
    # the callback's reason so a caller learns that a change waits for ~/reset.
    def set_parameters_atomically(self, parameter_list):
        self._tls.reason = None
        with self._cv:
            refused, _ = self._validate([p for p in parameter_list if p.name in self._all_param_names()])
        if refused:   # our reason (key, value, allowed range) before rclpy's generic range message
            return SetParametersResult(successful=False, reason=refused)
        result = super().set_parameters_atomically(parameter_list)
        if result.successful and self._tls.reason:
            result.reason = self._tls.reason
        return result

    def set_parameters(self, parameter_list):
        return [self.set_parameters_atomically([p]) for p in parameter_list]

    def _all_param_names(self):
        return set(NODE_PARAMS) | set(self._scene_params)

    def _set_quietly(self, values):
        """Set parameters from the simulation thread without the validation callback (already in effect)."""
        self._tls.bypass = True
        try:
            super().set_parameters([Parameter(k, value=to_ros_value(v)) for k, v in values.items()])
        finally:
            self._tls.bypass = False

    def _sync_scene_parameters(self, spec):
        """After a scene change: parameters for the new scene's keys, with its values; drop the others."""
        new = {k: p for k, p in spec.schema.params.items() if k not in HIDDEN_SCENE_KEYS}
        self._tls.bypass = True
        try:
            for key in [k for k in self._scene_params if k not in new]:
                self.undeclare_parameter(key)
            changed = {}
            for key, p in new.items():
                if self.has_parameter(key):
                    changed[key] = spec.values[key]
                else:
                    self.declare_parameter(key, to_ros_value(spec.values[key]), descriptor_for(p),
                                           ignore_override=True)
            with self._cv:
                self._scene_params = new
            super().set_parameters([Parameter(k, value=to_ros_value(v)) for k, v in changed.items()])
        finally:
            self._tls.bypass = False

    # ---- services: answer at once -------------------------------------------------------------------------
    def _srv_reset(self, _request, response):
        with self._cv:
            self._commands.append(("reset",))
            pending = sorted(self._pending_keys | ({"scene"} if self._pending_scene is not None else set())
                             | ({"qos"} if self._pending_qos is not None else set()) | set(self._pending_recording))
            self._cv.notify_all()
        response.success = True
        response.message = "resetting to t = 0" + (f", applying {', '.join(pending)}" if pending else "")
        return response

    def _srv_pause(self, request, response):
        with self._cv:
            was = self._paused
            self._paused = bool(request.data)
            self._cv.notify_all()
            t = self._sim_time
        response.success = True
        if request.data:
            response.message = f"paused at t = {t:.6g} s" if not was else f"already paused at t = {t:.6g} s"
        else:
            response.message = "resumed" if was else "already running"
        return response

    def _srv_step(self, _request, response):
        self._check_end_time()   # end_time may have been raised a moment ago, before the sim thread looked
        with self._cv:
            if self._diverged is not None:
                response.success, response.message = False, "the run diverged; call ~/reset"
            elif self._finished:
                response.success, response.message = False, ("the run is at its end time; call ~/reset (or raise "
                                                              "end_time)")
            elif not self._paused:
                response.success, response.message = False, "~/step works while paused; call ~/pause true first"
            else:
                self._commands.append(("step",))
                self._cv.notify_all()
                response.success = True
                response.message = f"stepping one publish period from t = {self._sim_time:.6g} s"
        return response

    # ---- lifecycle ----------------------------------------------------------------------------------------
    def start(self):
        self._thread.start()

    def stop(self):
        """Stop the simulation thread (after its current outer step), join it, and close the recordings."""
        with self._cv:
            self._stopping = True
            self._cv.notify_all()
        if self._thread.is_alive():
            self._thread.join()
        self._close_recorder("interrupted")
        self._write_run_log("interrupted")

    def _finish_node(self, code):
        self.exit_code = code
        self._stop_event.set()

    # ---- simulation thread --------------------------------------------------------------------------------
    def _run(self):
        try:
            self._loop()
        except Exception as exc:   # a bug, not a divergence: report it and end the process non-zero
            self.get_logger().error(f"simulation thread failed: {type(exc).__name__}: {exc}")
            import traceback
            traceback.print_exc()
            self._finish_node(1)

    def _loop(self):
        try:
            self._build(self._first_spec)
        except SceneError as exc:
            self.get_logger().error(str(exc))
            self._finish_node(EXIT_BAD_INPUT)
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
            self._check_end_time()
            if self._can_run():
                wait = self._realtime_wait()
                if wait > 0.0:
                    self._wait(wait)
                else:
                    self._advance(interruptible=True)
                continue
            if time.monotonic() - self._last_diag_wall >= 1.0:
                self._publish_diagnostics()
            self._wait(1.0)

    def _wait(self, seconds):
        with self._cv:
            if not self._commands and not self._stopping and (seconds > 0.0):
                self._cv.wait(min(seconds, 1.0))

    def _can_run(self):
        with self._cv:
            return not (self._paused or self._finished or self._diverged is not None or self._stopping)

    def _end_time(self):
        return self._settings["end_time"] or self.sim.spec["scene.end_time"]

    def _check_end_time(self):
        """end_time (or scene.end_time) raised past a finished run's time: it runs on."""
        with self._cv:
            if self._finished and self.sim.time < self._end_time() - 1e-6 * self._outer_dt:
                self._finished = False
                again = True
            else:
                again = False
        if again:
            self.get_logger().info(f"end time raised to {self._end_time():g} s: running on")
            self._publish_diagnostics()

    def _build(self, spec):
        t0 = time.perf_counter()
        sim = Simulation(spec)
        setup_s = time.perf_counter() - t0
        self._close_recorder("reset")
        self._write_run_log("reset")
        self.sim = sim
        self._outer_dt = self.sim.outer_step_duration()
        with self._cv:
            self._finished = False
            self._diverged = None
            self._sim_time = 0.0
        self._rate = 0.0
        self._rate_mark = None
        self._anchor = None
        self._sync_publishers()
        self._publish_walls()
        self._publish_frame()
        self._open_recorder()
        self._run_log = RunLog(sim, setup_s)
        self._run_log_dir = (_numbered(self._settings["out_dir"], self._run_logs) if self._settings["out_dir"]
                             else None)
        if self._run_log_dir:
            try:
                make_writable_dir(self._run_log_dir)
            except OSError as exc:
                why = f"out_dir {self._run_log_dir!r}: not writable ({exc.strerror})"
                if self._run_logs == 0:
                    raise SceneError(f"{why}; allowed: a writable directory") from None
                self.get_logger().error(f"{why}; this run's summary goes to the log only")
                self._run_log_dir = None
        self._run_logs += 1
        self._run_log_steps = 0

    # ---- the run's time series and summary (simulation thread; the last one written by stop()) -------------
    def _write_run_log(self, status, diverged=None):
        """Summary (error against the reference, wall time) to the log and, with out_dir, to disk; once per
        state: not again while the run has not stepped since (a reset or stop after the end or a divergence),
        nor for a run that never stepped. A divergence always writes (it can trip before the step is counted)."""
        log = self._run_log
        if log is None or (diverged is None and log.sim.outer_steps == self._run_log_steps):
            return
        self._run_log_steps = log.sim.outer_steps
        summary = log.summary(self._end_time(), status, diverged)
        where = ""
        if self._run_log_dir:
            try:
                log.write(self._run_log_dir, summary)
                where = f" (written to {self._run_log_dir}/)"
            except OSError as exc:
                where = f" (not written to {self._run_log_dir}/: {exc})"
                with self._cv:
                    self._last_error = f"out_dir: {exc}"
        line = f"run {headline(summary)}{where}"
        if status == "diverged":   # rclpy: one severity per call site
            self.get_logger().error(line)
        else:
            self.get_logger().info(line)

    # ---- recordings (simulation thread; closed by stop() after the thread has ended) ----------------------
    def _open_recorder(self):
        with self._cv:
            self._settings.update(self._pending_recording)
            self._pending_recording = {}
        st = self._settings
        if not (st["mcap_path"] or st["rrd_path"] or st["rerun_connect"]):
            return
        n = self._recordings
        paths = {key: _numbered(st[key], n) if st[key] else None for key in ("mcap_path", "rrd_path")}
        from .recording import Recorder
        try:
            self._recorder = Recorder(self.sim, mcap_path=paths["mcap_path"],
                                      mcap_compression=st["mcap_compression"], rrd_path=paths["rrd_path"],
                                      rerun_connect=st["rerun_connect"] or None, interval=st["record_interval"],
                                      frame_id=st["frame_id"], namespace=self.get_fully_qualified_name(),
                                      log=self.get_logger().warning)
        except (OSError, ValueError) as exc:
            if n == 0:
                raise SceneError(f"recording: {exc}") from None
            self.get_logger().error(f"recording not restarted: {exc}")
            with self._cv:
                self._last_error = f"recording not restarted: {exc}"
            return
        self._recordings += 1
        self._recorder.maybe_record(self.sim)
        self.get_logger().info("recording to " + ", ".join(p for p in [paths["mcap_path"], paths["rrd_path"],
                                                                       st["rerun_connect"]] if p))

    def _close_recorder(self, reason):
        rec, self._recorder = self._recorder, None
        if rec is None:
            return
        with self._cv:
            status = "diverged" if self._diverged is not None else "finished" if self._finished else reason
        stats = rec.close(None if status == "diverged" else self.sim, status=status)
        self.get_logger().info(f"recording closed ({status}): {rec.frames} frames"
                               + (f"; the simulation waited {stats['waits']} times for the recorder"
                                  if stats["waits"] else ""))

    def _sync_publishers(self):
        want = topic_plan(self.sim)
        with self._cv:
            new_qos, self._pending_qos = self._pending_qos, None
        if new_qos is not None:
            self._settings["qos"] = new_qos
            for name in list(self._pubs):   # QoS changed: recreate every streamed topic
                if name != "walls":
                    self.destroy_publisher(self._pubs.pop(name))
        for name in list(self._pubs):
            if name not in want:
                self.destroy_publisher(self._pubs.pop(name))
        stream_qos = qos_profile_sensor_data if self._settings["qos"] == "sensor_data" else QoSProfile(depth=10)
        latched = QoSProfile(depth=1, history=HistoryPolicy.KEEP_LAST, reliability=ReliabilityPolicy.RELIABLE,
                             durability=DurabilityPolicy.TRANSIENT_LOCAL)
        for name in sorted(want - set(self._pubs)):
            self._pubs[name] = self.create_publisher(_TOPIC_TYPES[name], f"~/{name}",
                                                     latched if name == "walls" else stream_qos)

    def _handle(self, cmd):
        kind = cmd[0]
        if kind == "apply":
            try:
                self.sim.apply(cmd[1])
            except SceneError as exc:   # a live value the running state cannot take (e.g. an unstable dt)
                effective = {k: self.sim.spec.values[k] for k in cmd[1]}
                with self._cv:
                    self._desired = self._desired.with_overrides(effective)
                    self._last_error = str(exc)
                self._set_quietly(effective)
                self.get_logger().error(f"{exc}; kept {effective}")
                self._publish_diagnostics()
        elif kind == "reset":
            self._reset()
        elif kind == "step":
            with self._cv:
                ok = self._paused and not self._finished and self._diverged is None
            if ok:
                self._advance(interruptible=False)

    def _reset(self):
        with self._cv:
            scene = self._pending_scene
            self._pending_scene = None
            desired = self._desired
        old = self.sim
        try:
            if scene is not None:
                desired = load_scene(scene or None)
                self._settings["scene"] = scene
            self._build(desired)
        except SceneError as exc:
            with self._cv:
                self._last_error = f"reset refused: {exc}"
            self.get_logger().error(f"reset refused: {exc}")
            self.sim = old
            self._publish_diagnostics()
            return
        with self._cv:
            self._pending_keys.clear()
            self._desired = desired
            self._last_error = ""
        if scene is not None:
            self._sync_scene_parameters(desired)

    def _realtime_wait(self):
        rtf = self._settings["realtime_factor"]
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

    def _advance(self, interruptible):
        """One publish period (whole outer steps), or less at end_time or on an interruption; then publish."""
        sim = self.sim
        n = max(1, math.ceil(self._settings["publish_period"] / self._outer_dt - 1e-9))
        end = self._end_time()
        tol = 1e-6 * self._outer_dt
        if self._rate_mark is None:
            self._rate_mark = (time.monotonic(), _steps(sim))
        done = 0
        while done < n and sim.time < end - tol:
            if interruptible and self._interrupted():
                break
            t0 = time.perf_counter()
            try:
                sim.step()
            except Diverged as exc:
                self._run_log.add_stepping(time.perf_counter() - t0)
                self._on_diverged(exc)
                return
            self._run_log.add_stepping(time.perf_counter() - t0)
            self._run_log.add_sample()
            if self._recorder is not None:
                self._recorder.maybe_record(sim)
            done += 1
            self._take_applies()
        now = time.monotonic()
        if now > self._rate_mark[0]:
            self._rate = (_steps(sim) - self._rate_mark[1]) / (now - self._rate_mark[0])
        self._rate_mark = (now, _steps(sim))
        reached_end = sim.time >= end - tol
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
            self.get_logger().info(f"finished at t = {sim.time:.6g} s")
            self._write_run_log("finished")
            if self._settings["on_end"] == "exit":
                self._finish_node(0)

    def _on_diverged(self, exc):
        with self._cv:
            self._diverged = exc
            self._sim_time = self.sim.time
        self.get_logger().error(str(exc))
        self._write_run_log("diverged", exc)
        self._publish_diagnostics()
        if self._settings["on_end"] == "exit":
            self._finish_node(EXIT_DIVERGED)

    # ---- publishing (simulation thread only) --------------------------------------------------------------
    def _ok(self):
        return self.context.ok()

    def _header(self, t):
        return Header(stamp=stamp_from_seconds(t), frame_id=self._settings["frame_id"])

    def _publish_walls(self):
        pub = self._pubs.get("walls")
        if pub is None or not self._ok():
            return
        pub.publish(walls_to_cloud(wall_positions(self.sim), stamp_from_seconds(self.sim.time),
                                   self._settings["frame_id"]))

    def _publish_frame(self):
        """Particles, probes and energies at the current simulated time, then /clock and /diagnostics."""
        if not self._ok():
            return
        sim = self.sim
        header = self._header(sim.time)
        try:
            pub = self._pubs.get("particles")
            if pub is not None:
                pub.publish(structured_to_cloud(particle_points(sim), header.stamp, header.frame_id))
            pub = self._pubs.get("tip_displacement")
            if pub is not None:
                d = sim.probe_displacements()["tip"]
                pub.publish(Vector3Stamped(header=header, vector=Vector3(x=float(d[0]), y=float(d[1]),
                                                                         z=float(d[2]))))
            pub = self._pubs.get("strain_energy")
            if pub is not None:
                pub.publish(Float64(data=float(sim.energies()["strain_energy"])))
            self._clock_pub.publish(Clock(clock=header.stamp))
        except Exception:
            if self._ok():
                raise
            return   # shut down during the publish
        self._publish_diagnostics()

    def _status(self):
        with self._cv:
            if self._diverged is not None:
                return DiagnosticStatus.ERROR, "diverged"
            if self._finished:
                return DiagnosticStatus.OK, "finished"
            if self._paused:
                return DiagnosticStatus.OK, "paused"
            level = DiagnosticStatus.WARN if self._last_error else DiagnosticStatus.OK
            return level, "running"

    def _publish_diagnostics(self):
        self._last_diag_wall = time.monotonic()
        if not self._ok() or self.sim is None:
            return
        sim = self.sim
        level, message = self._status()
        running = message == "running"
        values = {"scene": sim.spec.name, "sim_time": f"{sim.time:.9g}", "end_time": f"{self._end_time():.9g}",
                  "steps_per_second": f"{self._rate if running else 0.0:.6g}", "particles": str(sim.particle_count),
                  "moving_particles": str(sum(len(p[1]) for p in moving_particles(sim))),
                  "solid_steps": str(getattr(sim, "solid_steps", 0)),
                  "solid_dt": f"{getattr(sim, 'last_solid_dt', 0.0):.6g}"}
        if getattr(sim, "fluid", None) is not None:   # the density correction's last step
            values.update(iterations=f"{sim.last_density_iterations:d}",
                          density_error=f"{sim.last_density_error:.6g}", fluid_steps=str(sim.fluid_steps),
                          fluid_dt=f"{sim.last_fluid_dt:.6g}", capped_steps=str(sim.fluid_capped_steps))
        with self._cv:
            pending = sorted(self._pending_keys | ({"scene"} if self._pending_scene is not None else set())
                             | ({"qos"} if self._pending_qos is not None else set()) | set(self._pending_recording))
            diverged = self._diverged
            last_error = self._last_error
        if pending:
            values["pending_reset"] = ", ".join(pending)
        if last_error:
            values["last_error"] = last_error
        if sim.warnings:
            values["warning"] = sim.warnings[-1]
        if diverged is not None:
            values.update({"check": diverged.check, "time": f"{diverged.time:.9g}", "detail": diverged.detail,
                           "particles_involved": ", ".join(str(i) for i in diverged.particles)})
            values["sim_time"] = f"{diverged.time:.9g}"
        status = DiagnosticStatus(level=level, name="sph_fsi", message=message, hardware_id="sph_fsi",
                                  values=[KeyValue(key=k, value=v) for k, v in values.items()])
        msg = DiagnosticArray(header=self._header(sim.time), status=[status])
        try:
            self._diag_pub.publish(msg)
        except Exception:
            if self._ok():
                raise


if __name__ == "__main__":
    sys.exit(main())
