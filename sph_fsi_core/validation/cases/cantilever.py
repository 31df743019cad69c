"""The cantilever in free vibration (scenes/cantilever.py, Satake et al.'s beam, judged by the scene's evaluate on
its first bending frequency against 3D FE): a resolution ladder and a length sweep (the paper's Fig. 5) with the
default scheme as it ran, with the plain nodal sum and with the paper's own scheme, and the long run (Fig. 4)."""
from pathlib import Path

import numpy as np

from ...answers.references import read_reference_csv
from ..report_tools import fmt, save_panels, series_rows
from ..rung import Rung
from .as_run import EXPLICIT_PRESSURE


# the keys of the beam that set its reference frequency (answers/references.cantilever_references' arguments)
BEAM_KEYS = ("geometry.length", "geometry.thickness", "geometry.width", "solid.young_modulus", "solid.poisson_ratio",
             "solid.density")


def cantilever_end_time(overrides, periods):
    """`periods` periods of the 3D reference frequency of the beam the overrides make (the scene's own else)."""
    from ...answers.references import cantilever_references
    from ...scene import load_scene
    values = load_scene("cantilever", [(k, v) for k, v in overrides.items() if k in BEAM_KEYS]).values
    return periods / cantilever_references(*(values[k] for k in BEAM_KEYS))["reference_hz"]


def rungs():
    """The paper's beam on a resolution ladder and a length sweep, with the scheme of the day it ran and two older
    ones (the plain nodal sum, the paper's own)."""
    rungs = []
    # quadratic_gradient, the quadratic fit with the strain-gradient nodal integration, with the fixed clamp: as these
    # rungs were run, before the scheme took the mirrored clamp (the default scheme itself: cantilever_shapes).
    fixed = {"solid.clamp": "fixed", **EXPLICIT_PRESSURE}
    # Resolution ladder H/dp = 4, 6, 8 (2.25 periods of the reference each: the zero-crossing fit and the damping
    # ratio need two full periods of the tip). CI runs the paper's beam with the default scheme instead
    # (test/validation/test_cantilever_quick.py): a sixth of these explicit-pressure steps.
    for ratio, quick in ((4, False), (6, False), (8, False)):
        dp = 0.004 / ratio
        rungs.append(Rung("cantilever_ladder", f"H_over_dp_{ratio}", "cantilever",
                          {"numerics.spacing": dp, **fixed}, periods=2.25, quick=quick, bound=0.03,
                          note=f"dp = {dp * 1e3:.3f} mm"))
    # Length sweep at dp = 1 mm, as the paper's Fig. 5 (2.25 periods, as the ladder; shorter records let the
    # free end's higher modes bias the frequency). The cost grows as L^3 (particles x period).
    rungs += [Rung("cantilever_length", f"L{length_mm}", "cantilever", {"geometry.length": length_mm * 1e-3, **fixed},
                   periods=2.25, note=f"L = {length_mm} mm, dp = 1 mm") for length_mm in (40, 60, 80, 100, 120)]
    # The paper's beam at the paper's spacing, 10 periods: frequency, damping, energy, sideways mode.
    rungs.append(Rung("cantilever", "L40_dp1.0_10periods", "cantilever", fixed, periods=10.0,
                      note="the paper's beam, 10 periods"))
    # The same beams with quadratic_plain, the plain nodal integration (each particle's strain at its centre, the
    # scheme before the gradient integration; a 4-layer beam's EI 6 % short, docs/method.md).
    plain = {"solid.scheme": "quadratic_plain"}
    for ratio in (4, 6, 8):
        dp = 0.004 / ratio
        rungs.append(Rung("cantilever_plain_ladder", f"H_over_dp_{ratio}", "cantilever",
                          {"numerics.spacing": dp, **plain}, periods=2.25,
                          note=f"dp = {dp * 1e3:.3f} mm, solid.scheme = quadratic_plain"))
    rungs += [Rung("cantilever_plain_length", f"L{length_mm}", "cantilever",
                   {"geometry.length": length_mm * 1e-3, **plain}, periods=2.25,
                   note=f"L = {length_mm} mm, dp = 1 mm, solid.scheme = quadratic_plain")
              for length_mm in (40, 60, 80, 100, 120)]
    rungs.append(Rung("cantilever_plain", "L40_dp1.0_10periods", "cantilever", plain, periods=10.0,
                      note="the paper's beam, 10 periods, solid.scheme = quadratic_plain"))
    # The paper's own scheme (gray2001: Gray's SPH gradient, plain sum) on the same beams: close at L = 40 mm, too
    # stiff beyond. As these rungs were run (the cantilever scene's artificial stress was 0 and its step factor
    # 0.25): without gray2001's artificial stress and at the quadratic schemes' step factor.
    paper = {"solid.scheme": "gray2001", "solid.artificial_stress_epsilon": 0.0, "solid.cfl": 0.25}
    for length_mm in (40, 60, 80):
        rungs.append(Rung("cantilever_paper_scheme", f"L{length_mm}", "cantilever",
                          {"geometry.length": length_mm * 1e-3, **paper},
                          periods=2.25, note=f"L = {length_mm} mm, dp = 1 mm, solid.scheme = gray2001 without "
                                             f"artificial stress, solid.cfl = 0.25"))
    return rungs


