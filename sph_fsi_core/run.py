"""Headless runs: drive a Simulation to its end time and write timeseries.csv, summary.json and snapshots.

Every run writes its error against the scene's reference together with the wall time it cost, whether it ends
normally or diverges (then summary.json says which check tripped, and the exit status is non-zero).
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

from .diagnostics import Diverged
from .simulation import Simulation
from .tensors import COMPONENT_NAMES


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
        rate = (sim.solid_steps + sim.fluid_steps) / elapsed if elapsed > 0 else 0.0
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
        data.update(solid_position=s.pos, solid_velocity=s.vel, solid_density=s.rho, solid_pressure=s.pressure,
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


def run_scene(spec, out_dir=None, progress=None, end_time=None, on_sample=None):
    """Run `spec` to its end time; returns the summary dict (also written to out_dir/summary.json if given)."""
    end = end_time if end_time is not None else spec["scene.end_time"]
    progress = _Progress(end, sys.stderr.isatty() if progress is None else progress)
    out = Path(out_dir) if out_dir else None
    if out:
        out.mkdir(parents=True, exist_ok=True)
        (out / "snapshots").mkdir(exist_ok=True)
    t0 = time.perf_counter()
    sim = Simulation(spec)
    setup_s = time.perf_counter() - t0
    rows = [sim.sample()]
    if on_sample:
        on_sample(sim, rows[-1])
    snap_dt = spec["output.snapshot_interval"]
    next_snap, snap_count = 0.0, 0
    diverged = None
    t1 = time.perf_counter()
    try:
        while sim.time < end - 1e-12:
            if out and snap_dt > 0 and sim.time >= next_snap - 1e-12:
                write_snapshot(sim, out / "snapshots" / f"snapshot_{snap_count:05d}.npz", snap_count)
                snap_count += 1
                next_snap += snap_dt
            sim.step()
            rows.append(sim.sample())
            if on_sample:
                on_sample(sim, rows[-1])
            progress.update(sim)
    except Diverged as exc:
        diverged = exc
    finally:
        progress.update(sim, force=True)
        progress.close()
    stepping_s = time.perf_counter() - t1
    if out and snap_dt > 0 and diverged is None:
        write_snapshot(sim, out / "snapshots" / f"snapshot_{snap_count:05d}.npz", snap_count)
        snap_count += 1
    series = {k: np.array([r[k] for r in rows]) for k in rows[0]}
    evaluation = {}
    if diverged is None and hasattr(sim.builder, "evaluate"):
        evaluation = sim.builder.evaluate(series, spec.values)
    solid_count = sim.solid.count if sim.solid is not None else 0
    fluid_count = sim.fluid.count if sim.fluid is not None else 0
    particle_steps = solid_count * sim.solid_steps + fluid_count * sim.fluid_steps
    fluid_particle_iterations = fluid_count * sim.fluid_iterations
    fluid_builds = sim.fluid_solver.builds if sim.fluid_solver is not None else 0
    summary = {
        "scene": spec.name, "builder": spec.builder, "source": spec.source, "phases": list(sim.phases),
        "particles": {"solid": solid_count,
                      "solid_moving": sim.solid.moving_count if sim.solid is not None else 0,
                      **sim.particle_counts},
        "end_time_s": end, "simulated_time_s": sim.time, "stable": diverged is None,
        "diverged": diverged.as_dict() if diverged else None, "warnings": sim.warnings,
        "solid_steps": sim.solid_steps, "outer_steps": sim.outer_steps, "solid_dt_s": sim.last_solid_dt,
        "neighbour_builds": sim.neighbour_builds + fluid_builds,
        "fluid_steps": sim.fluid_steps, "fluid_dt_s": sim.last_fluid_dt,
        "fluid_iterations": sim.fluid_iterations, "fluid_capped_steps": sim.fluid_capped_steps,
        "fluid_iterations_per_step": sim.fluid_iterations / sim.fluid_steps if sim.fluid_steps else None,
        "fluid_particle_iterations": fluid_particle_iterations,
        "fluid_particle_iterations_per_second": (fluid_particle_iterations / stepping_s
                                                 if stepping_s > 0 and fluid_count else None),
        "wall_time_s": setup_s + stepping_s, "setup_time_s": setup_s, "stepping_time_s": stepping_s,
        "particle_steps": particle_steps,
        "particle_steps_per_second": particle_steps / stepping_s if stepping_s > 0 else None,
        "coupling": ({"model": sim.coupling.model, "gamma": sim.coupling.gamma,
                      "surface_particles": sim.coupling.surface_count,
                      "last_substeps": sim.coupling.last_substeps} if getattr(sim, "coupling", None) else None),
        "snapshots": snap_count, "machine": machine_info(),
        "settings": {k: (list(v) if isinstance(v, tuple) else v) for k, v in spec.values.items()},
        **evaluation,
    }
    if out:
        with open(out / "timeseries.csv", "w", newline="") as fh:
            writer = csv.writer(fh)
            writer.writerow(list(series))
            for r in rows:
                writer.writerow([repr(float(v)) for v in r.values()])
        (out / "summary.json").write_text(json.dumps(_finite_or_null(summary), indent=2) + "\n")
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
