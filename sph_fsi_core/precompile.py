"""Compile a coupled scene's kernels in two processes at once when Numba's on-disk cache is cold.

A cold run of the paper's gate compiles for about two minutes in one process (docs/performance/BENCH.md, "Compile
time"): about 60 % of it the solid's passes and 40 % the fluid's, which share nothing but the neighbour search, the
coupling a few per cent. Numba keeps each compiled function in its cache whichever process compiled it, and a
function compiles once per argument types, not per value. So two processes on two cores fill the cache with both
halves at once, and the run then compiles only the coupling:
- the solid's part compiles the scheme's driver (the leapfrog and every pass it calls: about half of all the
  compiling) for the argument types a run of the small beam passes it, from the beam's arrays as allocated
  (scenes.build_scene and the solid's phase, not started), running no kernel (the settings that select compiled
  code: the scheme's keys and the artificial stress's exponent, SOLID_CODE_KEYS);
- the fluid's part takes a step of the small dam break (the same fluid passes: a slab periodic along y), then a step
  of the same small beam: its neighbour list and fit (the solid's build), whose driver the other part has cached by
  then. Split so, the two parts take about the same time (each alone about 45 s on this host).

`python -m sph_fsi_core.precompile TASKS_JSON` is one such process: [[how, scene, {key: value}], ...] in order, `how`
"driver" (compile_driver) or "step" (warm_up).

compile_scene does all of a scene's compiling ahead of its run: the two parts so, then the rest (the coupling, the
water's settling) by building the scene itself and taking one outer step. `sph-fsi compile` calls it, and `make
install` with the main job, so that the first `make run` after an install starts stepping at once.
"""
import json
import os
import subprocess
import sys
import time

from typing import NamedTuple

from .jit_cache import fitted_solid, kernels_cached
from .solid.schemes import SCHEME_KEYS

# The keys whose values select which compiled code the solid runs (solid/stepper.solid_drivers, pair_variant).
SOLID_CODE_KEYS = SCHEME_KEYS + ("solid.artificial_stress_exponent",)
SOLID_WARM_UP_SCENE = "cantilever"   # 4 x 6 x 40 particles: a step takes well under a second once compiled
FLUID_WARM_UP_SCENE = "dam_break"    # its fluid and walls as the coupled scenes': a slab periodic along y
WARM_UP_TIMEOUT_S = 1800.0
# SPH_FSI_PARALLEL_COMPILE=0 in the environment: compile in the run's own process only (a shared or busy host)
SWITCH_ENV = "SPH_FSI_PARALLEL_COMPILE"


class Part(NamedTuple):
    """One compiling process: the half of the kernels it is for ("solid" or "fluid", the cache's test) and its
    tasks in order, each (how, scene, {key: value}) with `how` "driver" (compile_driver) or "step" (warm_up)."""
    half: str
    tasks: list


def warm_up_parts(spec):
    """The compiling processes for a scene (scene.SceneSpec), as Parts (the module docstring); empty unless the
    scene has both a solid and a fluid (one half alone compiles no faster in a process of its own)."""
    if not ("solid" in spec.phases and "fluid" in spec.phases):
        return []
    beam = (SOLID_WARM_UP_SCENE, {key: spec[key] for key in SOLID_CODE_KEYS})
    return [Part("solid", [("driver",) + beam]), Part("fluid", [("step", FLUID_WARM_UP_SCENE, {}), ("step",) + beam])]


def uncached_parts(spec):
    """warm_up_parts whose half of the kernels is not in the cache yet (its entry kernel: jit_cache.py)."""
    return [part for part in warm_up_parts(spec) if kernels_cached((part.half,), fitted_solid(spec)) is not True]


def compile_in_parallel(spec, cpus=None, parts=None, tick=None, tick_interval_s=15.0):
    """Run the scene's warm-up parts (`parts`, by default uncached_parts) in processes of their own, all at once, each
    on one Numba thread; returns (seconds, failures: one line per part that did not finish), or None when there is
    nothing to run in parallel (a scene with one phase, one half already cached, a single CPU, or
    SPH_FSI_PARALLEL_COMPILE=0). A failed part costs only time: the run compiles what it left out itself.
    `tick(seconds)`, if given, is called every `tick_interval_s` of waiting (a progress line)."""
    parts = uncached_parts(spec) if parts is None else parts
    cpus = os.cpu_count() if cpus is None else cpus
    if len(parts) < 2 or (cpus or 1) < 2 or os.environ.get(SWITCH_ENV, "1") == "0":
        return None
    env = dict(os.environ, NUMBA_NUM_THREADS="1")
    started = time.perf_counter()
    procs = [(f"the {part.half}'s part", subprocess.Popen(
        [sys.executable, "-m", "sph_fsi_core.precompile", json.dumps(part.tasks)], env=env,
        stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)) for part in parts]
    failures = []
    deadline = started + WARM_UP_TIMEOUT_S
    try:
        for name, proc in procs:
            err = _wait(proc, deadline, tick, tick_interval_s, started)
            if err is None:
                failures.append(f"{name}: still compiling after {WARM_UP_TIMEOUT_S:.0f} s, stopped")
            elif proc.returncode != 0:
                last = (err.strip().splitlines() or ["no message"])[-1]
                failures.append(f"{name}: exit status {proc.returncode}: {last}")
    finally:   # stopped (a signal, an error): no process is left compiling behind the run
        for _, proc in procs:
            if proc.poll() is None:
                proc.kill()
                proc.wait()
    return time.perf_counter() - started, failures


