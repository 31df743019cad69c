"""sph_fsi_core/precompile.py: a coupled scene's kernels compiled in two processes at once (the solid's driver; the
fluid's passes and the solid's build)."""
import subprocess
import sys
import time

import pytest

from sph_fsi_core import precompile
from sph_fsi_core.scene import load_scene


@pytest.mark.parametrize("scheme", ["quadratic_gradient", "gray2001", "quadratic_plain_artificial_stress"])
def test_the_solid_warm_up_runs_the_scenes_own_solid_code(scheme):
    """A coupled scene gets two parts: the solid's driver compiled for the small beam with the scene's code-selecting
    solid values (so the driver and pair variant the scene runs, not the beam's own scheme), and the dam break's
    fluid followed by a step of the same beam (its list and fit; the driver cached by then)."""
    gate = load_scene("elastic_gate", [f"solid.scheme={scheme}"])
    parts = precompile.warm_up_parts(gate)
    assert [part.half for part in parts] == ["solid", "fluid"]
    assert [task[:2] for task in parts[0].tasks] == [("driver", "cantilever")]
    assert [task[:2] for task in parts[1].tasks] == [("step", "dam_break"), ("step", "cantilever")]
    solid_overrides = parts[0].tasks[0][2]
    assert parts[1].tasks[1][2] == solid_overrides
    assert set(solid_overrides) == set(precompile.SOLID_CODE_KEYS)
    beam = load_scene("cantilever", list(solid_overrides.items()))
    assert {k: beam[k] for k in precompile.SOLID_CODE_KEYS} == {k: gate[k] for k in precompile.SOLID_CODE_KEYS}
    fluid = load_scene(*parts[1].tasks[0][1:])
    assert "fluid" in fluid.phases and "solid" not in fluid.phases


@pytest.mark.parametrize("scheme", ["quadratic_gradient", "gray2001"])
def test_the_driver_compiled_ahead_is_the_one_the_runs_call(scheme):
    """compile_driver's signature, from the beam's arrays as allocated (no kernel run), is the one the beam's own
    steps and the coupled gate's (the fluid's push as ext_acc) call: neither compiles another specialisation. A
    mismatch would cost a cold install the whole driver's compile twice."""
    from sph_fsi_core.simulation import Simulation
    from sph_fsi_core.solid.stepper import solid_drivers
    gate = load_scene("elastic_gate", [f"solid.scheme={scheme}", "numerics.spacing=0.001333",
                                       "geometry.water_height=0.02"])
    _, scene, overrides = precompile.warm_up_parts(gate)[0].tasks[0]
    signature = precompile.compile_driver(scene, overrides)
    beam = Simulation(load_scene(scene, list(overrides.items())))
    driver = solid_drivers(beam.solid_phase.solver.params)[0]
    compiled = list(driver.signatures)
    assert signature in compiled
    beam.step()
    coupled = Simulation(gate)
    coupled.step()
    assert coupled.solid_phase.steps > 0 and solid_drivers(coupled.solid_phase.solver.params)[0] is driver
    assert driver.signatures == compiled


@pytest.mark.parametrize("scene", ["cantilever", "dam_break", "hydrostatic"])
def test_a_scene_with_one_phase_compiles_in_its_own_process(scene, monkeypatch):
    """Nothing to share out: no part, and no process started."""
    monkeypatch.setattr(subprocess, "Popen", _no_process)
    spec = load_scene(scene)
    assert precompile.warm_up_parts(spec) == []
    assert precompile.compile_in_parallel(spec, cpus=2) is None


def test_one_cpu_or_the_switch_keeps_it_in_process(monkeypatch):
    monkeypatch.setattr(subprocess, "Popen", _no_process)
    gate = load_scene("elastic_gate")
    both = precompile.warm_up_parts(gate)
    assert precompile.compile_in_parallel(gate, cpus=1, parts=both) is None
    monkeypatch.setenv(precompile.SWITCH_ENV, "0")
    assert precompile.compile_in_parallel(gate, cpus=2, parts=both) is None


