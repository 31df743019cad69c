"""The coupled gates in motion: Antoci et al. 2007's rubber gate (scenes/antoci_gate.py, judged by the scene's
evaluate on the free end against the experiment) and the paper's elastic gate (scenes/elastic_gate.py, against its
Figs. 6-8), over coupling models, schemes and spacings. The tables and plots take every run of the two scenes,
whatever its case (gate_default, solid_pressure, volumetric_gradient and gate_span run them too)."""
from pathlib import Path

import numpy as np

from ...scenes.cases.elastic_gate import PAPER_GATE_WIDTH_M
from ...answers.references import read_reference_table
from ..report_tools import save_panels, series_rows
from ..rung import Rung
from .as_run import EXPLICIT_PRESSURE, PAPER_SPAN


# The paper's 4 mm gate with 3 and 6 particles through it, beside its 1 mm (4): (spacing, label, particles through)
PAPER_GATE_LADDER = ((0.004 / 3, "dp1.33mm", 3), (0.002 / 3, "dp0.67mm", 6))


def rungs():
    """The coupled cases, both coupling models at two resolutions each.

    antoci_gate: Antoci et al. 2007's measured free end over 0-0.4 s at dp = 2.5 mm (2 particles through the 5 mm
    gate) and 5/3 mm (3) with Gray's SPH gradient, and at 5/3 and 1.25 mm (4) with the quadratic fit (the scene's
    solid as these rungs were run: solid.scheme = quadratic_plain_artificial_stress). elastic_gate: the paper's case to
    t = 0.14 s at 2 mm and at the paper's 1 mm (80k-particle class runs: the 1 mm rungs are the long ones). CI runs
    shorter versions (test/validation/test_gate_quick.py).
    """
    rungs = []
    # Gray's scheme as these rungs were run: at the quadratic schemes' step factor (the Antoci scene never set 0.5).
    gray = {"solid.scheme": "gray2001", "solid.cfl": 0.25}
    for dp, label in ((0.0025, "dp2.5mm"), (0.005 / 3, "dp1.67mm")):
        for model in ("pressure", "seed"):
            rungs.append(Rung("antoci_gate", f"{model}_{label}", "antoci_gate",
                              {"numerics.spacing": dp, "coupling.model": model, **gray},
                              end_time=0.4, note=f"dp = {dp * 1e3:.3g} mm, coupling {model}, solid.scheme = gray2001 "
                                                 f"(solid.cfl = 0.25); free end vs Antoci et al. 2007"))
    # With three layers through the 5 mm gate the quadratic fit is determined; Gray's SPH gradient is too stiff at
    # this gate's L/H = 16 (docs/validation/OPEN.md, sec. 2). The scene's scheme.
    for dp, label in ((0.005 / 3, "dp1.67mm"), (0.00125, "dp1.25mm")):
        rungs.append(Rung("antoci_gate", f"pressure_quadratic_{label}", "antoci_gate",
                          {"numerics.spacing": dp, "coupling.model": "pressure",
                           "solid.scheme": "quadratic_plain_artificial_stress"}, end_time=0.4,
                          note=f"dp = {dp * 1e3:.3g} mm, coupling pressure, "
                               f"solid.scheme = quadratic_plain_artificial_stress"))
    # The scene keeps Gray's artificial stress (eps = 0.15, its runs above); the quadratic fit needs none, and at
    # nu = 0.49 it feeds a growing mode (docs/method.md): the same run without it.
    rungs.append(Rung("antoci_gate", "pressure_quadratic_eps0_dp1.67mm", "antoci_gate",
                      {"numerics.spacing": 0.005 / 3, "coupling.model": "pressure",
                       "solid.scheme": "quadratic_plain"}, end_time=0.4,
                      note="dp = 1.67 mm, coupling pressure, solid.scheme = quadratic_plain (no artificial stress)"))
    # Three layers through the gate sum z^2 = 2 dp^2 where the section has H^3 / 12 = 2.25 dp^2: the plain nodal sum
    # leaves the gate 11 % soft in bending; the strain-gradient nodal integration puts it back (docs/method.md).
    rungs.append(Rung("antoci_gate", "pressure_gradient_eps0_dp1.67mm", "antoci_gate",
                      {"numerics.spacing": 0.005 / 3, "coupling.model": "pressure",
                       "solid.scheme": "quadratic_gradient", "solid.clamp": "fixed", **EXPLICIT_PRESSURE},
                      end_time=0.4,
                      note="dp = 1.67 mm, coupling pressure, solid.scheme = quadratic_gradient (strain-gradient "
                           "nodal integration, no artificial stress) with the fixed clamp"))
    for dp, label, extra in ((0.002, "dp2mm", {"geometry.gate_clamp_height": 0.004}), (0.001, "dp1mm", {})):
        for model in ("seed", "pressure"):
            rungs.append(Rung("elastic_gate", f"{model}_{label}", "elastic_gate",
                              {"numerics.spacing": dp, "coupling.model": model, "solid.scheme": "gray2001", **extra,
                               **PAPER_SPAN},
                              end_time=0.14,
                              snapshot_interval=0.02,
                              note=f"dp = {dp * 1e3:g} mm, coupling {model}; the paper's Figs. 6-8 (qualitative)"))
    # Gray's scheme on the default's ladder (solid_pressure's gate_default_elastic_gate_*): 3 and 6 particles through
    for dp, label, through in PAPER_GATE_LADDER:
        rungs.append(Rung("elastic_gate", f"pressure_{label}", "elastic_gate",
                          {"numerics.spacing": dp, "coupling.model": "pressure", "solid.scheme": "gray2001",
                           **PAPER_SPAN}, end_time=0.14, snapshot_interval=0.02,
                          note=f"dp = {dp * 1e3:.3g} mm ({through} particles through the gate), coupling "
                               f"pressure, solid.scheme = gray2001; the paper's Figs. 6-8 (qualitative)"))
    # At 1 mm the paper's gate is 4 particles thick, enough for the quadratic-fit solid (the scene pins gray2001
    # for its 2 mm runs, where the gate is 2 particles thick and the fit falls back to linear). quadratic_plain
    # brings its own solid.cfl, 0.25: gray2001's 0.5 suits Gray's gradient, not the fit.
    rungs.append(Rung("elastic_gate", "pressure_quadratic_dp1mm", "elastic_gate",
                      {"numerics.spacing": 0.001, "coupling.model": "pressure", "solid.scheme": "quadratic_plain",
                       **PAPER_SPAN},
                      end_time=0.14, snapshot_interval=0.02,
                      note="dp = 1 mm, coupling pressure, solid.scheme = quadratic_plain (quadratic-fit solid without "
                           "artificial stress)"))
    return rungs


