"""Where the default scheme's end effect sits (scenes/clamped_plate.py's strips and scenes/cantilever_loaded.py's
beam, each judged by its scene's evaluate against FE for itself): the error over L / t split into a section part, a
shear-like part and a clamp offset (validation/end_effect.py); a table and a plot."""
import math
from pathlib import Path

import numpy as np

from ..report_tools import grid_table, save_panels
from ..rung import Rung


# Where the default scheme's end effect sits (docs/validation/OPEN.md, 6: the cantilever's error falls as H / L):
# one plate, 4 particles through (t = 0.02 m, dp = 5 mm, E = 0.1 GPa, nu = 0.3: the small plate's), clamped at
# both ends (no free end) and clamped at one (a cantilever), over L / t, each against plane-strain FE for itself.
# A clamp acting as if the strip were longer by delta adds 8 delta / L to the first and 4 delta / L to the second
# (scenes/cases/clamped_plate.py); what the cantilever has beyond that is its free end's. The loads scale as (t / L)^4 so
# every strip deflects as much relative to its thickness (0.5 % clamped at both ends, 2 % as a cantilever: linear).
# The runs go 5 periods of the first mode: the load ramps in over 2 and the critical damping settles it.
CLAMP_EFFECT_RATIOS = {"clamped_clamped": (5, 10, 15, 20, 30), "clamped_free": (5, 10, 15, 20)}
CLAMP_EFFECT_PLATE = {"geometry.thickness": 0.02, "numerics.spacing": 0.005, "solid.young_modulus": 1.0e8}
CLAMP_EFFECT_BEAM_RATIOS = (5, 10, 15, 20)
CLAMP_EFFECT_LOAD = {"clamped_clamped": 1000.0 * 9.81 * 0.1, "clamped_free": 1000.0 * 9.81 * 0.01}   # Pa at L/t 10


def rungs():
    from ...scenes.cases.clamped_plate import FIRST_MODE_BETA_L
    t, e, nu, rho = 0.02, 1.0e8, 0.3, 2700.0
    rungs = []
    for supports, ratios in CLAMP_EFFECT_RATIOS.items():
        for ratio in ratios:
            span = ratio * t
            scale = (10.0 / ratio) ** 4
            pressure = CLAMP_EFFECT_LOAD[supports] * scale
            gravity = -9.81 * scale * CLAMP_EFFECT_LOAD[supports] / CLAMP_EFFECT_LOAD["clamped_clamped"]
            omega = (FIRST_MODE_BETA_L[supports] / span) ** 2 * math.sqrt(e * t ** 2 / (12.0 * (1.0 - nu * nu) * rho))
            rungs.append(Rung("clamp_effect", f"{supports}_L_over_t_{ratio}", "clamped_plate",
                              {**CLAMP_EFFECT_PLATE, "geometry.span": span, "geometry.supports": supports,
                               "geometry.load_pressure": pressure, "scene.gravity": (0.0, 0.0, gravity)},
                              end_time=5.0 * 2.0 * math.pi / omega, quick=supports == "clamped_free" and ratio == 5,
                              bound=0.1, note=f"L / t = {ratio}, 4 particles through, {supports}, the default scheme"))
    # the same in 3D, static: the cantilever_shapes beam (4 x 6 mm, 4 particles through, nu = 0.3) under a linear
    # dead load (alpha = 0.05), whose frequency error is a + b H / L (docs/validation/OPEN.md, 6); against 3D FE
    # at the free end's particle layer (validation/end_effect.py)
    for ratio in CLAMP_EFFECT_BEAM_RATIOS:
        rungs.append(Rung("clamp_effect", f"beam3d_L_over_H_{ratio}", "cantilever_loaded",
                          {"geometry.length": ratio * 0.004, "solid.poisson_ratio": 0.3,
                           "geometry.load_parameter": 0.05}, end_time=0.25 * (ratio / 10.0) ** 2,
                          note=f"L / H = {ratio}, the cantilever_shapes beam with nu = 0.3 under a linear dead load, "
                               "the default scheme"))
    return rungs


_PARTS = {}


def _parts(rungs, summaries, out_dir):
    """validation/end_effect.decompose for case clamp_effect's rungs (about 15 s of FE), once per set of results:
    the table and the plot share it."""
    runs = [r for r in rungs if r.case == "clamp_effect"]
    key = tuple((r.key, (summaries.get(r.key) or {}).get("error_signed")) for r in runs)
    if key not in _PARTS:
        from ..end_effect import decompose
        _PARTS[key] = decompose(runs, summaries, out_dir)
    return _PARTS[key]


def plot(out_dir, rungs, summaries, plt):
    """The strips' errors against FE at the probe over t / L, each support with its fit (a + g phi + d s)."""
    if not any(summaries.get(r.key) for r in rungs if r.case == "clamp_effect"):
        return []
    parts = _parts(rungs, summaries, out_dir)
    fig, ax = plt.subplots(figsize=(6, 4.5))
    for color, (sup, entry) in zip(("C0", "C3", "C2", "C1"), parts.items()):
        ratio, err, phi, sens = (np.array(c) for c in zip(*entry["rows"]))
        ax.plot(1.0 / ratio, 100 * err, "s" if sup.startswith("beam3d") else "o", color=color,
                label=f"{sup}: SPH against FE at the probe")
        if "fit" in entry:
            a, g, d, _ = entry["fit"]
            ax.plot(1.0 / ratio, 100 * (a + g * phi + d * sens), "-", color=color,
                    label=f"fit {100 * a:+.2f} % + {100 * g:.0f} % phi + {d:.3f} s")
        if "fit_length" in entry:
            a, b, _ = entry["fit_length"]
            ax.plot(1.0 / ratio, 100 * (a + b / ratio), "-", color=color, label=f"fit {100 * a:+.2f} % + "
                                                                               f"{100 * b:.1f} % H / L")
    ax.set_xlabel("t / L (H / L)")
    ax.set_ylabel("deflection error against FE [%]")
    ax.set_title("The default scheme, 4 particles through: error over the strip's length")
    ax.set_xlim(left=0.0)
    return [save_panels(plt, fig, [ax], Path(out_dir) / "clamp_effect.png", legend_size=7)]


