"""Headless runs: drive a Simulation to its end time and write timeseries.csv, summary.json and snapshots.

Every run writes its error against the scene's reference together with the wall time it cost, whether it ends
normally or the watchdog stops it (summary.json's status: diverged, or water_lost where the scene set
watchdog.max_fluid_lost; it says which check tripped, and the exit status is non-zero).
"""
import csv
import json
import math
import os
import platform
import subprocess
import sys
import time
from pathlib import Path

import numba
import numpy as np

from .checkpoint import write_checkpoint
from .diagnostics import Diverged, Stopped
from .fluid.lost_water import lost_line
from .vtk_snapshots import write_vtk_snapshot
from .simulation import Simulation
from .numerics.tensors import COMPONENT_NAMES


class _Progress:
    """A one-line progress display on a terminal, refreshed by wall-clock interval (never per step)."""

    def __init__(self, end_time, enabled):
        self.end_time = end_time
        self.enabled = enabled
        self.start = time.perf_counter()
        self.last = 0.0

    def update(self, sim, force=False):
        now = time.perf_counter()
        if not self.enabled or (now - self.last < 0.5 and not force):
            return
        self.last = now
        elapsed = now - self.start
        frac = min(sim.time / self.end_time, 1.0)
        rate = sum(step_counts(sim)) / elapsed if elapsed > 0 else 0.0
        eta = elapsed * (1.0 - frac) / frac if frac > 0 else float("nan")
        sys.stderr.write(f"\r  t = {sim.time:.4f} / {self.end_time:g} s  {100 * frac:5.1f} %  "
                         f"{rate:,.0f} steps/s  ETA {eta:6.1f} s ")
        sys.stderr.flush()

    def close(self):
        if self.enabled:
            sys.stderr.write("\n")


def _git_commit():
    try:
        return subprocess.run(["git", "rev-parse", "--short", "HEAD"], cwd=Path(__file__).parent,
                              capture_output=True, text=True, timeout=5).stdout.strip() or None
    except (OSError, subprocess.SubprocessError):
        return None


def machine_info():
    return {"cpus": os.cpu_count(), "numba_threads": numba.get_num_threads(), "python": platform.python_version(),
            "numba": numba.__version__, "numpy": np.__version__, "platform": platform.platform(),
            "commit": _git_commit()}


def write_snapshot(sim, path, snapshot_index=0):
    """Particle state of every phase the scene has, as compressed NumPy arrays (walls, fixed: first snapshot only)."""
    data = {"time": sim.time}
    if sim.solid is not None:
        s = sim.solid
        data.update(solid_position=s.pos, solid_velocity=sim.solid_velocity(), solid_density=s.rho,
                    solid_pressure=s.pressure,
                    solid_stress_deviatoric=s.stress, solid_movable=s.movable,
                    solid_sigma_zz=s.stress[:, 2] - s.pressure,   # the paper's sigma^22 (Fig. 6), Pa
                    stress_components=np.array(COMPONENT_NAMES))
        if s.surface_normal is not None:
            data.update(solid_surface_normal=s.surface_normal)
    if sim.fluid is not None:
        f = sim.fluid
        data.update(fluid_position=f.pos, fluid_velocity=f.vel, fluid_density=f.rho, fluid_pressure=f.pressure,
                    fluid_correction_displacement=f.correction_displacement)
    if sim.walls is not None and snapshot_index == 0:
        data.update(wall_position=sim.walls.pos)
    np.savez_compressed(path, **data)


def make_writable_dir(path):
    """Create `path` (and parents) and prove it takes a file; raises OSError otherwise. The node's out_dir and the
    CLI's --out (which then removes what it made, until the scene is built) call it before the run, so a bad
    directory is found before a long run, not after it."""
    out = Path(path)
    out.mkdir(parents=True, exist_ok=True)
    probe = out / ".write_test"
    probe.write_text("")
    probe.unlink()
    return out