def test_only_the_halves_not_cached_yet_are_compiled(monkeypatch):
    """A half whose entry kernel is cached is left out; with one half left there is nothing to run side by side."""
    gate = load_scene("elastic_gate")
    monkeypatch.setattr(precompile, "kernels_cached", lambda phases, fitted=True: "solid" in phases)
    assert [part.half for part in precompile.uncached_parts(gate)] == ["fluid"]
    monkeypatch.setattr(subprocess, "Popen", _no_process)
    assert precompile.compile_in_parallel(gate, cpus=2) is None
    monkeypatch.setattr(precompile, "kernels_cached", lambda phases, fitted=True: False)
    assert [part.half for part in precompile.uncached_parts(gate)] == ["solid", "fluid"]
    monkeypatch.setattr(precompile, "kernels_cached", lambda phases, fitted=True: None)   # cannot tell: compile
    assert len(precompile.uncached_parts(gate)) == 2


def test_a_failed_part_is_named_and_the_run_goes_on(monkeypatch):
    """Two real processes that fail at once (unknown scenes): each failure comes back as one line naming its part
    and the error, and compile_cold_scene warns with it instead of raising."""
    parts = [precompile.Part("solid", [("driver", "no_such_scene_a", {})]),
             precompile.Part("fluid", [("step", "no_such_scene_b", {})])]
    monkeypatch.setattr(precompile, "uncached_parts", lambda spec: parts)
    seconds, failures = precompile.compile_in_parallel(load_scene("elastic_gate"), cpus=2)
    assert seconds > 0.0
    assert len(failures) == 2
    assert failures[0].startswith("the solid's part: exit status 1: ") and "no_such_scene_a" in failures[0]
    assert failures[1].startswith("the fluid's part: exit status 1: ") and "no_such_scene_b" in failures[1]
    said, warned = [], []
    precompile.compile_cold_scene(load_scene("elastic_gate"), said.append, warned.append)
    assert len(said) == 1 and "two processes" in said[0]
    assert len(warned) == 2 and all("the run compiles its part itself" in w for w in warned)


def _no_process(*args, **kwargs):
    raise AssertionError("no process should start")


def test_waiting_ticks_and_a_process_past_its_deadline_is_stopped():
    """precompile._wait: a progress tick every interval while a process runs, its stderr once it ends; a process
    still running at the deadline is killed and reported as None."""
    started = time.perf_counter()
    quick = subprocess.Popen([sys.executable, "-c", "import sys, time; time.sleep(0.5); sys.stderr.write('done')"],
                             stderr=subprocess.PIPE, text=True)
    ticks = []
    assert precompile._wait(quick, started + 30.0, ticks.append, 0.1, started) == "done"
    assert len(ticks) >= 2 and ticks == sorted(ticks) and 0.0 < ticks[0] < ticks[-1] < 30.0
    slow = subprocess.Popen([sys.executable, "-c", "import time; time.sleep(30)"], stderr=subprocess.PIPE, text=True)
    assert precompile._wait(slow, time.perf_counter() + 0.3, None, 0.1, started) is None
    assert slow.poll() is not None   # killed, not left behind


def test_compile_scene_compiles_the_halves_then_steps_the_scene_itself(monkeypatch):
    """compile_scene (`sph-fsi compile`, make install): the parallel halves first, a failed one warned about, then one
    outer step of the very scene asked for (so the coupling and the settling compile too), in that order."""
    calls = []
    monkeypatch.setattr(precompile, "compile_in_parallel",
                        lambda spec, tick=None, tick_interval_s=15.0: calls.append(("halves", spec.name)) or
                        (12.0, ["cantilever: exit status 1: boom"]))

    class FakeSimulation:
        def __init__(self, spec):
            calls.append(("build", spec.name, spec["numerics.spacing"]))

        def step(self):
            calls.append(("step",))

    import sph_fsi_core.simulation
    monkeypatch.setattr(sph_fsi_core.simulation, "Simulation", FakeSimulation)
    said, warned = [], []
    gate = load_scene("elastic_gate", ["numerics.spacing=0.00125"])
    assert precompile.compile_scene(gate, said.append, warned.append) >= 0.0
    assert calls == [("halves", "elastic_gate"), ("build", "elastic_gate", 0.00125), ("step",)]
    assert len(said) == 1 and "12 s" in said[0] and "one outer step of 'elastic_gate'" in said[0]
    assert warned == ["a compiling process did not finish (cantilever: exit status 1: boom); compiling its part here"]


def test_the_compile_command_refuses_a_bad_scene_in_one_line(capsys):
    """`sph-fsi compile` takes a scene as `run` does: an unknown key is one line naming it, exit status 2."""
    from sph_fsi.cli import EXIT_BAD_INPUT, main
    assert main(["compile", "elastic_gate", "--set", "solid.no_such_key=1"]) == EXIT_BAD_INPUT
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "solid.no_such_key" in err[0]