def table(out_dir, rungs, summaries):
    """Tables of the coupled cases: Antoci's gate against the experiment, the paper's gate against Figs. 6-8."""
    antoci, paper = [], []
    for r in rungs:
        s = summaries.get(r.key)
        if s is None or not s["stable"]:
            continue
        model = (f"{s['settings'].get('coupling.model', '-')}, {s['settings'].get('solid.scheme', '-')}, "
                 f"{s['settings'].get('solid.clamp', 'fixed')} clamp")
        dp = s["settings"]["numerics.spacing"] * 1e3
        if r.scene == "antoci_gate" and s.get("tip_x_peak_m") is not None:
            material = (f"E {s['settings']['solid.young_modulus'] / 1e6:.3g} MPa, "
                        f"nu {s['settings']['solid.poisson_ratio']:.3g}")
            smoothed = (f"{1e3 * s['tip_x_peak_smoothed_m']:.1f} at {s['tip_x_peak_smoothed_time_s']:.3f} s"
                        if s.get("tip_x_peak_smoothed_m") is not None else "-")
            antoci.append(
                f"| {r.label} | {model}, {material} | {dp:.3g} | {1e3 * s['tip_x_peak_m']:.1f} | "
                f"{s['tip_x_peak_time_s']:.3f} | "
                f"{smoothed} | "
                f"{100 * s['tip_x_peak_error']:+.1f} % | {100 * s['tip_x_rms_over_exp_peak']:.1f} % | "
                f"{1e3 * s['tip_z_peak_m']:.1f} | {s['tip_z_peak_time_s']:.3f} | "
                f"{100 * s['tip_z_peak_error']:+.1f} % | "
                f"{100 * s['tip_z_rms_over_exp_peak']:.1f} % | {s['wall_time_s']:.0f} |")
        elif r.scene == "elastic_gate" and s.get("tip_dx_peak_m") is not None:
            checks = ", ".join(k[6:] for k in ("check_peak_in_paper_window", "check_springs_back",
                                                "check_energy_rises_and_falls") if s.get(k))
            paper.append(
                f"| {r.label} | {model} | {dp:.3g} | {1e3 * s['tip_dx_peak_m']:.2f} | {s['tip_dx_peak_time_s']:.3f} | "
                f"{100 * s['spring_back_fraction']:.0f} % | "
                f"{1e3 * s.get('strain_energy_peak_paper_width_j', s['strain_energy_peak_j']):.3g} | "
                f"{s['strain_energy_peak_time_s']:.3f} | {100 * s['strain_energy_fall_fraction']:.0f} % | "
                f"{checks or 'none'} | {s['wall_time_s']:.0f} |")
    lines = []
    if antoci:
        lines += ["", "### Antoci et al. 2007's gate: free end against the experiment, 0-0.4 s", "",
                  "Peaks: largest simulated value up to 0.4 s against the largest measured point (x: 46.0 mm at "
                  "0.162 s; z: 17.1 mm at 0.163 s); RMS at the 10 measured times, over the measured peak. Goal "
                  "(issue 4): peak within 5 %, RMS <= 10 %. Smoothed: the peak of the free end's x averaged over "
                  "10 ms (the motion's peak without a ringing on it; runs from before 2026-12-03 have none).", "",
                  "| run | coupling, solid | dp [mm] | x peak [mm] | at [s] | x peak smoothed [mm] | x peak error | "
                  "x RMS / peak | z peak [mm] | at [s] | z peak error | z RMS / peak | wall [s] |",
                  "|---|---|---|---|---|---|---|---|---|---|---|---|---|", *antoci, *antoci_peers()]
    if paper:
        lines += ["", "### The paper's elastic gate (Satake et al. Figs. 6-8)", "",
                  "dx peak: the free end's largest x displacement (negative: towards the dry side); spring-back: "
                  "how much of it is recovered by the end (0.14 s); strain energy of the gate, its peak, when, and "
                  "its fall by the end. Checks passed: the peak in the paper's 0.06-0.08 s, spring-back >= 20 %, "
                  "energy falls >= 20 % after its peak.", "",
                  "| run | coupling, solid | dp [mm] | dx peak [mm] | at [s] | spring-back | "
                  "strain energy peak, 36 mm gate [mJ] | "
                  "at [s] | fall | checks passed | wall [s] |",
                  "|---|---|---|---|---|---|---|---|---|---|---|", *paper]
    return lines