def _wait(proc, deadline, tick, tick_interval_s, started):
    """proc's stderr once it has ended, or None if it was still running at `deadline` (then it is killed); calls
    tick(seconds since `started`) every tick_interval_s of waiting."""
    while True:
        left = deadline - time.perf_counter()
        try:
            return proc.communicate(timeout=max(min(left, tick_interval_s) if tick else left, 0.01))[1]
        except subprocess.TimeoutExpired:
            if time.perf_counter() >= deadline:
                proc.kill()
                proc.communicate()
                return None
            if tick:
                tick(time.perf_counter() - started)


def compile_cold_scene(spec, say, warn, tick=None, tick_interval_s=15.0,
                       then="the run compiles the rest (the coupling)", instead="the run compiles its part itself"):
    """compile_in_parallel, saying what it did: `say(line)` how long it took and `then` (what comes next), `warn(line)`
    each part that failed and `instead` (who compiles it); `tick`: as compile_in_parallel's."""
    done = compile_in_parallel(spec, tick=tick, tick_interval_s=tick_interval_s)
    if done is None:
        return
    seconds, failures = done
    say(f"compiled the solid's and the fluid's kernels in two processes at once in {seconds:.0f} s; {then}")
    for failure in failures:
        warn(f"a compiling process did not finish ({failure}); {instead}")


def compile_scene(spec, say, warn, tick_interval_s=15.0):
    """Compile everything a run of `spec` (scene.SceneSpec) calls, now, before the run: its solid's and fluid's
    halves in two processes at once (compile_cold_scene; only those not cached yet), then the rest (the coupling,
    the water's settling) by building the scene itself and taking one outer step in this process. `say(line)`:
    progress (a line every tick_interval_s while the two processes work); `warn(line)`: a part that failed (this
    process then compiles it). Returns the seconds it took."""
    started = time.perf_counter()
    compile_cold_scene(spec, say, warn, tick=lambda t: say(f"compiling ... {t:.0f} s"),
                       tick_interval_s=tick_interval_s, then=f"now the rest, in one outer step of '{spec.name}'",
                       instead="compiling its part here")
    from .simulation import Simulation
    Simulation(spec).step()
    return time.perf_counter() - started


def warm_up(scene, overrides):
    """Build `scene` with `overrides` and take one outer step: every kernel that step calls is compiled and cached."""
    from .scene import load_scene
    from .simulation import Simulation
    Simulation(load_scene(scene, list(overrides.items()))).step()


def compile_driver(scene, overrides):
    """Compile (and cache) the solid scheme's driver of `scene` with `overrides`, and so every pass it calls, for the
    argument types a run passes it (SolidSolver.leapfrog_arguments of its arrays as allocated), running no kernel;
    returns the signature."""
    import numba
    from .scene import load_scene
    from .schema import solid_smoothing_ratio
    from .scenes import build_scene
    from .solid.phase import SolidPhase
    from .solid.stepper import solid_drivers
    spec = load_scene(scene, list(overrides.items()))
    built, _ = build_scene(spec.builder, spec.values)
    h = solid_smoothing_ratio(spec.values) * spec["numerics.spacing"]
    solver = SolidPhase(built.solid, built, spec.values, h, []).solver
    signature = tuple(numba.typeof(value) for value in solver.leapfrog_arguments(1, False, 0.0))
    solid_drivers(solver.params)[0].compile(signature)
    return signature


def run_tasks(tasks):
    """A compiling process's tasks in order (Part.tasks)."""
    how = {"driver": compile_driver, "step": warm_up}
    for kind, scene, overrides in tasks:
        how[kind](scene, overrides)


if __name__ == "__main__":
    run_tasks(json.loads(sys.argv[1]))