# The cases whose runs are the cantilever scene's free vibration: the table below reads each one's measures.
CANTILEVER_CASES = ("cantilever", "cantilever_ladder", "cantilever_length", "cantilever_shapes", "cantilever_plain",
                    "cantilever_plain_ladder", "cantilever_plain_length", "cantilever_paper_scheme")


def table(out_dir, rungs, summaries):
    """Every free-vibration run's frequency against each reference, its damping, energy and sideways mode."""
    lines = []
    for r in rungs:
        s = summaries.get(r.key)
        if s is None or r.case not in CANTILEVER_CASES:
            continue
        if s.get("frequency_hz") is None:
            continue
        lines.append(
            f"| {r.key} | {fmt(s.get('error_vs_fe3d_percent'), '+.2f')} | "
            f"{fmt(s.get('error_vs_euler_bernoulli_percent'), '+.2f')} | "
            f"{fmt(s.get('error_vs_eq15_percent'), '+.2f')} | "
            f"{fmt(s.get('damping_ratio'), '.4f')} | {fmt(s.get('energy_max_period_growth'), '+.2e')} | "
            f"{fmt(s.get('max_sideways_speed_over_tip_speed'), '.2e')} | {fmt(s.get('periods'), '.1f')} |")
    if not lines:
        return []
    return ["", "### Cantilever: against each reference, damping, energy and the sideways mode", "",
            "Errors in % against the 3D elasticity value (fe3d), Euler-Bernoulli beam theory and the paper's eq. (15) "
            "(plane-strain plate). Damping ratio from the decay of the tip's peaks. Energy: largest growth of the "
            "period-averaged kinetic + strain energy from one period to the next (negative: it decays). Sideways: "
            "largest mean sideways speed of the free end after the first period, over Vf.", "",
            "| run | vs fe3d | vs beam | vs eq. (15) | damping ratio | energy growth / period | sideways / Vf | "
            "periods |",
            "|---|---|---|---|---|---|---|---|", *lines]


def plot(out_dir, rungs, summaries, plt):
    """cantilever_frequency_vs_length.png (the length sweeps against the references, as the paper's Fig. 5) and
    cantilever_tip_and_energy.png (the long run's free end and energy, as its Fig. 4)."""
    made = []
    sweep = [(summaries[r.key]["settings"]["geometry.length"], summaries[r.key]) for r in rungs
             if r.case == "cantilever_length" and r.key in summaries and summaries[r.key].get("frequency_hz")]
    if sweep:
        table = read_reference_csv("cantilever_frequencies.csv")
        lengths = np.array([row["L_mm"] for row in table])
        fig, ax = plt.subplots(figsize=(6, 4.5))
        ax.plot(lengths, [row["eq15_Hz"] for row in table], "k--", label="eq. (15), plane-strain plate")
        ax.plot(lengths, [row["eb_Hz"] for row in table], "k:", label="Euler-Bernoulli beam")
        ax.plot(lengths, [row["fe3d_1mm_Hz"] for row in table], "k-", label="3D elasticity (FE, 1 mm)")
        ax.errorbar([length * 1e3 for length, _ in sweep], [s["frequency_hz"] for _, s in sweep],
                    yerr=[s["frequency_uncertainty_hz"] for _, s in sweep], fmt="o", color="C3",
                    label="sph_fsi, dp = 1 mm (quadratic fit, gradient nodal integration: default)")
        for case, marker, color, label in (
                ("cantilever_plain_length", "^", "C2", "sph_fsi, dp = 1 mm, quadratic fit, plain nodal sum"),
                ("cantilever_paper_scheme", "s", "C0", "sph_fsi, dp = 1 mm, Gray's SPH gradient (the paper's scheme)")):
            other = [(summaries[r.key]["settings"]["geometry.length"], summaries[r.key]) for r in rungs
                     if r.case == case and r.key in summaries and summaries[r.key].get("frequency_hz")]
            if other:
                ax.plot([length * 1e3 for length, _ in other], [s["frequency_hz"] for _, s in other], marker,
                        color=color, mfc="none", label=label)
        ax.set_xlabel("beam length L [mm]")
        ax.set_ylabel("first bending frequency [Hz]")
        ax.set_title("Cantilever frequency against length (cf. the paper's Fig. 5)")
        made.append(save_panels(plt, fig, [ax], Path(out_dir) / "cantilever_frequency_vs_length.png",
                                legend_size=8))
    # The long run's free-end motion and energy, like the paper's Fig. 4.
    long_run = [r for r in rungs if r.case == "cantilever" and r.key in summaries]
    if long_run:
        rows = series_rows(out_dir, long_run[0])
        if rows is not None:
            t = np.array([float(r["time"]) for r in rows])
            z = np.array([float(r["tip_dz"]) for r in rows])
            e = np.array([float(r["kinetic_energy"]) + float(r["strain_energy"]) for r in rows])
            fig, (a1, a2) = plt.subplots(2, 1, figsize=(7, 5), sharex=True)
            a1.plot(t, z * 1e3)
            a1.set_ylabel("free-end z displacement [mm]")
            a1.set_title("Cantilever L = 40 mm, dp = 1 mm (cf. the paper's Fig. 4)")
            a2.plot(t, e * 1e9)
            a2.set_ylabel("kinetic + strain energy [nJ]")
            a2.set_xlabel("t [s]")
            made.append(save_panels(plt, fig, (a1, a2), Path(out_dir) / "cantilever_tip_and_energy.png"))
    return made
