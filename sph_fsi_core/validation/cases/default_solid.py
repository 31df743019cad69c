"""The default scheme's solid alone, against exact answers: the cases of the default suite (`sph-fsi validate`) that
have no water.

    paper_beam    the paper's beam (40 x 4 x 6 mm, nu 0.49) at 4, 6 and 8 particles through: first frequency
                  against the project's 3D FE (reference_data/cantilever_fe3d_nondimensional.csv)
    beam_grid     the beam at nu 0.3 / 0.4 / 0.49 and L / H 10 / 20 / 30, 4 through: the same reference
    elastica      the beam settled under a distributed dead load, alpha = q L^3 / (E I) 0.05, 2, 4: free end against
                  the elastica (answers/references.py)
    plate_fe      a clamped-clamped plate under a prescribed water pressure (the hydrostatic-plate benchmark's plate,
                  no water) at 4, 6, 8 through: settled mid-span deflection against plane-strain FE
                  (answers/fe_reference.py)

Every rung runs the scenes' defaults (solid.scheme quadratic_gradient, the mirrored clamp, the implicit pressure);
only the case's own lengths, material and resolution are set. Each scene judges its run (scenes/*.py evaluate).
"""
from ..rung import Rung

SECTION = "## The solid alone"
PAPER_BEAM_THICKNESS = 0.004       # m, H (config/cantilever.yaml)
PAPER_BEAM_LADDER = (4, 6, 8)      # particles through H
GRID_POISSON = (0.3, 0.4, 0.49)
GRID_SLENDERNESS = (10, 20, 30)    # L / H, 4 through (the cost grows as (L / H)^3)
ELASTICA_LOADS = (0.05, 2.0, 4.0)  # alpha: linear, the free end turned 18 and 34 degrees
PLATE_THICKNESS = 0.05             # m (config/clamped_plate.yaml)
PLATE_LADDER = (4, 6, 8)

# Cases whose rungs are not a resolution ladder (shapes, loads): the figure shows their points unjoined
NOT_LADDERS = ("beam_grid", "elastica")

# What each case measures, and against what (the report's headline columns).
MEASURES = {
    "paper_beam": ("first vertical frequency", "3D FE of the same beam (project's, quadratic hexahedra, "
                                               "extrapolated; reference_data/cantilever_fe3d_nondimensional.csv)"),
    "beam_grid": ("first vertical frequency", "3D FE of each shape and nu (same table)"),
    "elastica": ("settled free-end deflection under a dead load", "the elastica (Bisshopp & Drucker 1945; "
                                                                  "answers/references.py)"),
    "plate_fe": ("settled mid-span deflection under rho g H", "plane-strain FE, biquadratic, t / 8 "
                                                             "(answers/fe_reference.py)"),
}


def rungs():
    out = []
    for n in PAPER_BEAM_LADDER:
        out.append(Rung("paper_beam", f"H_over_dp_{n}", "cantilever",
                        {"numerics.spacing": PAPER_BEAM_THICKNESS / n}, periods=2.25, resolution=f"{n} through",
                        quick=n == 4, bound=0.02,
                        note=f"the paper's beam, {n} particles through, 2.25 periods"))
    for nu in GRID_POISSON:
        for ratio in GRID_SLENDERNESS:
            out.append(Rung("beam_grid", f"nu{nu:g}_L_over_H_{ratio}", "cantilever",
                            {"geometry.length": ratio * PAPER_BEAM_THICKNESS, "solid.poisson_ratio": nu},
                            periods=2.25, resolution=f"nu {nu:g}, L/H {ratio}",
                            note=f"L / H = {ratio}, nu = {nu:g}, 4 particles through, 2.25 periods"))
    for alpha in ELASTICA_LOADS:
        out.append(Rung("elastica", f"alpha_{alpha:g}", "cantilever_loaded", {"geometry.load_parameter": alpha},
                        end_time=0.25, resolution=f"alpha {alpha:g}", note=f"alpha = {alpha:g}, L / H = 10, 4 through"))
    for n in PLATE_LADDER:
        out.append(Rung("plate_fe", f"t_over_dp_{n}", "clamped_plate", {"numerics.spacing": PLATE_THICKNESS / n},
                        end_time=0.02, resolution=f"{n} through", note=f"{n} particles through the plate"))
    return out