class RunLog:
    """A run's time series and summary, whoever drives it (run_scene here, the ROS node, the validation ladder).

    The driver times what it wants counted: `setup_s` (building the Simulation) and each stretch of stepping
    (`add_stepping`); pauses and publishing are not stepping time. `summary()` gives the error against the
    scene's reference (when the run reached its end) with the wall time it cost; `write()` puts timeseries.csv
    and summary.json into a directory.
    """

    def __init__(self, sim, setup_s):
        self.sim = sim
        self.setup_s = setup_s
        self.stepping_s = 0.0
        self.rows = [sim.sample()]

    @classmethod
    def restored(cls, sim, state):
        """The log of a run continued from a checkpoint (checkpoint.py): its rows and times so far."""
        log = cls.__new__(cls)
        log.sim, log.rows = sim, state["rows"]
        log.setup_s, log.stepping_s = state["setup_s"], state["stepping_s"]
        return log

    def add_sample(self):
        self.rows.append(self.sim.sample())
        return self.rows[-1]

    def add_stepping(self, seconds):
        self.stepping_s += seconds

    def series(self):
        return {k: np.array([r[k] for r in self.rows]) for k in self.rows[0]}

    def summary(self, end_time, status, stopped=None, snapshots=0):
        """status: 'finished' (end time reached: judged against the reference), the watchdog's stop ('diverged',
        'water_lost': `stopped`, the diagnostics.Stopped exception), or how the run was cut short ('interrupted',
        'reset'): not judged."""
        sim, stepping_s = self.sim, self.stepping_s
        solid, water = sim.solid_phase, sim.fluid_phase
        evaluation = {}
        if status == "finished" and sim.builder.evaluate is not None:
            evaluation = sim.builder.evaluate(self.series(), sim.spec.values)
        solid_count = sim.solid.count if sim.solid is not None else 0
        fluid_count = sim.fluid.count if sim.fluid is not None else 0
        solid_steps, fluid_steps = step_counts(sim)
        particle_steps = particle_steps_of(sim)
        fluid_iterations = water.iterations if water is not None else 0
        fluid_particle_iterations = fluid_count * fluid_iterations
        pressure_solve = solid.solver.pressure_solve_stats() if solid is not None else None
        spec = sim.spec
        return {
            "scene": spec.name, "builder": spec.builder, "source": spec.source, "phases": list(sim.phases),
            "particles": {"solid": solid_count,
                          "solid_moving": sim.solid.moving_count if sim.solid is not None else 0,
                          # a mirrored clamp's particles no moving one reaches: the water's walls, or gone
                          **({"clamp_left_out": sim.unreached_clamp} if sim.unreached_clamp else {}),
                          **sim.particle_counts},
            "status": status,
            "end_time_s": end_time, "simulated_time_s": sim.time, "stable": not isinstance(stopped, Diverged),
            "diverged": stopped.as_dict() if isinstance(stopped, Diverged) else None,
            # a stop the scene asked for (watchdog.max_fluid_lost): not a divergence
            **({"stopped": stopped.as_dict()} if stopped is not None and not isinstance(stopped, Diverged) else {}),
            "warnings": sim.warnings, "notes": sim.notes,
            "solid_steps": solid_steps, "outer_steps": sim.outer_steps,
            "solid_dt_s": solid.last_dt if solid is not None else 0.0,
            "neighbour_builds": ((solid.solver.neighbour_builds if solid is not None else 0)
                                 + (water.solver.builds if water is not None else 0)),
            "fluid_steps": fluid_steps, "fluid_dt_s": water.last_dt if water is not None else 0.0,
            "fluid_iterations": fluid_iterations,
            "fluid_capped_steps": water.capped_steps if water is not None else 0,
            "fluid_particles_lost": int(water.lost.sum()) if water is not None else 0,
            **({"fluid_lost": water.lost_water.summary()} if water is not None else {}),
            **({"settling": water.settled} if water is not None and water.settled else {}),
            **({"solid_pressure_solve": pressure_solve} if pressure_solve else {}),
            "fluid_iterations_per_step": fluid_iterations / fluid_steps if fluid_steps else None,
            "fluid_particle_iterations": fluid_particle_iterations,
            "fluid_particle_iterations_per_second": (fluid_particle_iterations / stepping_s
                                                     if stepping_s > 0 and fluid_count else None),
            "wall_time_s": self.setup_s + stepping_s, "setup_time_s": self.setup_s, "stepping_time_s": stepping_s,
            # of it, the solid's steps (with the coupling: its sub-steps); the rest is the fluid's and the outputs'
            **({"solid_stepping_time_s": solid.seconds} if solid_count else {}),
            "particle_steps": particle_steps,
            "particle_steps_per_second": particle_steps / stepping_s if stepping_s > 0 else None,
            "coupling": ({"model": sim.coupling.model, "gamma": sim.coupling.gamma,
                          "surface_particles": sim.coupling.surface_count,
                          "last_substeps": sim.coupling.last_substeps}
                         if sim.coupling is not None else None),
            "snapshots": snapshots, "machine": machine_info(),
            "settings": {k: (list(v) if isinstance(v, tuple) else v) for k, v in spec.values.items()},
            **evaluation,
        }

    def write(self, out_dir, summary):
        out = Path(out_dir)
        out.mkdir(parents=True, exist_ok=True)
        # Each file appears whole or not at all (written aside, then renamed): a node's subscriber or a resumed
        # ladder that sees summary.json reads a complete one.
        partial = out / "timeseries.csv.partial"
        with open(partial, "w", newline="") as fh:
            writer = csv.writer(fh)
            writer.writerow(list(self.rows[0]))
            for r in self.rows:
                writer.writerow([repr(float(v)) for v in r.values()])
        os.replace(partial, out / "timeseries.csv")
        partial = out / "summary.json.partial"
        partial.write_text(json.dumps(_finite_or_null(summary), indent=2) + "\n")
        os.replace(partial, out / "summary.json")