def antoci_peers():
    """Published and public numerical results on Antoci's gate (reference_data/antoci2007_numerical_peaks.csv, from
    ../shared/reference: maxima of digitised curves), as lines of the report beside ours."""
    lines = ["", "Beside ours, the published and public results on the same gate (reference_data/"
             "antoci2007_numerical_peaks.csv: the maxima of digitised curves; the papers' resolutions and some "
             "materials unknown):", "",
             "| result | method | resolution | x peak [mm] | at [s] | z peak [mm] |", "|---|---|---|---|---|---|"]
    for row in read_reference_table("antoci2007_numerical_peaks.csv"):
        lines.append(f"| {row['result']} | {row['method']} | {row['resolution']} | {row['max_dx_mm']} | "
                     f"{row['t_max_dx_s']} | {row['max_dy_mm']} |")
    return lines


_MATERIAL = ("solid.young_modulus", "solid.poisson_ratio")


def material_bands(curves):
    """The published materials' band at each spacing: curves [(rung, settings, t, y)] grouped by the spacing and by
    every other override of the rung (a relaxed or settled twin is not another material), each group's lower and
    upper envelope on its first curve's times. Returns [(spacing, [(E, nu), ...], t, lower, upper)] for the groups
    with two materials or more (the first curve of each material)."""
    groups = {}
    for rung, settings, t, y in curves:
        others = frozenset((k, str(v)) for k, v in rung.overrides.items()
                           if k not in _MATERIAL and k != "numerics.spacing")
        groups.setdefault((round(settings["numerics.spacing"], 9), others), {}).setdefault(
            (settings["solid.young_modulus"], settings["solid.poisson_ratio"]), (t, y))
    bands = []
    for (dp, _), by_material in groups.items():
        if len(by_material) < 2:
            continue
        t = next(iter(by_material.values()))[0]
        ys = np.array([np.interp(t, tc, yc) for tc, yc in by_material.values()])
        bands.append((dp, list(by_material), t, ys.min(axis=0), ys.max(axis=0)))
    return bands


