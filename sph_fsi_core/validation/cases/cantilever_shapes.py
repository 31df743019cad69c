"""The default scheme's cantilever over shapes and materials (scenes/cantilever.py; judged by the scene's evaluate
on its first frequency against 3D FE for its own shape and nu): nu by L / H, one table."""
from ..report_tools import grid_table
from ..rung import Rung
from .as_run import EXPLICIT_PRESSURE


# The default scheme's cantilever over shapes and materials: quadratic_gradient
# with the mirrored clamp at 4 particles through the paper's 4 x 6 mm section (dp = 1 mm), nu = 0.3, 0.4, 0.49 and
# L / H = 10, 20, 30, each judged against the project's 3D FE for its own shape and nu
# (reference_data/cantilever_fe3d_nondimensional.csv). The cost grows as (L / H)^3 and with the bulk sound speed
# (nu = 0.49's step is 3.6x nu = 0.3's): the nu = 0.49, L / H = 30 rung is the long one (~40 min on 2 threads).
CANTILEVER_SHAPE_POISSON = (0.3, 0.4, 0.49)
CANTILEVER_SHAPE_SLENDERNESS = (10, 20, 30)


def rungs():
    rungs = []
    for nu in CANTILEVER_SHAPE_POISSON:
        for ratio in CANTILEVER_SHAPE_SLENDERNESS:
            quick = nu == 0.3 and ratio == 10     # CI's: the default scheme as it is
            overrides = {"geometry.length": ratio * 0.004, "solid.poisson_ratio": nu, "solid.clamp": "mirrored",
                         **({} if quick else EXPLICIT_PRESSURE)}
            rungs.append(Rung("cantilever_shapes", f"nu{nu:g}_L_over_H_{ratio}", "cantilever", overrides,
                              periods=2.25, quick=quick, bound=0.02,
                              note=f"L / H = {ratio}, nu = {nu:g}, 4 particles through, solid.clamp = mirrored"
                                   + ("" if quick else ", solid.pressure = explicit")))
    return rungs


def table(out_dir, rungs, summaries):
    """The default scheme's cantilever by Poisson ratio and slenderness: frequency error against its own 3D FE."""
    runs = [(r, summaries.get(r.key)) for r in rungs if r.case == "cantilever_shapes"]
    if not any(s for _, s in runs):
        return []
    poisson = list(dict.fromkeys(r.overrides["solid.poisson_ratio"] for r, _ in runs))
    ratios = list(dict.fromkeys(round(r.overrides["geometry.length"] / 0.004) for r, _ in runs))

    def cell(nu, n):
        s = summaries.get(f"cantilever_shapes/nu{nu:g}_L_over_H_{n}")
        if s is None:
            return "not run"
        if s.get("frequency_hz") is None or not s.get("reference_hz"):
            return "no frequency"
        return f"{100 * (s['frequency_hz'] / s['reference_hz'] - 1.0):+.2f} % ({s['wall_time_s']:.0f} s)"
    return grid_table("## The default scheme's cantilever over shapes and materials (cantilever_shapes)",
                 "`quadratic_gradient` with the mirrored clamp, 4 particles through the paper's 4 x 6 mm section (dp = "
                 "1 mm), 2.25 periods from the first mode's velocity (eq. (12)); the first vertical frequency against "
                 "the project's 3D FE for the same shape and nu (reference_data/cantilever_fe3d_nondimensional.csv, "
                 "meshes H/2, H/4, H/6 extrapolated). - is softer than FE. Wall time in brackets.", "nu",
                 [(nu, f"{nu:g}") for nu in poisson], [(f"L/H = {n}", n) for n in ratios], cell)
