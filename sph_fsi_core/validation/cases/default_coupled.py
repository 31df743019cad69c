"""Water and an elastic body together: the default suite's coupled cases, each part of which is checked alone in
default_solid.py and default_fluid.py.

    water_plate    the hydrostatic-plate benchmark (Fourey et al. 2017): 2 m of water at rest on a clamped plate,
                   4, 6, 8 through; settled mid-span deflection against plane-strain FE under rho_f g H. The plate's
                   E is the benchmark's / 20 (the same ratio to FE, a 4.5x longer step) and the push relaxed (0.3):
                   the column's added mass alternates the unrelaxed push from 6 through (docs/validation/OPEN.md 1.0)
    antoci_loaded  Antoci's gate under its water's exact hydrostatic pressure, no water: free end against FE
    antoci_static  Antoci's gate at rest under its water (g = 1 m/s^2, the gap closed): free end against the same FE
    antoci         Antoci et al. 2007's gate opened by its water: free end against the experiment, 0-0.4 s
    paper_gate     the paper's dam break through an elastic gate across its 36 mm: no measurement exists; the free
                   end's peak against the finest rung's (self-convergence)

Every rung runs the scenes' defaults (quadratic_gradient, the mirrored clamp, the implicit pressure, the pressure
coupling) but for the resolution and what the case names. Peers beside ours: Antoci's gate
(reference_data/antoci2007_numerical_peaks.csv) and the benchmark plate (hydrostatic_plate.PEERS).
"""
from ..rung import Rung
from .as_run import PAPER_SPAN
from .gate import antoci_peers
from .hydrostatic_plate import HYDROSTATIC_PLATE_SCALED_E, peers_table

SECTION = "## Water and an elastic body"
PLATE_THICKNESS = 0.05                       # m (config/hydrostatic_plate.yaml)
GATE_THICKNESS = 0.005                       # m, Antoci's (config/antoci_gate.yaml)
PAPER_GATE_THICKNESS = 0.004                 # m, the paper's (config/elastic_gate.yaml)
ANTOCI_LADDER = (3, 4, 5)                    # particles through the gate
PAPER_GATE_LADDER = (3, 4, 6)
FINEST = "paper_gate/through_6"              # the paper's gate's reference: its finest rung

MEASURES = {
    "water_plate": ("settled mid-span deflection under 2 m of water", "plane-strain FE under rho_f g H "
                                                                      "(answers/fe_reference.py)"),
    "antoci_loaded": ("settled free end under the exact water pressure", "plane-strain FE of the gate "
                                                                         "(answers/fe_reference.py)"),
    "antoci_static": ("settled free end under its water at rest", "the same FE under rho_f g H"),
    "antoci": ("free-end x displacement, RMS over 0-0.4 s / peak", "Antoci et al. 2007's experiment "
                                                                   "(reference_data/antoci2007_exp_gate_tip_x.csv)"),
    "paper_gate": ("free end's x peak (no measurement exists)", "the finest rung (6 through): self-convergence"),
}


def rungs():
    out = []
    for n in (4, 6, 8):
        out.append(Rung("water_plate", f"t_over_dp_{n}", "hydrostatic_plate",
                        {"numerics.spacing": PLATE_THICKNESS / n, "solid.young_modulus": HYDROSTATIC_PLATE_SCALED_E,
                         "fluid.time_step": 1.0e-3, "coupling.relaxation": 0.3}, end_time=0.3,
                        resolution=f"{n} through", note=f"{n} particles through the plate, E = 3.375 GPa, "
                                                        f"coupling.relaxation = 0.3"))
    for n in ANTOCI_LADDER[:2]:
        out.append(Rung("antoci_loaded", f"through_{n}", "antoci_gate_loaded", {"numerics.spacing": GATE_THICKNESS / n},
                        end_time=0.4, resolution=f"{n} through", note=f"{n} particles through the gate"))
    for n in ANTOCI_LADDER[:2]:
        out.append(Rung("antoci_static", f"through_{n}", "antoci_gate_static", {"numerics.spacing": GATE_THICKNESS / n},
                        end_time=0.6, resolution=f"{n} through",
                        note=f"{n} particles through the gate, to 0.6 s (judged over its last half)"))
    for n in ANTOCI_LADDER:
        out.append(Rung("antoci", f"through_{n}", "antoci_gate", {"numerics.spacing": GATE_THICKNESS / n},
                        end_time=0.4, resolution=f"{n} through", note=f"{n} particles through the gate"))
    for n in PAPER_GATE_LADDER:
        out.append(Rung("paper_gate", f"through_{n}", "elastic_gate",
                        {"numerics.spacing": PAPER_GATE_THICKNESS / n, **PAPER_SPAN}, end_time=0.14,
                        resolution=f"{n} through", note=f"{n} particles through the gate, across the paper's 36 mm"))
    return out


def derived_error(rung, summaries):
    """(error, what it is against) for the paper's gate, whose scene has no reference: the relative difference of
    the free end's x peak from the finest rung's; None for the other cases (their scenes judge them)."""
    if rung.case != "paper_gate" or rung.key == FINEST:
        return None
    s, finest = summaries.get(rung.key), summaries.get(FINEST)
    if s is None or finest is None or not finest.get("tip_dx_peak_m") or s.get("tip_dx_peak_m") is None:
        return None
    return abs(s["tip_dx_peak_m"] / finest["tip_dx_peak_m"] - 1.0), "the 6-through rung"


def table(out_dir, rungs, summaries):
    """The peers beside ours: Antoci's gate and the benchmark plate."""
    ours = [r for r in rungs if r.case == "antoci" and r.key in summaries]
    lines = []
    if ours:
        lines += ["", "### Antoci's gate beside the published results", "",
                  "| result | x peak [mm] | at [s] | RMS / peak |", "|---|---|---|---|"]
        for r in ours:
            s = summaries[r.key]
            lines.append(f"| this code, {r.resolution} | {1e3 * s['tip_x_peak_m']:.1f} | {s['tip_x_peak_time_s']:.3f} "
                         f"| {100 * s['error']:.1f} % |")
        lines += antoci_peers()
    lines += peers_table(rungs, summaries, case="water_plate")
    return lines
