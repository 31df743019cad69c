"""What a built-in case needs besides its scene file: one module per case, each with the same declared interface.

A scene file is the case: its parts, probes, judges and its own parameters (config/<case>.yaml, scene.builder:
geometry). What a file cannot say stays code, in the module its `scene.case` names (config/cantilever.yaml:
`case: cantilever` -> scenes/cases/cantilever.py): a case's own reference (a frequency from a 3D FE table, an FE
deflection, a measured front with its own scaling), columns computed from the state (a surge front, a floor
pressure fit), a prescribed load and the relaxation rates that follow from a first mode. The module's values are
the scene's resolved values (its parameters as `geometry.<name>`, its derived quantities beside them).

Each module defines `CASE = Case(...)` with the parts it has and None for the others; nothing is looked up by name
or probed for. The geometry builder (scenes/geometry.py) calls `check` when it checks the scene, `load` and
`relaxation` when it builds; the simulation calls `sample` and `sample_fluid` on every time-series row; the run calls
`evaluate` on the finished run's time series (its output is the summary's, beside the file's judges).
"""
from dataclasses import dataclass
from typing import Callable


@dataclass(frozen=True)
class Case:
    """A case module's interface: each part a function, or None where the case has none.

    check(values)                 SceneError for values its parts cannot refuse (a length not a whole number of
                                  spacings, a slab too narrow), each naming its key
    load(values, built)           (force on each solid particle at full load (N, 3) N, ramp time s): a prescribed
                                  dead load, ramped in smoothly from t = 0
    relaxation(values, built)     (solid rate, water rate) 1/s: mass-proportional damping of the solid and
                                  relaxation of the water's velocities that settle a static case
    sample(solid, probes, vel)    {column: value} of the solid's extra time-series columns (vel: the solid's
                                  velocity as outputs report it; probes: the scene's, in file order)
    sample_fluid(sim)             {column: value} of the water's extra columns (sim: the simulation.Simulation)
    evaluate(series, values)      {measure: value} of the finished run ({column: array}): its measures, reference,
                                  'error' and 'error_metric'
    """
    name: str
    check: Callable = None
    load: Callable = None
    relaxation: Callable = None
    sample: Callable = None
    sample_fluid: Callable = None
    evaluate: Callable = None


def probe_named(probes, name):
    """The scene's probe `name` (a case module's columns follow its probes by name, not by place)."""
    return next(p for p in probes if p.name == name)


def _registry():
    from . import (antoci_gate, antoci_gate_loaded, antoci_gate_static, cantilever, cantilever_loaded, clamped_plate,
                   dam_break, elastic_gate, hydrostatic, hydrostatic_plate, lobovsky_dam_break)
    return {module.CASE.name: module.CASE for module in (
        cantilever, cantilever_loaded, clamped_plate, hydrostatic, dam_break, lobovsky_dam_break, hydrostatic_plate,
        elastic_gate, antoci_gate, antoci_gate_static, antoci_gate_loaded)}


CASES = _registry()