def _free_end_plots(out_dir, rungs, summaries, plt):
    """Overlay of the free end against Antoci's data (every antoci_gate rung); the paper's Figs. 7-8 analogues."""
    made = []
    runs = [r for r in rungs if r.scene == "antoci_gate" and r.key in summaries]
    if runs:
        from ...answers.references import antoci_gate_tip
        fig, axes = plt.subplots(2, 1, figsize=(10, 6.5), sharex=True)
        for ax, comp, col in ((axes[0], "x", "tip_dx"), (axes[1], "z", "tip_dz")):
            te, ye = antoci_gate_tip(comp)
            ax.plot(te, ye * 1e3, "ko", label="Antoci et al. 2007 (experiment)")
            curves = []
            for i, r in enumerate(runs):
                rows = series_rows(out_dir, r)
                if rows is None:
                    continue
                t = np.array([float(x["time"]) for x in rows])
                y = np.array([float(x[col]) for x in rows])
                ax.plot(t, y * 1e3, "-" if "pressure" in r.label else "--", color=f"C{i}", label=r.label)
                curves.append((r, summaries[r.key]["settings"], t, y))
            for dp, materials, t, lower, upper in material_bands(curves):
                names = ", ".join(f"E {e / 1e6:.3g} / nu {nu:.3g}" for e, nu in materials)
                ax.fill_between(t, lower * 1e3, upper * 1e3, color="0.5", alpha=0.25,
                                label=f"material band, dp {dp * 1e3:.3g} mm ({names})")
            ax.set_ylabel(f"free-end {comp} displacement [mm]")
            ax.grid(True, alpha=0.3)
        axes[0].set_title("Antoci et al. 2007's rubber gate: free end, simulation against experiment")
        axes[1].set_xlabel("t [s]")
        axes[0].legend(fontsize=6.5, loc="upper left", bbox_to_anchor=(1.01, 1.0))
        made.append(save_panels(plt, fig, [], Path(out_dir) / "antoci_gate_tip.png"))
    runs = [r for r in rungs if r.scene == "elastic_gate" and r.key in summaries]
    if runs:
        fig, axes = plt.subplots(2, 1, figsize=(7, 6.5), sharex=True)
        for i, r in enumerate(runs):
            rows = series_rows(out_dir, r)
            if rows is None:
                continue
            t = np.array([float(x["time"]) for x in rows])
            # the slab is uniform across y: its energy for the paper's 36 mm gate
            span = summaries[r.key].get("geometry_effective", {}).get("span_m", PAPER_GATE_WIDTH_M)
            axes[0].plot(t, [1e3 * float(x["tip_dx"]) for x in rows], "-", color=f"C{i}", label=f"{r.label} x")
            axes[0].plot(t, [1e3 * float(x["tip_dz"]) for x in rows], ":", color=f"C{i}", label=f"{r.label} z")
            axes[1].plot(t, [1e3 * PAPER_GATE_WIDTH_M / span * float(x["strain_energy"]) for x in rows], "-",
                         color=f"C{i}", label=r.label)
        axes[0].axvspan(0.06, 0.08, color="0.9", label="paper: largest deflection")
        axes[0].set_ylabel("free-end displacement [mm]")
        axes[0].set_title("The paper's elastic gate: free end (cf. Fig. 7) and strain energy (cf. Fig. 8)")
        axes[1].set_ylabel("strain energy of the 36 mm gate [mJ]")
        axes[1].set_xlabel("t [s]")
        made.append(save_panels(plt, fig, axes, Path(out_dir) / "elastic_gate_tip_and_energy.png", legend_size=7))
    return made