def step_counts(sim):
    """(solid steps, fluid steps) so far; 0 for a phase the scene does not have."""
    return (sim.solid_phase.steps if sim.solid_phase is not None else 0,
            sim.fluid_phase.steps if sim.fluid_phase is not None else 0)


def particle_steps_of(sim):
    """Every solid particle (clamp included) per solid step plus every fluid particle per fluid step, so far."""
    solid_steps, fluid_steps = step_counts(sim)
    solid_count = sim.solid.count if sim.solid is not None else 0
    fluid_count = sim.fluid.count if sim.fluid is not None else 0
    return solid_count * solid_steps + fluid_count * fluid_steps


class Progress:
    """How far a run is and how fast it goes, over the wall time spent stepping only (pauses do not count):
    simulated time, percent of the end time, ETA and particle-steps/s. `add(seconds)` after each stretch of
    stepping; `numbers(end)` and `line(end)` read it."""

    def __init__(self, sim):
        self.sim = sim
        self.start_time = sim.time
        self.start_steps = particle_steps_of(sim)
        self.stepping_s = 0.0

    def add(self, seconds):
        self.stepping_s += seconds

    def numbers(self, end):
        sim, wall = self.sim, self.stepping_s
        done = sim.time - self.start_time
        percent = 100.0 * sim.time / end if end > 0 else 100.0
        eta = wall * max(end - sim.time, 0.0) / done if done > 0 and wall > 0 else None
        rate = (particle_steps_of(sim) - self.start_steps) / wall if wall > 0 else None
        return {"sim_time": sim.time, "end_time": end, "percent": percent, "eta_s": eta,
                "particle_steps_per_second": rate}

    def line(self, end):
        n = self.numbers(end)
        eta = f"{n['eta_s']:.0f} s" if n["eta_s"] is not None else "-"
        rate = f"{n['particle_steps_per_second'] / 1e6:.3g} M" if n["particle_steps_per_second"] else "-"
        return (f"t = {n['sim_time']:.6g} of {n['end_time']:.6g} s ({n['percent']:.1f} %), ETA {eta}, "
                f"{rate} particle-steps/s")


def solid_share_of_stepping(summary):
    """The fraction of a run's stepping time its solid's steps took, where it has a solid and a fluid; else None."""
    solid, stepping = summary.get("solid_stepping_time_s"), summary.get("stepping_time_s")
    if solid is None or not summary.get("fluid_steps") or not stepping:
        return None
    return solid / stepping


def headline(summary):
    """One line for a log: how the run ended, its error against the reference (or its checks), its cost."""
    s = summary
    parts = [f"{s['status']} at t = {s['simulated_time_s']:.6g} s"]
    if s.get("error") is not None:
        parts.append(f"error {100 * s['error']:.2f} % ({s.get('error_metric', 'against the scene reference')})")
    checks = {k[len("check_"):]: v for k, v in s.items() if k.startswith("check_")}
    if checks:
        parts.append("checks " + ", ".join(f"{k} {'yes' if v else 'NO'}" for k, v in checks.items()))
    if s["status"] == "diverged" or s.get("stopped"):
        d = s["diverged"] or s["stopped"]
        parts.append(f"{d['check']}: {d['detail']}")
    lost = lost_line(s.get("fluid_lost"))
    if lost:
        parts.append(lost)
    solid_share = solid_share_of_stepping(s)
    parts.append(f"wall time {s['wall_time_s']:.1f} s (setup {s['setup_time_s']:.1f} s"
                 + (f", the solid's steps {100 * solid_share:.0f} % of the stepping)" if solid_share is not None
                    else ")"))
    if s.get("particle_steps_per_second"):
        parts.append(f"{s['particle_steps_per_second'] / 1e6:.3g} M particle-steps/s")
    return "; ".join(parts)


