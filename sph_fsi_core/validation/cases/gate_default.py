"""Both gates with the default scheme as it ran with the pressure explicit (scenes/antoci_gate.py and
scenes/elastic_gate.py, judged by their evaluate); their tables and plots are the gates' (cases/gate.py)."""
from ..rung import Rung
from .as_run import EXPLICIT_PRESSURE, PAPER_SPAN


# Both gates with the default scheme (quadratic_gradient and its mirrored clamp, every scene's): the paper's gate at its 1 mm against its figures' window and Gray's run above,
# Antoci's on a ladder of 3 / 4 / 5 particles through the gate against the experiment.
def rungs():
    """As they were run: with the pressure explicit (EXPLICIT_PRESSURE); their twins with the implicit pressure, and
    the Antoci ladder's third rung (1 mm), are case `solid_pressure`'s."""
    explicit = EXPLICIT_PRESSURE
    rungs = [Rung("gate_default", "elastic_gate_dp1mm", "elastic_gate",
                  {"numerics.spacing": 0.001, **explicit, **PAPER_SPAN},
                  end_time=0.14, snapshot_interval=0.02,
                  note="the paper's gate at its 1 mm, solid.pressure = explicit")]
    for dp, label in ((0.005 / 3, "dp1.67mm"), (0.00125, "dp1.25mm")):
        rungs.append(Rung("gate_default", f"antoci_gate_{label}", "antoci_gate", {"numerics.spacing": dp, **explicit},
                          end_time=0.4,
                          note=f"dp = {dp * 1e3:.3g} mm ({round(0.005 / dp)} particles through the gate), "
                               f"solid.pressure = explicit; free end vs Antoci et al. 2007"))
    # the other published material (CoCoNuT's row of reference/antoci2007_material_by_source.csv): the band's edge
    rungs.append(Rung("gate_default", "antoci_gate_E10MPa_nu0.49_dp1.67mm", "antoci_gate",
                      {"numerics.spacing": 0.005 / 3, "solid.young_modulus": 1.0e7, "solid.poisson_ratio": 0.49,
                       **explicit}, end_time=0.4,
                      note="E = 10 MPa, nu = 0.49 (CoCoNuT's plane-strain FE row) at dp = 5/3 mm, solid.pressure = "
                           "explicit"))
    # the water settled at rest behind the gate (held straight, a plug in the gap) before t = 0 (fluid.settle_time),
    # and the paper's gate with the 0.1 % tolerance as well
    rungs += [Rung("gate_default", "elastic_gate_settled_dp1mm", "elastic_gate",
                   {"numerics.spacing": 0.001, "fluid.settle_time": 0.1, **explicit, **PAPER_SPAN}, end_time=0.14,
                   note="the paper's gate at 1 mm, the water settled 0.1 s behind it, solid.pressure = explicit"),
              Rung("gate_default", "elastic_gate_settled_tolerance0.1pct_dp1mm", "elastic_gate",
                   {"numerics.spacing": 0.001, "fluid.settle_time": 0.1, "fluid.density_tolerance": 0.001,
                    **explicit, **PAPER_SPAN}, end_time=0.14,
                   note="the paper's gate at 1 mm, settled, density tolerance 0.1 %, solid.pressure = explicit"),
              Rung("gate_default", "antoci_gate_settled_dp1.67mm", "antoci_gate",
                   {"numerics.spacing": 0.005 / 3, "fluid.settle_time": 0.2, **explicit}, end_time=0.4,
                   note="Antoci's gate at dp = 5/3 mm, the water settled 0.2 s behind it, solid.pressure = explicit")]
    return rungs
