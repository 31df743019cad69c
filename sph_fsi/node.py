"""The ROS 2 node `sph_fsi`: runs a scene and publishes it, stamped with simulated time. This module wires the
parts together; each has its own module:

- sph_fsi.parameters: the node's parameters table, scene keys as parameters, descriptors, value checks;
- sph_fsi.runner: the simulation thread (pause, step, reset, end time, divergence, summaries, recordings),
  ROS-free;
- sph_fsi.publishing: the topics and their messages;
- here: the rclpy Node (parameters declared, parameter callbacks, services) and `main`.

    sph_fsi_node [--ros-args -p scene:=cantilever -p solid.young_modulus:=2e6 --params-file FILE]
    python -m sph_fsi [--ros-args ...]

Threads:
- main thread: starts everything, then waits for a signal (SIGINT/SIGTERM) or the end of the run
  (on_end 'exit'); then stops the simulation thread, shuts the executor down and joins both. Exit status 0
  (2: bad startup parameters; 3: the run diverged with on_end 'exit'; 4: more water left the domain than the
  scene's watchdog.max_fluid_lost allows, with on_end 'exit'). A second signal while the current outer step
  finishes exits at once (status 130).
- executor thread: services (~/reset, ~/pause, ~/step, ~/write_checkpoint) and parameter callbacks. They validate,
  hand the runner a command or a flag under its short lock and answer at once; they never wait for a step, except
  ~/write_checkpoint, which waits up to 5 s for the checkpoint to be written between two outer steps.
- simulation thread (sph_fsi.runner): owns the simulation. Builds it, advances it one publish period at a time
  (whole outer steps of output.timeseries_interval), publishes after each period, and takes commands between
  outer steps.

Parameters: the node's own (scene, end_time, publish_period, realtime_factor, frame_id, qos, on_end, the
recording ones, out_dir) and one per scene key, named by its dotted key (solid.young_modulus, numerics.spacing,
...), declared from the scene schema with description, unit and range. Keys that need a rebuild (Param.rebuild,
plus scene, qos and the recording ones) are accepted and take effect at the next ~/reset; the others apply at
once. A bad value is refused with a reason naming the key and the allowed range. Changing `scene` reloads the new
scene's own values at the next ~/reset.

Topics exist only for what the scene has (sph_fsi.publishing, README.md "ROS 2 node"): ~/particles (moving
particles of every phase), ~/walls (fixed particles; transient-local, after every build), ~/tip_displacement (a
probe named 'tip'), ~/strain_energy (a solid), ~/probes/<name>/<quantity> (one per quantity of each of the
scene's probes), ~/parts/<name>/pose and /wrench (a wall driven by commands, which it takes on ~/parts/<name>/pose_cmd
and /twist_cmd), /clock and /diagnostics (always). Nothing is published from a diverged state.
"""
import os
import signal
import sys
import threading
import time

from .ament import ensure_ament_prefix
from .parameters import StartupError
from .runner import EXIT_BAD_INPUT, EXIT_DIVERGED, EXIT_WATER_LOST  # noqa: F401  (its exit statuses)


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
    ensure_ament_prefix()

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


# ---- the node ---------------------------------------------------------------------------------------------
# Imports below are module level for the node class; `main` imports rclpy itself after installing handlers.
from rcl_interfaces.msg import SetParametersResult  # noqa: E402
from rclpy.node import Node  # noqa: E402
from rclpy.parameter import Parameter  # noqa: E402
from std_srvs.srv import SetBool, Trigger  # noqa: E402

from .parameters import (NODE_PARAMS, check_changes, descriptor_for, from_ros_value,  # noqa: E402
                         parameter_overrides, scene_parameters, startup_values, to_ros_value)
from .publishing import Publishing  # noqa: E402
from .runner import Runner  # noqa: E402