END_TOLERANCE = 1e-12   # s: a run has reached its end time once sim.time >= end - END_TOLERANCE


class Interrupted(Exception):
    """Raised by a sample hook to stop a run cleanly at an outer-step boundary (the CLI's SIGINT/SIGTERM)."""


class Run:
    """One run of a scene, the loop every driver shares: `run_scene` (the CLI, validation, stability) and the
    node's runner (sph_fsi.runner), so the end-time rule, the time series, the summary and the recorder calls
    live here once.

        run = Run(spec)                   # builds the Simulation (timed as setup)
        run.add_recorder(rec)             # optional: offered every sample, closed by run.close()
        while not run.at_end and run.advance():
            ...
        summary = run.finish("finished")  # or run.stopped.outcome ('diverged', 'water_lost'), "interrupted", ...
        run.close("finished")

    `end_time` None follows the scene's `scene.end_time`, read live (the node can change it); a number fixes it.
    Stepping time (RunLog.add_stepping) is the time spent in `advance()`: the snapshot due before the step, the
    outer step, its sample and the sample hooks (recorders' capture, progress, the CLI's signal check).
    """

    def __init__(self, spec, end_time=None, out_dir=None, snapshots_dir=None, restored=None):
        t0 = time.perf_counter()
        if restored is None:
            self.sim = Simulation(spec)
            self.log = RunLog(self.sim, time.perf_counter() - t0)
        else:   # checkpoint.read_checkpoint's state: the run goes on where it was written
            self.sim = restored["sim"]
            spec = self.sim.spec
            self.log = RunLog.restored(self.sim, restored)
        self.end_time = end_time
        self.out_dir = Path(out_dir) if out_dir else None
        self.stopped = None                     # the watchdog's Stopped (Diverged, WaterLost), once it tripped
        self.hooks = []                         # hook(sim, row) after every sample
        self.recorders = []                     # closed by close()
        self.snapshots_dir = Path(snapshots_dir) if snapshots_dir else None
        self.snapshots = 0
        self._snapshot_dt = spec["output.snapshot_interval"] if snapshots_dir else 0.0
        if self._snapshot_dt > 0:    # a run without snapshots leaves no empty folder for them
            self.snapshots_dir.mkdir(parents=True, exist_ok=True)
        self.next_snapshot = 0.0
        if restored is not None:
            self.snapshots, self.next_snapshot = restored["snapshots"], restored["next_snapshot"]
            self.stopped = restored["stopped"]

    @property
    def end(self):
        return self.end_time if self.end_time is not None else self.sim.spec["scene.end_time"]

    @property
    def at_end(self):
        """The simulated time has reached the end time (the one end-time rule of every driver)."""
        return self.sim.time >= self.end - END_TOLERANCE

    def add_hook(self, hook, now=True):
        """Call hook(sim, row) after every outer step's sample, and at once with the latest row if `now`."""
        if now:
            hook(self.sim, self.log.rows[-1])
        self.hooks.append(hook)

    def add_recorder(self, recorder):
        """A recorder (sph_fsi.recording.Recorder or alike: maybe_record(sim, row), close(sim, status=, detail=)):
        offered the current state now and every sample from now on; closed by close()."""
        self.add_hook(recorder.maybe_record)
        self.recorders.append(recorder)

    def advance(self):
        """One outer step, sampled into the time series and handed to the hooks. False if the watchdog stopped the
        run (`self.stopped`: the state is left as the watchdog found it, unsampled). An exception from a hook ends
        the step (its stepping time still counted) and goes on to the caller."""
        t0 = time.perf_counter()
        try:
            sim = self.sim
            if self._snapshot_dt > 0 and sim.time >= self.next_snapshot - 1e-12:
                self._write_snapshot()
                self.next_snapshot += self._snapshot_dt
            try:
                sim.step()
            except Stopped as exc:
                self.stopped = exc
                return False
            row = self.log.add_sample()
            for hook in self.hooks:
                hook(sim, row)
            return True
        finally:
            self.log.add_stepping(time.perf_counter() - t0)

    def _write_snapshot(self):
        fmt = self.sim.spec["output.snapshot_format"]
        if fmt in ("npz", "both"):
            write_snapshot(self.sim, self.snapshots_dir / f"snapshot_{self.snapshots:05d}.npz", self.snapshots)
        if fmt in ("vtk", "both"):
            write_vtk_snapshot(self.sim, self.snapshots_dir, self.snapshots)
        self.snapshots += 1

    def finish(self, status):
        """The summary of the run as it stands (RunLog.summary), written to out_dir if given (OSError goes on to
        the caller). A finished run with snapshots gets its last snapshot first."""
        if status == "finished" and self._snapshot_dt > 0:
            self._write_snapshot()
        summary = self.log.summary(self.end, status, self.stopped, self.snapshots)
        if self.out_dir:
            self.log.write(self.out_dir, summary)
        return summary

    @property
    def detail(self):
        """How the watchdog stopped the run, one line; None if it did not."""
        d = self.stopped
        return f"{d.check} at t = {d.time:.6g} s: {d.detail}" if d is not None else None

    def close(self, status):
        """Close the recorders (the final state unless diverged, a last /diagnostics saying `status`); returns
        [(recorder, its writer's stats)]. Idempotent."""
        closed = []
        recorders, self.recorders = self.recorders, []
        for rec in recorders:
            closed.append((rec, rec.close(self.sim, status=status, detail=self.detail)))
        return closed


