"""Recordings of a run, written off the simulation thread: MCAP (ROS 2 topics) and Rerun (.rrd / live viewer).

    rec = Recorder(sim, mcap_path="run.mcap", rrd_path="run.rrd", interval=0.005)
    ... after each sim.step(): rec.maybe_record(sim)
    rec.close(sim, status="finished")        # on every exit path (try/finally)

`Recorder` captures a frame (copies of the moving particles' state, probes, energies) whenever the simulated
time reaches the next multiple of `interval` (whole outer steps: a frame is taken at the first outer step at or
past it; interval 0 records every outer step), and hands it to a BackgroundWriter whose thread packs, encodes,
compresses and writes it. The recording interval is independent of the node's publish period.
`close()` records the final state (unless the run diverged), appends a last /diagnostics saying how the run ended,
and waits until both files are complete.
"""
import time

from sph_fsi.points import topic_plan
from sph_fsi_core.run import step_counts

from .frame import Final, capture, capture_static
from .writer import BackgroundWriter

__all__ = ["Recorder", "COMPRESSIONS", "DEFAULT_INTERVAL"]

COMPRESSIONS = ("zstd", "lz4", "none")
DEFAULT_INTERVAL = 0.005   # s of simulated time, the node's default publish period


class Recorder:
    def __init__(self, sim, *, mcap_path=None, mcap_compression="zstd", rrd_path=None, rerun_connect=None,
                 interval=DEFAULT_INTERVAL, frame_id="map", namespace="/sph_fsi", max_queue=8, log=None,
                 rerun_process=False):
        if interval < 0:
            raise ValueError(f"record interval {interval:g} s: allowed: >= 0 s (0 = every outer step)")
        sinks = []
        try:
            if mcap_path:
                from .mcap_sink import McapSink
                sinks.append(McapSink(mcap_path, topic_plan(sim), compression=mcap_compression,
                                      frame_id=frame_id, namespace=namespace))
            if rrd_path or rerun_connect:
                # a process that opens many recordings (the node, one per reset) keeps each Rerun stream in a
                # child process: rerun-sdk keeps native memory for every stream it created (rerun_process.py)
                if rerun_process:
                    from .rerun_process import RerunProcessSink as RerunSink
                else:
                    from .rerun_sink import RerunSink
                sinks.append(RerunSink(rrd_path=rrd_path, connect=rerun_connect))
        except BaseException:
            for s in sinks:
                s.close()
            raise
        self.sinks = list(sinks)
        self.interval = float(interval)
        self.frames = 0
        self.last_time = None
        self._closed = False
        self._next = float(sim.time)
        self._tol = 1e-6 * (self.interval or 1e-6)
        self._wall0 = time.perf_counter()
        self._steps0 = step_counts(sim)[0]
        self._commands_seen = 0          # the boundary's applied commands already recorded
        self.writer = BackgroundWriter(sinks, max_queue=max_queue, log=log)
        if sinks:
            self.writer.submit(capture_static(sim))

    @property
    def active(self):
        return bool(self.sinks)

    def maybe_record(self, sim, row=None):
        """Record a frame if the simulated time reached the next recording time; True if it did."""
        if not self.sinks or sim.time + self._tol < self._next:
            return False
        self.record(sim, row)
        return True

    def record(self, sim, row=None, status="running"):
        frame = capture(sim, row, self._diagnostics(sim), commands_from=self._commands_seen)
        self._commands_seen += len(frame.commands)
        frame.status = status
        self.writer.submit(frame)
        self.frames += 1
        self.last_time = float(sim.time)
        if self.interval > 0:
            k = int((sim.time + self._tol) // self.interval) + 1
            self._next = k * self.interval
        else:
            self._next = sim.time

    def _diagnostics(self, sim):
        elapsed = time.perf_counter() - self._wall0
        steps = step_counts(sim)[0]
        solid, water = sim.solid_phase, sim.fluid_phase
        values = {"scene": sim.spec.name, "sim_time": f"{sim.time:.9g}",
                  "steps_per_second": f"{(steps - self._steps0) / elapsed if elapsed > 0 else 0.0:.6g}",
                  "particles": str(sim.particle_count), "solid_steps": str(steps),
                  "solid_dt": f"{solid.last_dt if solid is not None else 0.0:.6g}"}
        if water is not None:
            values.update(iterations=f"{water.last_iterations:.6g}", density_error=f"{water.last_error_max:.6g}")
        return values

    def close(self, sim=None, status="finished", detail=None, timeout=None):
        """Record the final state (if new and not diverged), a last /diagnostics with `status`, and close the
        files. Returns the writer's stats. Idempotent."""
        if self._closed:
            return self.writer.stats()
        self._closed = True
        try:
            if self.sinks:
                if sim is not None and status != "diverged" and (
                        self.last_time is None or sim.time > self.last_time + self._tol):
                    self.record(sim, status=status)
                values = self._diagnostics(sim) if sim is not None else {}
                if detail:
                    values["detail"] = detail
                self.writer.submit(Final(time=float(sim.time) if sim is not None else (self.last_time or 0.0),
                                         status=status, diagnostics=values))
        finally:
            stats = self.writer.close(timeout)
        return stats