class SphFsiNode(Node):
    def __init__(self, stop_event=None, **kwargs):
        super().__init__("sph_fsi", **kwargs)
        self._stop_event = stop_event or threading.Event()
        self._tls = threading.local()
        node_values, spec, self._scene_params = startup_values(parameter_overrides(self))
        for key, p in NODE_PARAMS.items():
            self.declare_parameter(key, to_ros_value(node_values[key]), descriptor_for(p))
        for key, p in self._scene_params.items():
            self.declare_parameter(key, to_ros_value(spec.values[key]), descriptor_for(p))
        self.publishing = Publishing(self)
        self.runner = Runner(spec, node_values, out=self, log=self.get_logger(),
                             namespace=self.get_fully_qualified_name())
        self.publishing.on_command = self.runner.part_command
        self.add_on_set_parameters_callback(self._on_set_parameters)
        self.create_service(Trigger, "~/reset", self._srv_reset)
        self.create_service(SetBool, "~/pause", self._srv_pause)
        self.create_service(Trigger, "~/step", self._srv_step)
        self.create_service(Trigger, "~/write_checkpoint", self._srv_write_checkpoint)

    @property
    def exit_code(self):
        return self.runner.exit_code

    @property
    def sim(self):
        return self.runner.sim

    # ---- lifecycle ----------------------------------------------------------------------------------------
    def start(self):
        self.runner.start()

    def stop(self):
        """Stop the simulation thread (after its current outer step), join it, and close the recordings."""
        self.runner.stop()

    # ---- the runner's outputs (simulation thread) -----------------------------------------------------------
    def ok(self):
        return self.publishing.ok()

    def sync_topics(self, sim, qos):
        self.publishing.sync_topics(sim, qos)

    def publish_walls(self, sim, frame_id):
        self.publishing.publish_walls(sim, frame_id)

    def publish_frame(self, sim, frame_id):
        return self.publishing.publish_frame(sim, frame_id)

    def publish_diagnostics(self, t, level, message, values, frame_id):
        self.publishing.publish_diagnostics(t, level, message, values, frame_id)

    def ended(self, _code):
        self._stop_event.set()

    def restore_parameters(self, values):
        """Set parameters from the simulation thread without the validation callback (already in effect)."""
        self._tls.bypass = True
        try:
            super().set_parameters([Parameter(k, value=to_ros_value(v)) for k, v in values.items()])
        finally:
            self._tls.bypass = False

    def scene_changed(self, spec):
        """After a scene change: parameters for the new scene's keys, with its values; drop the others."""
        new = scene_parameters(spec)
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
            with self.runner.lock:
                self._scene_params = new
            super().set_parameters([Parameter(k, value=to_ros_value(v)) for k, v in changed.items()])
        finally:
            self._tls.bypass = False

    # ---- parameters ---------------------------------------------------------------------------------------
    def _check(self, params):
        """(reason if refused else None, plan) for rclpy Parameters; call with the runner's lock held."""
        return check_changes([(p.name, from_ros_value(p.value)) for p in params], self._scene_params,
                             self.runner.desired)

    def _on_set_parameters(self, params):
        if getattr(self._tls, "bypass", False):
            return SetParametersResult(successful=True)
        with self.runner.lock:
            refused, plan = self._check(params)
            if refused:
                return SetParametersResult(successful=False, reason=refused)
            node_changes, scene_changes, candidate = plan
            rebuild = {k for k in scene_changes if self._scene_params[k].rebuild}
            now, later = self.runner.change(node_changes, scene_changes, candidate, rebuild)
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
        with self.runner.lock:
            ours = set(NODE_PARAMS) | set(self._scene_params)
            refused, _ = self._check([p for p in parameter_list if p.name in ours])
        if refused:   # our reason (key, value, allowed range) before rclpy's generic range message
            return SetParametersResult(successful=False, reason=refused)
        result = super().set_parameters_atomically(parameter_list)
        if result.successful and self._tls.reason:
            result.reason = self._tls.reason
        return result

    def set_parameters(self, parameter_list):
        return [self.set_parameters_atomically([p]) for p in parameter_list]

    # ---- services: answer at once -------------------------------------------------------------------------
    def _srv_reset(self, _request, response):
        pending = self.runner.request_reset()
        response.success = True
        response.message = "resetting to t = 0" + (f", applying {', '.join(pending)}" if pending else "")
        return response

    def _srv_pause(self, request, response):
        was, t = self.runner.pause(request.data)
        response.success = True
        if request.data:
            response.message = f"paused at t = {t:.6g} s" if not was else f"already paused at t = {t:.6g} s"
        else:
            response.message = "resumed" if was else "already running"
        return response

    def _srv_step(self, _request, response):
        response.success, response.message = self.runner.request_step()
        return response

    def _srv_write_checkpoint(self, _request, response):
        """Between the next two outer steps; answers once written (or after 5 s, saying it is queued)."""
        response.success, response.message = self.runner.request_checkpoint()
        return response


if __name__ == "__main__":
    sys.exit(main())
