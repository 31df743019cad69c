"""The interface a scene builder gives the scene loader, the simulation, the run and the watchdog (scenes.BUILDERS):
one record, each optional part None (or its stated default) where a builder has none.

    phases          tuple of the most phases its scenes have ('solid', 'fluid', ...)
    geometry        list of schema.Param: its own keys (under 'geometry.', and 'scene.case')
    defaults        {key: value} overriding the schema's defaults for its scenes
    conservative    True when nothing feeds energy in (the watchdog then bounds the energy's growth)
    check(values)               SceneError for inconsistent values (e.g. spacing larger than the body)
    build(values) -> Built      particles, probes, domain
    particle_counts(values)     {phase: count} of what build() makes, computed without making it (memory guard)
    evaluate(series, values)    {measured quantities, reference, error} from the run's time series
    sample(solid, probes, vel)  extra time-series columns of the solid, e.g. the tip's velocity
    sample_fluid(sim)           extra time-series columns of the water, e.g. a front position
    phases_of(flat)             a scene's phases, from its keys
    list_params(flat)           the Params of its part, probe and judge lists (geometry/parts.py)
    resolve_files(values, path) its files' paths made absolute, relative to the scene file
    absent_sections             {section: what in the file would give the scene that section}, for the refusal
    expressions                 True: its file declares parameters, and its lists' and own keys' numbers may be
                                expressions in them (geometry/declared.py, geometry/expressions.py)
"""
from dataclasses import dataclass
from typing import Callable


@dataclass(frozen=True)
class Builder:
    name: str
    phases: tuple
    geometry: list
    defaults: dict
    conservative: bool
    check: Callable
    build: Callable
    particle_counts: Callable
    evaluate: Callable = None
    sample: Callable = None
    sample_fluid: Callable = None
    phases_of: Callable = None
    list_params: Callable = None
    resolve_files: Callable = None
    absent_sections: dict = None
    expressions: bool = False
