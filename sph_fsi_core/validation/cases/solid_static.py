"""The hydrostatic plate's plate alone under its water's exact load (scenes/clamped_plate.py; judged by the scene's
evaluate on the settled mid-span deflection against plane-strain FE): every scheme on a resolution ladder."""
from ..report_tools import grid_table
from ..rung import Rung
from .as_run import EXPLICIT_PRESSURE


# The solid's static answer under a prescribed load (config/clamped_plate.yaml: the hydrostatic-plate benchmark's
# plate with the water's exact pressure), judged against plane-strain FE; every scheme on a resolution ladder.
SOLID_STATIC_SCHEMES = ("quadratic_gradient", "quadratic_plain", "gray2001")
SOLID_STATIC_LAYERS = (4, 6, 8, 10)


def rungs():
    """solid_static: 4 / 6 / 8 / 10 particles through the plate for each scheme with the fixed clamp, and the
    default scheme with the mirrored clamp (whose face is where the FE clamp is)."""
    rungs = []
    thickness = 0.05
    variants = [(scheme, {"solid.scheme": scheme, "solid.clamp": "fixed",
                          **(EXPLICIT_PRESSURE if scheme == "quadratic_gradient" else {})})
                for scheme in SOLID_STATIC_SCHEMES]
    variants.append(("quadratic_gradient_mirrored", {"solid.scheme": "quadratic_gradient", "solid.clamp": "mirrored",
                                                     **EXPLICIT_PRESSURE}))
    for name, overrides in variants:
        for layers in SOLID_STATIC_LAYERS:
            dp = thickness / layers
            rungs.append(Rung("solid_static", f"{name}_t_over_dp_{layers}", "clamped_plate",
                              {"numerics.spacing": dp, **overrides}, end_time=0.02,
                              note=f"{layers} particles through the plate, " + ", ".join(
                                  f"{k} = {v}" for k, v in overrides.items())))
    return rungs


def table(out_dir, rungs, summaries):
    """The static plate by scheme and resolution: the error of the settled mid-span deflection against FE."""
    runs = [(r, summaries.get(r.key)) for r in rungs if r.case == "solid_static"]
    if not any(s for _, s in runs):
        return []
    layers = sorted({int(r.label.rsplit("_", 1)[1]) for r, _ in runs})
    schemes = list(dict.fromkeys(r.label.rsplit("_t_over_dp_", 1)[0] for r, _ in runs))

    def cell(scheme, n):
        s = summaries.get(f"solid_static/{scheme}_t_over_dp_{n}")
        if s is None:
            return "not run"
        if s.get("error_signed") is None:
            return "did not finish"
        return f"{100 * s['error_signed']:+.2f} % ({s['wall_time_s']:.0f} s)"
    return grid_table("## The solid alone under a prescribed load (solid_static)",
                 "The hydrostatic-plate benchmark's plate (1 m x 0.05 m aluminium, clamped at both ends, plane strain) "
                 "under the water's exact pressure and its own weight, settled; the mid-span, mid-thickness deflection "
                 "against the project's plane-strain FE value (answers/fe_reference.py). + is softer than FE. "
                 "Wall time in brackets.", "scheme", [(x, x) for x in schemes],
                 [(f"t/dp = {n}", n) for n in layers], cell)