def run_scene(spec, out_dir=None, progress=None, end_time=None, on_sample=None, recorder=None, restart=None,
              checkpoint=None, checkpoint_interval=0.0):
    """Run `spec` to its end time; returns the summary dict (also written to out_dir/summary.json if given).

    on_sample(sim, row) is called with the first row and after every outer step. recorder(sim), if given, makes
    a recorder (see Run.add_recorder) once the scene is built; it is closed at the end with how the run ended
    ('failed' for an unexpected exception). An exception from `on_sample` (the CLI's Ctrl-C: Interrupted) ends
    the run: what was computed is still written, with status 'interrupted', before the exception goes on.

    Checkpoints (checkpoint.py): `restart`, a state read by read_checkpoint, continues that run (spec is then
    ignored: the checkpoint's scene is the run's). With `checkpoint` (a path), one is written every
    `checkpoint_interval` of simulated time (0: none on the way) and when an Interrupted ends the run."""
    if restart is not None:
        spec = restart["sim"].spec
    end = end_time if end_time is not None else spec["scene.end_time"]
    progress = _Progress(end, sys.stderr.isatty() if progress is None else progress)
    out = Path(out_dir) if out_dir else None
    # built and checked before anything is written: a refused scene leaves no output directory
    run = Run(spec, end, out_dir=out, snapshots_dir=out / "snapshots" if out else None, restored=restart)
    if out:
        out.mkdir(parents=True, exist_ok=True)
        for stale in ("summary.json", "timeseries.csv"):   # an earlier run's, never mistaken for this one's
            (out / stale).unlink(missing_ok=True)
    sim = run.sim
    if on_sample:
        run.add_hook(on_sample)
    if checkpoint and checkpoint_interval > 0:
        due = [sim.time + checkpoint_interval]

        def write_when_due(s, _row):
            if s.time >= due[0] - END_TOLERANCE:
                write_checkpoint(run, checkpoint)
                while due[0] <= s.time + END_TOLERANCE:
                    due[0] += checkpoint_interval
        run.add_hook(write_when_due, now=False)
    if recorder:
        run.add_recorder(recorder(sim))
    run.add_hook(lambda s, _row: progress.update(s), now=False)
    status = recorder_status = "interrupted"
    try:
        try:
            while not run.at_end:
                if not run.advance():
                    break
            status = recorder_status = run.stopped.outcome if run.stopped is not None else "finished"
        except Interrupted:
            if checkpoint:    # between outer steps: a state to continue from
                write_checkpoint(run, checkpoint)
            raise
        except KeyboardInterrupt:
            raise
        except BaseException:
            recorder_status = "failed"
            raise
        finally:
            progress.update(sim, force=True)
            progress.close()
            summary = run.finish(status)
    finally:
        run.close(recorder_status)
    return summary


def _finite_or_null(obj):
    """JSON has no NaN: write null instead, so every reader can parse the summary."""
    if isinstance(obj, float):
        return obj if math.isfinite(obj) else None
    if isinstance(obj, dict):
        return {k: _finite_or_null(v) for k, v in obj.items()}
    if isinstance(obj, (list, tuple)):
        return [_finite_or_null(v) for v in obj]
    if isinstance(obj, np.generic):
        return _finite_or_null(obj.item())
    return obj
