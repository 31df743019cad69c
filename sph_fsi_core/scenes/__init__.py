"""Scenes: every scene is a file (config/*.yaml, or a user's) that the one builder, geometry.py, turns into particles:
its parts, probes and judges, its own parameters and the expressions in them. What a built-in case's file cannot
say (its own reference, columns computed from the state, a prescribed load, relaxation rates) is its case module's,
cases/<case>.py, named by the file's `scene.case` and declared as a cases.Case record.

`BUILDERS` holds the builders by name (builder.Builder, the interface the loader, the simulation and the run call);
`interface(builder, values)` is the one a scene runs with, its case module's hooks in it; `build_scene` the
particles a run starts from.
"""
from dataclasses import replace

from ..numerics.kernels import SUPPORT_RADIUS_IN_H, lattice_density_scale, water_kernel
from . import geometry
from ..errors import SceneError
from ..geometry.parts import list_entries
from ..schema import solid_smoothing_ratio
from .builder import Builder  # noqa: F401  (the interface's record)
from .built import check_layout, without_unreached_clamp


BUILDERS = {geometry.BUILDER.name: geometry.BUILDER}
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
    h = solid_smoothing_ratio(values) * spacing
    return without_unreached_clamp(built, SUPPORT_RADIUS_IN_H * h + spacing, values.get("fluid.density", 0.0),
                                   lattice_density_scale(values["numerics.smoothing_ratio"], water_kernel(values)))
