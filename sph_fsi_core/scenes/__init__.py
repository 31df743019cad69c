"""Geometry builders, one module per case. A builder declares the phases it has, its geometry keys, and how a
run of it is judged; it only makes particles and settings (the time loop is simulation.py's).

A builder module defines, and `Builder` (below) holds, each optional part None where a module has none:
    PHASES        tuple of phase names ('solid', 'fluid', ...)
    GEOMETRY      list of schema.Param under 'geometry.'
    DEFAULTS      {key: value} overriding schema defaults for this builder (optional)
    CONSERVATIVE  True when nothing feeds energy in (the watchdog then bounds energy growth; optional: False)
    check(values)               SceneError for inconsistent values (e.g. spacing larger than the body)
    build(values) -> Built      particles, probes, domain
    particle_counts(values)     {phase: count} of what build() makes, computed without making it (memory guard)
    evaluate(series, values)    {measured quantities, reference, error} from the run's time series (optional)
    sample(solid, probes, vel)  extra time-series columns of the solid, e.g. the tip's velocity (optional)
    sample_fluid(sim)           extra time-series columns of the water, e.g. a front position (optional)
A scene whose phases and keys follow from its file (the geometry builder) also has:
    phases_of(flat)             its phases, from the scene's keys
    list_params(flat)           the Params of its part, probe and judge lists (geometry/parts.py)
    resolve_files(values, path) its files' paths made absolute, relative to the scene file
    ABSENT_SECTIONS             {section: what in the file would give the scene that section}, for the refusal
    EXPRESSIONS                 True: its file declares parameters, and its lists' and own keys' numbers may be
                                expressions in them (geometry/declared.py, geometry/expressions.py)
and names a case module (scenes/cases: `scene.case`) with what its file cannot say; `interface(builder, values)` is
the one a scene runs with, the case's hooks in it.
"""
from dataclasses import dataclass, replace
from typing import Callable

from ..numerics.kernels import SUPPORT_RADIUS_IN_H, lattice_density_scale
from . import geometry
from ..errors import SceneError
from ..geometry.parts import list_entries
from .built import check_layout, without_unreached_clamp


@dataclass(frozen=True)
class Builder:
    """A builder module's interface (module docstring): what the scene loader, the simulation, the run and the
    watchdog call, each optional part None (or its stated default) where the module has none."""
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

    @classmethod
    def of(cls, name, module):
        """The interface of builder module `module`, registered as `name`."""
        optional = {key: getattr(module, key, None) for key in ("evaluate", "sample", "sample_fluid", "phases_of",
                                                                "list_params", "resolve_files")}
        optional["absent_sections"] = getattr(module, "ABSENT_SECTIONS", None)
        optional["expressions"] = getattr(module, "EXPRESSIONS", False)
        return cls(name, module.PHASES, module.GEOMETRY, getattr(module, "DEFAULTS", {}),
                   getattr(module, "CONSERVATIVE", False), module.check, module.build, module.particle_counts,
                   **optional)


BUILDERS = {name: Builder.of(name, module) for name, module in (("geometry", geometry),)}
DEFAULT_SCENE = "cantilever"


def interface(builder, values):
    """The Builder a scene of `builder` (a name in BUILDERS) with these values runs with: a geometry scene's with its
    case module's columns and evaluation (scenes/cases) and conservative when nothing feeds energy in (no water, no
    gravity, no prescribed load: the watchdog then bounds the energy's growth)."""
    record = BUILDERS[builder]
    if builder != "geometry":
        return record
    case = geometry.case_of(values)
    conservative = ("fluid.density" not in values and not any(values["scene.gravity"])
                    and (case is None or case.load is None))
    if case is None:
        return replace(record, conservative=conservative)

    def evaluate(series, values):
        judged = geometry.evaluate(series, values) if list_entries(values, "judge") else {}
        return {**judged, **case.evaluate(series, values)} if case.evaluate is not None else judged

    return replace(record, conservative=conservative, sample=case.sample, sample_fluid=case.sample_fluid,
                   evaluate=evaluate)


def build_scene(builder, values):
    """A scene's particles as a run starts from them: `builder`'s (a name in BUILDERS) from `values`, checked
    (built.check_layout: no overlapping bodies, nothing outside the domain; with solid.clamp = mirrored, a clamp
    the builder can mirror the body across), and with solid.clamp = mirrored without the clamp's particles that no
    moving particle reaches (built.without_unreached_clamp). Returns (Built, how many clamp particles were left
    out)."""
    built = BUILDERS[builder].build(values)
    check_layout(built, values["numerics.spacing"])
    if built.solid is None or values["solid.clamp"] != "mirrored":
        return built, 0
    mirrored = built.clamp_mirror is not None and (built.clamp_mirror >= 0).any()
    if not mirrored and not built.solid.movable.all():
        raise SceneError(f"solid.clamp = mirrored: scene builder '{builder}' has no plane clamp face to mirror the "
                         f"body across; allowed: fixed")
    if not mirrored:     # free bodies only: no clamp to mirror
        return built, 0
    spacing = values["numerics.spacing"]
    h = values["numerics.smoothing_ratio"] * spacing
    return without_unreached_clamp(built, SUPPORT_RADIUS_IN_H * h + spacing, values.get("fluid.density", 0.0),
                                   lattice_density_scale(values["numerics.smoothing_ratio"]))