def _frame_plots(out_dir, rungs, summaries, plt):
    """Frames of the finest elastic_gate run with snapshots, like the paper's Fig. 6: water and gate particles of
    the slab's middle layer in the x-z plane, the gate coloured by sigma_zz (the paper's sigma^22)."""
    made = []
    runs = [r for r in rungs if r.scene == "elastic_gate" and r.key in summaries and summaries[r.key]["stable"]]
    for r in runs:
        snaps = sorted((Path(out_dir) / "runs" / r.case / r.label / "snapshots").glob("snapshot_*.npz"))
        if len(snaps) < 2:
            continue
        frames = [np.load(p) for p in snaps]
        fig, axes = plt.subplots(2, (len(frames) + 1) // 2, figsize=(3.2 * ((len(frames) + 1) // 2), 3.6),
                                 sharex=True, sharey=True, squeeze=False)
        dp = summaries[r.key]["settings"]["numerics.spacing"]
        scale = max(max(float(np.percentile(np.abs(f["solid_sigma_zz"][f["solid_movable"]]), 98)) for f in frames),
                    1.0)
        for ax, f in zip(axes.flat, frames):
            fp, sp = f["fluid_position"], f["solid_position"]
            y_mid = np.median(sp[:, 1])
            fm = np.abs(fp[:, 1] - y_mid) < 0.5 * dp
            sm = (np.abs(sp[:, 1] - y_mid) < 0.5 * dp) & f["solid_movable"]
            szz = f["solid_sigma_zz"][sm]
            ax.scatter(fp[fm, 0] * 1e3, fp[fm, 2] * 1e3, s=2, c="C0", lw=0)
            sc = ax.scatter(sp[sm, 0] * 1e3, sp[sm, 2] * 1e3, s=4, c=szz, cmap="coolwarm", vmin=-scale,
                            vmax=scale, lw=0)
            ax.set_xlim(-60.0, 30.0)
            ax.set_title(f"t = {float(f['time']):.2f} s", fontsize=8)
            ax.set_aspect("equal")
        for ax in axes.flat[len(frames):]:
            ax.axis("off")
        fig.colorbar(sc, ax=axes.ravel().tolist(), shrink=0.6, label="sigma_zz [Pa]")
        fig.suptitle(f"elastic_gate {r.label}: middle layer, gate by sigma_zz (cf. the paper's Fig. 6)", fontsize=9)
        name = f"elastic_gate_frames_{r.label}.png"
        fig.savefig(Path(out_dir) / name, dpi=110)
        plt.close(fig)
        made.append(name)
    return made


def plot(out_dir, rungs, summaries, plt):
    """antoci_gate_tip.png, elastic_gate_tip_and_energy.png and the elastic gate's frames, where runs have them."""
    return _free_end_plots(out_dir, rungs, summaries, plt) + _frame_plots(out_dir, rungs, summaries, plt)
