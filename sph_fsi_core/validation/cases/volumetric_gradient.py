"""The default scheme with the strain gradient's volumetric part on the beams, the plate and the gates (judged by
each scene's evaluate); its rows are in the headline table and the gates' (cases/gate.py)."""
from ..rung import Rung
from .as_run import PAPER_SPAN
from .cantilever_shapes import CANTILEVER_SHAPE_POISSON


# The default scheme with the strain gradient's volumetric part (solid.volumetric_gradient), time
# stepped on the beams and static solids where the assembled answer (validation/linear_modes, docs/validation/
# linear_modes) predicts it: the cantilever at L/H = 10 -0.230 / -0.316 / -0.080 % at nu = 0.3 / 0.4 / 0.49 (without
# it -0.79 / -0.77 / -0.87 %), the plate at 4 through +0.93 % (+2.68 %), Antoci's gate under its exact load at 5/3 mm
# +0.12 % (+2.15 % assembled, +1.69 % time-stepped).
VOLUMETRIC = {"solid.volumetric_gradient": True}


def rungs():
    rungs = []
    for nu in CANTILEVER_SHAPE_POISSON:
        rungs.append(Rung("volumetric_gradient", f"cantilever_nu{nu:g}_L_over_H_10", "cantilever",
                          {"geometry.length": 0.04, "solid.poisson_ratio": nu, **VOLUMETRIC}, periods=2.25,
                          note=f"L / H = 10, nu = {nu:g}, 4 particles through, the default scheme with "
                               f"solid.volumetric_gradient"))
    rungs.append(Rung("volumetric_gradient", "plate_t_over_dp_4", "clamped_plate",
                      {"numerics.spacing": 0.0125, **VOLUMETRIC}, end_time=0.02,
                      note="the hydrostatic plate's plate under its exact load, 4 particles through, the default "
                           "scheme with solid.volumetric_gradient"))
    rungs.append(Rung("volumetric_gradient", "gate_loaded_dp1.67mm", "antoci_gate_loaded",
                      {"numerics.spacing": 0.005 / 3, **VOLUMETRIC}, end_time=0.4,
                      note="Antoci's gate under its water's exact pressure, 3 particles through, the default scheme "
                           "with solid.volumetric_gradient"))
    # in motion, beside the default scheme's runs (solid_pressure/gate_default_*): how far the gates move with it
    rungs.append(Rung("volumetric_gradient", "elastic_gate_dp1mm", "elastic_gate",
                      {"numerics.spacing": 0.001, **VOLUMETRIC, **PAPER_SPAN}, end_time=0.14,
                      note="the paper's gate at its 1 mm, the default scheme with solid.volumetric_gradient"))
    rungs.append(Rung("volumetric_gradient", "antoci_gate_dp1.67mm", "antoci_gate",
                      {"numerics.spacing": 0.005 / 3, **VOLUMETRIC}, end_time=0.4,
                      note="dp = 5/3 mm (3 particles through the gate); free end vs Antoci et al. 2007; the default "
                           "scheme with solid.volumetric_gradient"))
    return rungs