def table(out_dir, rungs, summaries):
    """The default scheme's strip over L / t on both supports, and its error split into a section part, a
    shear-like part and a clamp offset (validation/end_effect.py)."""
    runs = [r for r in rungs if r.case == "clamp_effect"]
    if not any(summaries.get(r.key) for r in runs):
        return []
    parts = _parts(runs, summaries, out_dir)
    beams = [r for r in runs if r.scene == "cantilever_loaded"]
    runs = [r for r in runs if r.scene != "cantilever_loaded"]
    ratios = sorted({int(r.label.rsplit("_", 1)[1]) for r in runs})
    supports = list(dict.fromkeys(r.label.split("_L_over_t_")[0] for r in runs))

    def cell(ratio, sup):
        s = summaries.get(f"clamp_effect/{sup}_L_over_t_{ratio}")
        if s is None:
            return "not run" if any(r.label == f"{sup}_L_over_t_{ratio}" for r in runs) else "-"
        if s.get("error_signed") is None:
            return "did not finish"
        row = next((x for x in parts.get(sup, {}).get("rows", []) if x[0] == ratio), None)
        at_probe = f"; at the probe {100 * row[1]:+.2f} %, phi {row[2]:.3f}, s {row[3]:.3f}" if row else ""
        return f"{100 * s['error_signed']:+.2f} %{at_probe} ({s['wall_time_s']:.0f} s)"
    lines = grid_table("## Where the end effect sits: the clamp, the free end or the section (clamp_effect)",
                  "The default scheme as it is, 4 particles through a strip (t = 0.02 m, dp = 5 mm, E = 0.1 GPa, "
                  "nu = 0.3, plane strain) clamped at both ends (mid-span) or at one (a cantilever: free end, x = L - "
                  "dp / 2), each settled under a uniform pressure and its own weight scaled as (t / L)^4, against "
                  "plane-strain FE for itself (the summary's error: FE at the centre, elements of t / 8, within 0.13 % "
                  "of t / 32 at L / t = 5). Then, by validation/end_effect.py: the error against FE (t / 16) read "
                  "where the probe's particles are, the shear fraction phi = 1 - w_EB / w_FE, and the sensitivity s "
                  "of the deflection to each clamp face moving back by one spacing. + is softer than FE. Wall time "
                  "in brackets.", "L / t", [(n, str(n)) for n in ratios], [(x, x) for x in supports], cell)
    for sup in supports:
        entry = parts.get(sup, {})
        for key, what in (("fit", "with a clamp offset d (spacings)"), ("fit_no_offset", "without")):
            if key in entry:
                a, g, d, res = entry[key]
                offset = f" + {d:.3f} s" if d is not None else ""
                lines += [f"- {sup}, {what}: error = {100 * a:+.2f} % + {100 * g:.1f} % x phi{offset} (largest "
                          f"residual {100 * max(abs(res)):.3f} points over {len(res)} rungs)."]
    if beams:
        lines += ["", "The same in 3D, static: the cantilever_shapes beam (4 particles through its 4 mm, 6 mm wide, "
                  "nu = 0.3) under a linear dead load (alpha = 0.05, scene cantilever_loaded), "
                  "the free end's particle layer against the elastica (the summary's error) and against 3D FE at the "
                  "layer's particles (elements of dp / 2, validation/end_effect.py; within 0.14 % of elements of dp at "
                  "L / H = 5, 0.07 % at 10).", "",
                  "| beam | L / H | vs the elastica | vs 3D FE at the layer | phi | wall [s] |",
                  "|---|---|---|---|---|---|"]
        for r in beams:
            s = summaries.get(r.key)
            name, ratio = r.label.split("_L_over_H_")
            if s is None:
                lines.append(f"| {name} | {ratio} | not run | | | |")
                continue
            row = next((x for x in parts.get(name, {}).get("rows", []) if round(x[0]) == int(ratio)), None)
            lines.append(f"| {name} | {ratio} | {100 * s['error_signed']:+.2f} % | "
                         f"{'-' if row is None else f'{100 * row[1]:+.2f} %'} | "
                         f"{'-' if row is None else f'{row[2]:.4f}'} | {s['wall_time_s']:.0f} |")
        for name in dict.fromkeys(r.label.split("_L_over_H_")[0] for r in beams):
            entry = parts.get(name, {})
            if "fit_length" in entry:
                a, b, res = entry["fit_length"]
                lines += ["", f"- {name}: error = {100 * a:+.2f} % {100 * b:+.1f} % x H / L (largest residual "
                              f"{100 * max(abs(res)):.3f} points over {len(res)} rungs); in frequency (f ~ w^-1/2) "
                              f"{-50 * a:+.2f} % {-50 * b:+.1f} % x H / L."]
    return lines
