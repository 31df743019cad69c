"""REPORT.md and PNG plots of `sph-fsi validate`, made from the rungs' summary.json files (no simulation here)."""
import csv
import datetime
import json
import math
from pathlib import Path

import numpy as np

from .references import lobovsky_front, read_reference_csv
from . import spheric2
from .cases import CANTILEVER_CASES
from ..scenes.elastic_gate import PAPER_GATE_WIDTH_M


def _series_rows(out_dir, rung):
    """A rung's timeseries.csv as a list of rows (dicts of strings), None if it was not run."""
    path = Path(out_dir) / "runs" / rung.case / rung.label / "timeseries.csv"
    if not path.is_file():
        return None
    with path.open() as fh:
        return list(csv.DictReader(fh))


def _fmt(x, spec=".3g"):
    if x is None or (isinstance(x, float) and not math.isfinite(x)):
        return "-"
    return format(x, spec)


def _save_panels(plt, fig, axes, path, legend_size=None):
    """A figure's panels gridded (and their legends drawn at `legend_size`), laid out, saved at 120 dpi and closed;
    returns the file's name."""
    for a in axes:
        a.grid(True, alpha=0.3)
        if legend_size:
            a.legend(fontsize=legend_size)
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)
    return Path(path).name


def _row(rung, s):
    if s is None:
        return f"| {rung.case} | {rung.label} | not run | | | | | | | | | |"
    d = s["diverged"]
    stable = "yes" if s["stable"] else f"no: {d['check']} at {d['time']:.4g} s"
    measured = ref = "-"
    if s.get("frequency_hz") is not None:
        measured = f"{s['frequency_hz']:.3f} ± {s['frequency_uncertainty_hz']:.3f} Hz"
        ref = f"{s['reference_hz']:.3f} Hz ({s['fe3d_source']})"
    elif s.get("midspan_deflection_m") is not None:
        measured = f"mid-span {1e6 * s['midspan_deflection_m']:.2f} um"
        ref = f"FE {1e6 * s['reference_midspan_deflection_m']:.2f} um"
    elif s.get("free_end_deflection_m") is not None:
        measured = f"free end {1e6 * s['free_end_deflection_m']:.2f} um"
        ref = f"FE {1e6 * s['reference_free_end_deflection_m']:.2f} um" if s.get("reference_free_end_deflection_m") \
            else "-"
    elif s.get("elastica_deflection_m") is not None:
        measured = f"free end {1e3 * s['tip_deflection_m']:.3f} mm down"
        ref = f"elastica {1e3 * s['elastica_deflection_m']:.3f} mm"
    elif s.get("tip_deflection_m") is not None:
        measured = f"free end {1e3 * s['tip_deflection_m']:.3f} mm"
        ref = f"FE {1e3 * s['reference_tip_deflection_m']:.3f} mm" if s.get("reference_tip_deflection_m") else "-"
    elif s.get("floor_pressure_pa") is not None:
        measured = f"floor p {s['floor_pressure_pa']:.1f} Pa"
        ref = f"rho g H = {s['reference_floor_pressure_pa']:.1f} Pa"
    elif s.get("front_rms_relative_error") is not None:
        measured = f"front RMS {100 * s['front_rms_relative_error']:.1f} %"
        ref = "Lobovsky et al. 2014, T >= 1" if s.get("builder") == "lobovsky_dam_break" else "Martin & Moyce 1952"
    elif s.get("tip_x_peak_m") is not None:
        measured = f"tip x peak {1e3 * s['tip_x_peak_m']:.1f} mm at {s['tip_x_peak_time_s']:.3f} s"
        ref = f"Antoci 2007: {1e3 * s['tip_x_exp_peak_m']:.1f} mm at {s['tip_x_exp_peak_time_s']:.3f} s"
    elif s.get("tip_dx_peak_m") is not None:
        measured = f"tip dx peak {1e3 * s['tip_dx_peak_m']:.2f} mm at {s['tip_dx_peak_time_s']:.3f} s"
        ref = "paper: peak at 0.06-0.08 s"
    err = f"{100 * s['error']:.2f} %" if s.get("error") is not None else "-"
    if s.get("error_signed") is not None:
        err = f"{100 * s['error_signed']:+.2f} %"   # the sign says soft (+, deflects more) or stiff
    if s.get("frequency_hz") is not None and s.get("reference_hz") and s.get("error") is not None:
        err = f"{100 * (s['frequency_hz'] / s['reference_hz'] - 1.0):+.2f} %"   # the sign says stiff or soft
    m = s.get("machine", {})
    moving = s["particles"].get("solid", 0) + s["particles"].get("fluid", 0)
    steps = s["solid_steps"] + s.get("fluid_steps", 0)
    return (f"| {rung.case} | {rung.label} | {s['settings']['numerics.spacing'] * 1e3:.3g} | "
            f"{moving} | {steps} | {s['wall_time_s']:.1f} | "
            f"{_fmt(s['particle_steps_per_second'] / 1e6, '.3f')} | {measured} | {ref} | {err} | {stable} | "
            f"{m.get('numba_threads', '-')}, {m.get('commit', '-')} |")


def _answer(s):
    """The number a run is judged on, as (value, unit text, scale to that unit): the frequency, a static deflection or a
    gate's peak."""
    for key, unit, scale in (("frequency_hz", "Hz", 1.0), ("midspan_deflection_m", "um", 1e6),
                             ("tip_x_peak_m", "mm", 1e3), ("tip_dx_peak_m", "mm", 1e3),
                             ("tip_deflection_m", "mm", 1e3)):
        if s.get(key) is not None:
            return s[key], unit, scale
    return None, "", 1.0


def _error_text(s):
    e = s.get("error_signed", s.get("error"))
    if s.get("frequency_hz") is not None and s.get("reference_hz"):
        e = s["frequency_hz"] / s["reference_hz"] - 1.0
    return "-" if e is None else f"{100 * e:+.2f} %"


def _solid_pressure_extra(out_dir, rungs, summaries):
    """Each solid_pressure run beside its explicit counterpart (read from the counterpart case's own report
    directory next to this one, runs/CASE/LABEL/summary.json): the answer, its error, the steps and the wall time."""
    runs = [r for r in rungs if r.case == "solid_pressure"]
    if not runs:
        return []
    lines = ["", "## The implicit pressure against the explicit one", "",
             "Each run with the default scheme's pressure advanced implicitly (solid/implicit_pressure.py; the step set "
             "by the shear waves) beside the same run with it explicit (the counterpart's own report, where it was "
             "validated). Moved: the answer's relative change. Wall times: each run's own host state (the column "
             "`threads, commit` above and the counterpart's report); compare them as orders, and the same-process "
             "ratio in docs/performance/BENCH.md.", "",
             "| run | explicit: answer, error | solid steps | wall [s] | implicit: answer, error | solid steps | "
             "wall [s] | moved | fewer steps | CG iterations per step |", "|---|---|---|---|---|---|---|---|---|---|"]
    for r in runs:
        new = summaries.get(r.key)
        old = None
        if r.counterpart:
            case, label = r.counterpart.split("/")
            path = Path(out_dir).parent / case / "runs" / case / label / "summary.json"
            old = json.loads(path.read_text()) if path.is_file() else None

        def cells(s):
            if s is None:
                return ["not run", "", ""]
            value, unit, scale = _answer(s)
            answer = "-" if value is None else f"{scale * value:.4g} {unit}"
            return [f"{answer}, {_error_text(s)}", f"{s['solid_steps']}", f"{s['wall_time_s']:.0f}"]

        moved = steps = "-"
        if new is not None and old is not None:
            a, b = _answer(old)[0], _answer(new)[0]
            if a and b is not None:
                moved = f"{100 * (b / a - 1.0):+.2f} %"
            if new["solid_steps"]:
                steps = f"{old['solid_steps'] / new['solid_steps']:.2f}x"
        solve = (new or {}).get("solid_pressure_solve") or {}
        iterations = _fmt(solve.get("iterations_per_step"), ".1f")
        label = r.label if r.counterpart else f"{r.label} (no explicit run)"
        lines.append(f"| {label} | " + " | ".join(cells(old) + cells(new)) + f" | {moved} | {steps} | {iterations} |")
    return lines


def _large_deflection_extra(rungs, summaries):
    """The cantilever under a dead tip load, linear to large rotation, against the elastica (large_deflection)."""
    rows = []
    for r in rungs:
        s = summaries.get(r.key)
        if r.case != "large_deflection":
            continue
        if s is None or s.get("elastica_deflection_m") is None:
            rows.append(f"| {r.label} | not run | | | | | | |")
            continue
        st = s["settings"]
        pull = f"{100 * s['pull_back_error']:+.1f} %" if s.get("pull_back_error") is not None else "-"
        rows.append(f"| {r.label} | {st['solid.scheme']}, {st['solid.clamp']} clamp | "
                    f"{st['geometry.load_parameter']:g} | {s['elastica_tip_rotation_deg']:.1f} | "
                    f"{1e3 * s['tip_deflection_m']:.3f} / {1e3 * s['elastica_deflection_m']:.3f} | "
                    f"{100 * s['error_signed']:+.2f} % | {pull} | {s['wall_time_s']:.0f} |")
    if not rows:
        return []
    return ["", "### The cantilever under a dead load: linear to large rotation, against the elastica", "",
            "The paper's beam (4 x 6 mm section, 4 particles through) at rest under a distributed dead load q along "
            "its length, alpha = q L^3 / (E I), settled by damping (scenes/cantilever_loaded.py). The free end's "
            "settled deflection (down) against the elastica of the same load (Euler-Bernoulli with exact rotation, no "
            "shear; validation/references.py, checked against Bisshopp & Drucker 1945); pull-back: how far the free "
            "end moves towards the clamp, against the elastica's. L/H = 10 except `short_*` (L/H = 5, the CI rung). "
            "What the 3D beam adds to the elastica (shear, the width, the clamp) is about the same at every load: the "
            "change of the error from alpha = 0.05 (linear) to 2 and 4 (the free end turning 18 and 34 degrees, the "
            "root strained 5 and 10 %) is what large rotation does to the scheme.", "",
            "| run | solid | alpha | elastica rotation [deg] | deflection / elastica [mm] | error | pull-back error | "
            "wall [s] |", "|---|---|---|---|---|---|---|---|", *rows]


def _cantilever_extra(rungs, summaries):
    lines = []
    for r in rungs:
        s = summaries.get(r.key)
        if s is None or r.case not in CANTILEVER_CASES:
            continue
        if s.get("frequency_hz") is None:
            continue
        lines.append(
            f"| {r.key} | {_fmt(s.get('error_vs_fe3d_percent'), '+.2f')} | "
            f"{_fmt(s.get('error_vs_euler_bernoulli_percent'), '+.2f')} | {_fmt(s.get('error_vs_eq15_percent'), '+.2f')} | "
            f"{_fmt(s.get('damping_ratio'), '.4f')} | {_fmt(s.get('energy_max_period_growth'), '+.2e')} | "
            f"{_fmt(s.get('max_sideways_speed_over_tip_speed'), '.2e')} | {_fmt(s.get('periods'), '.1f')} |")
    if not lines:
        return []
    return ["", "### Cantilever: against each reference, damping, energy and the sideways mode", "",
            "Errors in % against the 3D elasticity value (fe3d), Euler-Bernoulli beam theory and the paper's eq. (15) "
            "(plane-strain plate). Damping ratio from the decay of the tip's peaks. Energy: largest growth of the "
            "period-averaged kinetic + strain energy from one period to the next (negative: it decays). Sideways: "
            "largest mean sideways speed of the free end after the first period, over Vf.", "",
            "| run | vs fe3d | vs beam | vs eq. (15) | damping ratio | energy growth / period | sideways / Vf | periods |",
            "|---|---|---|---|---|---|---|---|", *lines]


def _grid(title, text, row_name, rows, col_names, cell):
    """A section with one table: a row per entry of `rows`, a column per (label, key) of `col_names`, each cell
    cell(row, key)."""
    lines = ["", title, "", text, "", f"| {row_name} | " + " | ".join(label for label, _ in col_names) + " |",
             "|---|" + "---|" * len(col_names)]
    for row, row_label in rows:
        lines.append(f"| {row_label} | " + " | ".join(cell(row, key) for _, key in col_names) + " |")
    return lines


def _solid_static_extra(rungs, summaries):
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
    return _grid("## The solid alone under a prescribed load (solid_static)",
                 "The hydrostatic-plate benchmark's plate (1 m x 0.05 m aluminium, clamped at both ends, plane strain) "
                 "under the water's exact pressure and its own weight, settled; the mid-span, mid-thickness deflection "
                 "against the project's plane-strain FE value (validation/fe_reference.py). + is softer than FE. "
                 "Wall time in brackets.", "scheme", [(x, x) for x in schemes],
                 [(f"t/dp = {n}", n) for n in layers], cell)


_CLAMP_EFFECT_PARTS = {}


def _clamp_effect_parts(rungs, summaries, out_dir):
    """validation/end_effect.decompose for case clamp_effect's rungs (about 15 s of FE), once per set of results:
    the table and the plot share it."""
    runs = [r for r in rungs if r.case == "clamp_effect"]
    key = tuple((r.key, (summaries.get(r.key) or {}).get("error_signed")) for r in runs)
    if key not in _CLAMP_EFFECT_PARTS:
        from .end_effect import decompose
        _CLAMP_EFFECT_PARTS[key] = decompose(runs, summaries, out_dir)
    return _CLAMP_EFFECT_PARTS[key]


def _clamp_effect_plot(out_dir, rungs, summaries, plt):
    """The strips' errors against FE at the probe over t / L, each support with its fit (a + g phi + d s)."""
    if not any(summaries.get(r.key) for r in rungs if r.case == "clamp_effect"):
        return []
    parts = _clamp_effect_parts(rungs, summaries, out_dir)
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
    ax.grid(True, alpha=0.3)
    ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(Path(out_dir) / "clamp_effect.png", dpi=120)
    plt.close(fig)
    return ["clamp_effect.png"]


def _clamp_effect_extra(out_dir, rungs, summaries):
    """The default scheme's strip over L / t on both supports, and its error split into a section part, a
    shear-like part and a clamp offset (validation/end_effect.py)."""
    runs = [r for r in rungs if r.case == "clamp_effect"]
    if not any(summaries.get(r.key) for r in runs):
        return []
    parts = _clamp_effect_parts(runs, summaries, out_dir)
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
    lines = _grid("## Where the end effect sits: the clamp, the free end or the section (clamp_effect)",
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
        lines += ["", "The same in 3D, static: the cantilever_shapes beam (4 particles through its 4 mm, 6 mm wide, nu = 0.3) "
                  "under a linear dead load (alpha = 0.05, scene cantilever_loaded), "
                  "the free end's particle layer against the elastica (the summary's error) and against 3D FE at the "
                  "layer's particles (elements of dp / 2, validation/end_effect.py; within 0.14 % of elements of dp at "
                  "L / H = 5, 0.07 % at 10).", "",
                  "| beam | L / H | vs the elastica | vs 3D FE at the layer | phi | wall [s] |", "|---|---|---|---|---|---|"]
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


def _cantilever_shapes_extra(rungs, summaries):
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
    return _grid("## The default scheme's cantilever over shapes and materials (cantilever_shapes)",
                 "`quadratic_gradient` with the mirrored clamp, 4 particles through the paper's 4 x 6 mm section (dp = "
                 "1 mm), 2.25 periods from the first mode's velocity (eq. (12)); the first vertical frequency against "
                 "the project's 3D FE for the same shape and nu (reference_data/cantilever_fe3d_nondimensional.csv, "
                 "meshes H/2, H/4, H/6 extrapolated). - is softer than FE. Wall time in brackets.", "nu",
                 [(nu, f"{nu:g}") for nu in poisson], [(f"L/H = {n}", n) for n in ratios], cell)


_HYDROSTATIC_PLATE_LIGHT = (
    " The light_* rungs are the small plate at rho_s = 300 kg/m^3 (the water's added mass about 10x the plate's), whose "
    "staggered push alternates from fluid step to fluid step; *_relaxed_* hold coupling.relaxation w of each new push "
    "(0.1 there, 0.3 on the scaled plate), which damps that alternation below w = 2 / (1 + m_a / m_s) "
    "(docs/validation/OPEN.md, 1.0).")


def _hydrostatic_plate_extra(rungs, summaries):
    """The coupled plate: settled deflection against FE, the water's load against its weight, each rung's cost."""
    lines = []
    for r in rungs:
        s = summaries.get(r.key)
        if r.case != "hydrostatic_plate" or s is None or s.get("water_load_n") is None:
            continue
        dp = s["settings"]["numerics.spacing"]
        t = s["settings"]["geometry.thickness"]
        # the same plate under the water's exact pressure, where the case has it (small_loaded_*)
        loaded = summaries.get(r.key.replace("/small_t_over", "/small_loaded_t_over"))
        alone = (f"{100 * loaded['error_signed']:+.2f} % | "
                 f"{100 * (s['midspan_deflection_m'] / loaded['midspan_deflection_m'] - 1.0):+.2f} %"
                 if loaded and "/small_t_over" in r.key else "- | -")
        lines.append(
            f"| {r.label} | {t / dp:.0f} | {s['settings']['solid.young_modulus'] / 1e9:.4g} | "
            f"{1e6 * s['midspan_deflection_m']:.2f} | {1e6 * s['reference_midspan_deflection_m']:.2f} | "
            f"{100 * s['error_signed']:+.2f} % | {alone} | {_fmt(1e6 * s['midspan_deflection_swing_m'], '.3g')} | "
            f"{' / '.join(f'{1e6 * w:.1f}' for w in s.get('midspan_deflection_blocks_m', []))} | "
            f"{s['water_load_n']:.1f} / {s['water_weight_n']:.1f} N ({100 * s['water_load_error']:+.2f} %) | "
            f"{' / '.join(f'{f:.4g}' for f in s.get('water_load_blocks_n', []))} | "
            f"{s['water_load_all_n']:.1f} N | {s['particles'].get('fluid')} + {s['particles'].get('solid')} | "
            f"{s['solid_steps']} + {s['fluid_steps']} | {s['wall_time_s']:.0f} |")
    if not lines:
        return []
    return ["", "## Water at rest on a clamped plate (hydrostatic_plate)", "",
            "Fourey et al. 2017's benchmark, coupled (scenes/hydrostatic_plate.py): the settled mid-span deflection "
            "against the project's plane-strain FE value for the same plate under rho_f g H and its own weight (+: "
            "softer than FE) over the settled window (the run's last half), its swing there and the means of the window's "
            "three thirds (a trend says it has not settled), and the water's vertical force on the plate's span "
            "against the column's weight rho_f g H L W (its thirds; with the clamps' share: on the whole solid). Peers at 10 "
            "particles through (../shared/reference/hydrostatic_plate_fourey2017.csv): DualSPHysics about 8.5 %, "
            "TrixiParticles about 10 %; SPHinXsys +57 % at 4. The small plate (small_*: 0.2 m x 0.02 m, E = 0.1 GPa, "
            "under 0.1 m of water) also runs without water under the exact pressure rho_f g H (small_loaded_*): "
            "that plate against FE is the solid's error, the coupled one against it the load transfer's." + _HYDROSTATIC_PLATE_LIGHT, "",
            "| run | t/dp | E [GPa] | deflection [um] | FE [um] | error | loaded alone vs FE | coupled vs loaded | "
            "swing [um] | thirds [um] | water on span / weight | thirds [N] | on whole solid | particles (fluid + "
            "solid) | steps (solid + fluid) | wall [s] |",
            "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|", *lines]


def _gate_static_extra(rungs, summaries):
    """Antoci's gate held static: coupled, under the exact pressure and FE, per spacing and scheme; the two ratios
    that separate the load transfer from the bending."""
    spacings = list(dict.fromkeys(r.label.rsplit("_", 1)[1] for r in rungs if r.case == "gate_static"))
    schemes = (("quadratic_plain_artificial_stress", "coupled", "loaded"),
               ("quadratic_gradient, mirrored clamp (default)", "coupled_gradient_mirrored", "loaded_gradient_mirrored"),
               ("the default, the push relaxed (coupling.relaxation 0.15)", "coupled_gradient_mirrored_relaxed",
                "loaded_gradient_mirrored"),
               ("the same, the water's density tolerance 0.3 %", "coupled_gradient_mirrored_relaxed_tol0.3pct",
                "loaded_gradient_mirrored"),
               ("the default, the water built compressed with its walls (geometry.water_start)",
                "coupled_gradient_mirrored_compressed", "loaded_gradient_mirrored"),
               ("the default as it is (implicit pressure), built compressed, to 0.6 s, the fluid's step 1 ms",
                "coupled_default_compressed_fluid_dt1ms", "loaded_gradient_mirrored"),
               ("the same, the fluid's step 0.5 ms", "coupled_default_compressed_fluid_dt0.5ms",
                "loaded_gradient_mirrored"))
    lines = []
    for label in spacings:
        for scheme, coupled_kind, loaded_kind in schemes:
            coupled, loaded = (s if s and s.get("tip_deflection_m") is not None else None for s in (
                summaries.get(f"gate_static/{kind}_{label}") for kind in (coupled_kind, loaded_kind)))
            if not any((coupled, loaded)) or (coupled is None and coupled_kind not in ("coupled",
                                                                                   "coupled_gradient_mirrored")):
                continue   # a variant not run at this spacing
            fe = next((s["reference_tip_deflection_m"] for s in (coupled, loaded)
                       if s and s.get("reference_tip_deflection_m")), None)

            def mm(s):
                return "not run" if s is None else f"{1e3 * s['tip_deflection_m']:.3f} ({s['wall_time_s']:.0f} s)"

            transfer = (f"{100 * (coupled['tip_deflection_m'] / loaded['tip_deflection_m'] - 1):+.2f} %"
                        if coupled and loaded else "-")
            bending = (f"{100 * loaded['error_signed']:+.2f} %" if loaded and loaded.get("error_signed") is not None
                       else "-")
            coupled_error = (f"{100 * coupled['error_signed']:+.2f} %"
                             if coupled and coupled.get("error_signed") is not None else "-")
            swing = f"{1e3 * coupled['tip_deflection_swing_m']:.3f}" if coupled else "-"
            load = (f"{1e3 * coupled['water_load_n']:.1f} / {1e3 * coupled['water_load_exact_n']:.1f} mN "
                    f"({100 * coupled['water_load_error']:+.1f} %)"
                    if coupled and coupled.get("water_load_n") is not None else "-")
            lines.append(f"| {label} | {scheme} | {mm(coupled)} | {swing} | {load} | {mm(loaded)} | "
                         f"{_fmt(fe and 1e3 * fe, '.3f')} | {coupled_error} | {transfer} | {bending} |")
    if not lines:
        return []
    return ["", "## Antoci's gate held static (gate_static)", "",
            "The gap closed, gravity 1 m/s^2 (the free end deflects about 5 % of the gate's length), both phases "
            "relaxed to rest: the free end's settled deflection [mm] coupled (scenes/antoci_gate_static.py; its swing "
            "over the settled window; the water's push on the free length against the exact hydrostatic force), under "
            "the water's exact hydrostatic pressure (scenes/antoci_gate_loaded.py), and plane-strain FE of the free "
            "length read where the probe sits (the lowest particle layer, half a spacing above the free end), for the "
            "antoci_gate scene's former scheme and the default one. Coupled against FE is the whole answer; load "
            "transfer: coupled against loaded (same solid); bending: loaded against FE.", "",
            "| spacing | scheme | coupled | swing | water on the gate / exact | loaded | FE | coupled vs FE | "
            "load transfer | bending |",
            "|---|---|---|---|---|---|---|---|---|---|", *lines]


def _fluid_extra(rungs, summaries):
    lines = []
    for r in rungs:
        s = summaries.get(r.key)
        if s is None or r.case not in ("hydrostatic", "dam_break", "lobovsky_dam_break") or not s.get("fluid_steps"):
            continue
        if r.case == "hydrostatic":
            detail = (f"floor p (fit) {_fmt(100 * s['floor_pressure_error'], '+.2f')} %, bottom layer "
                      f"{_fmt(100 * s['bottom_layer_error'], '+.2f')} %, floor load {_fmt(100 * s['floor_load_error'], '+.2f')} %, "
                      f"profile RMS {_fmt(100 * s['pressure_profile_rms_over_rho_g_h'], '.2f')} %, "
                      f"outside walls {s['max_particles_outside_walls']}, mass change {s['mass_change_kg']:g} kg")
        elif r.case == "lobovsky_dam_break":
            detail = (f"RMS over T >= 1 {_fmt(100 * s['front_rms_relative_error'], '.2f')} %; best delay dT = "
                      f"{_fmt(s['front_time_shift_T'], '.3f')} leaves {_fmt(100 * s['front_rms_after_time_shift'], '.2f')} %; "
                      f"speed dZ/dT on T in [1, 1.6] {_fmt(s['front_speed_dZdT'], '.3f')} (experiment "
                      f"{_fmt(s['front_speed_dZdT_experiment'], '.3f')}, {_fmt(100 * s['front_speed_error'], '+.1f')} %); "
                      f"outside walls {s['max_particles_outside_walls']}")
        else:
            pts = ", ".join(f"T={p['T']:.2f}: {100 * p['relative_error']:+.1f} %" for p in s["front_points"])
            detail = (f"{pts}; RMS {100 * s['front_rms_relative_error']:.1f} %; best delay dT = "
                      f"{_fmt(s['front_time_shift_T'], '.3f')} leaves {_fmt(100 * s['front_rms_after_time_shift'], '.1f')} %; "
                      f"speed dZ/dT {_fmt(s['front_speed_dZdT'], '.3f')} (experiment {_fmt(s['front_speed_dZdT_experiment'], '.3f')}); "
                      f"outside walls {s['max_particles_outside_walls']}")
        lines.append(f"| {r.key} | {s['particles'].get('fluid')} | {s['fluid_steps']} | "
                     f"{_fmt(s.get('fluid_iterations_per_step'), '.1f')} | {s.get('iterations_max', '-')} | "
                     f"{s.get('fluid_capped_steps', 0)} | {_fmt((s.get('fluid_particle_iterations_per_second') or 0) / 1e6, '.3f')} | "
                     f"{s['wall_time_s']:.1f} | {detail} |")
    if not lines:
        return []
    return ["", "### Fluid: iterations, throughput and errors", "",
            "Iterations: density-correction iterations per fluid step (mean over the run, largest in any step); "
            "capped: steps that reached fluid.max_iterations. M particle-iterations/s: fluid particles x iterations "
            "over stepping time (whole steps, neighbour builds included).", "",
            "| run | fluid particles | fluid steps | iterations / step | max | capped | M particle-iterations/s | "
            "wall [s] | errors |", "|---|---|---|---|---|---|---|---|---|", *lines]


def _fluid_plots(out_dir, rungs, summaries, plt):
    made = []
    runs = [r for r in rungs if r.case == "dam_break" and r.key in summaries]
    if runs:
        fig, (a1, a2) = plt.subplots(2, 1, figsize=(6.5, 7))
        ref = read_reference_csv("martin_moyce_1952_a57mm.csv")
        a1.plot([row["T"] for row in ref], [row["Z"] for row in ref], "ko", label="Martin & Moyce 1952")
        for r in runs:
            rows = _series_rows(out_dir, r)
            if rows is None:
                continue
            t = np.array([float(x["T"]) for x in rows])
            a1.plot(t, [float(x["front_Z"]) for x in rows], label=r.label)
            a2.plot([float(x["time"]) for x in rows], [float(x["iterations_mean"]) for x in rows], label=r.label)
        a1.set_xlim(0, 3.5)
        a1.set_ylim(0.9, 5)
        a1.set_xlabel("T = t sqrt(2 g / a)")
        a1.set_ylabel("Z = x_front / a")
        a1.set_title("Dam break: surge front")
        a2.set_xlabel("t [s]")
        a2.set_ylabel("iterations per step")
        made.append(_save_panels(plt, fig, (a1, a2), Path(out_dir) / "dam_break_front.png", legend_size=8))
    runs = [r for r in rungs if r.case == "lobovsky_dam_break" and r.key in summaries]
    if runs:
        made.append(_lobovsky_plot(plt, out_dir, runs))
    runs = [r for r in rungs if r.case == "hydrostatic" and r.key in summaries]
    if runs:
        fig, (a1, a2) = plt.subplots(2, 1, figsize=(6.5, 6), sharex=True)
        for r in runs:
            rows = _series_rows(out_dir, r)
            if rows is None:
                continue
            t = [float(x["time"]) for x in rows]
            ref = summaries[r.key]["reference_floor_pressure_pa"]
            a1.plot(t, [float(x["floor_pressure"]) / ref for x in rows], label=r.label)
            a2.plot(t, [float(x["iterations_mean"]) for x in rows], label=r.label)
        a1.set_ylim(0.8, 1.2)
        a1.set_ylabel("floor pressure / rho g H")
        a1.set_title("Hydrostatic tank")
        a2.set_ylabel("correction iterations per step")
        a2.set_xlabel("t [s]")
        made.append(_save_panels(plt, fig, (a1, a2), Path(out_dir) / "hydrostatic_pressure.png", legend_size=8))
    return made


def _counterpart_run(out_dir, key):
    """The kept run (summary, timeseries rows) of rung `key` ("case/label") in the report directory next to this one
    (OUT/../CASE/runs/CASE/LABEL) or in this one's parent's runs (the main report's, OUT/../runs/CASE/LABEL);
    (None, None) if neither holds it."""
    case, label = key.split("/")
    parent = Path(out_dir).parent
    for run in (parent / case / "runs" / case / label, parent / "runs" / case / label):
        if (run / "summary.json").is_file():
            rows = None
            if (run / "timeseries.csv").is_file():
                with (run / "timeseries.csv").open() as fh:
                    rows = list(csv.DictReader(fh))
            return json.loads((run / "summary.json").read_text()), rows
    return None, None


def _free_end_gap(rows_a, rows_b):
    """[(t, dx_a - dx_b)] of the free end at the sample times both runs have (m; empty without both)."""
    if not rows_a or not rows_b:
        return []
    b = {round(float(r["time"]), 9): float(r["tip_dx"]) for r in rows_b}
    return [(float(r["time"]), float(r["tip_dx"]) - b[round(float(r["time"]), 9)]) for r in rows_a
            if round(float(r["time"]), 9) in b]


def _free_end_difference(rows_a, rows_b, until):
    """Largest |dx_a - dx_b| of the free end over the samples both runs have at t <= until, m (None without both)."""
    diffs = [abs(d) for t, d in _free_end_gap(rows_a, rows_b) if t <= until + 1e-12]
    return max(diffs) if diffs else None


def _gate_span_extra(out_dir, rungs, summaries):
    """The paper's gate on the narrowest periodic slab beside the same run across the paper's 36 mm (gate_span)."""
    runs = [r for r in rungs if r.case == "gate_span"]
    if not runs:
        return []
    lines = ["", "## The paper's gate: the narrowest periodic slab against the paper's 36 mm", "",
             "Each run on the slab the scene builds since 2026-12-05 (6 layers across y) beside the same run across "
             "the paper's 36 mm (the counterpart's kept run, in its own report). The flow is uniform across y, so "
             "the slab's width should not move the answer: the free end's largest difference up to 0.06 s (the rise "
             "to the peak) and over the whole run, against the size of the deflection; the strain energy's peak for "
             "the paper's 36 mm gate (the energy goes as the span). Wall times: each run's own threads and host "
             "state (the `threads, commit` column above and the counterpart's report).", "",
             "| run | particles: 36 mm / narrow | dx peak [mm] at [s]: 36 mm / narrow | spring-back | strain energy "
             "peak, 36 mm gate [mJ] | free end's largest difference to 0.06 s / over the run [mm] | checks passed | "
             "wall [s]: 36 mm / narrow | threads |", "|---|---|---|---|---|---|---|---|---|"]

    def count(s):
        p = s["particles"]
        return p["solid"] + p["fluid"] + p["walls"]

    def energy(s):
        return s.get("strain_energy_peak_paper_width_j", s["strain_energy_peak_j"])

    def checks(s):
        return sum(bool(s.get(k)) for k in ("check_peak_in_paper_window", "check_springs_back",
                                            "check_energy_rises_and_falls"))

    for r in runs:
        new, new_rows = summaries.get(r.key), _series_rows(out_dir, r)
        old, old_rows = _counterpart_run(out_dir, r.counterpart)
        if new is None or old is None:
            lines.append(f"| {r.label} | {'not run' if new is None else 'narrow run only'}; counterpart "
                         f"{r.counterpart}{' not kept' if old is None else ''} | | | | | | | |")
            continue
        early = _free_end_difference(new_rows, old_rows, 0.06)
        whole = _free_end_difference(new_rows, old_rows, new["simulated_time_s"])
        lines.append(
            f"| {r.label} | {count(old):,} / {count(new):,} | {1e3 * old['tip_dx_peak_m']:.4f} at "
            f"{old['tip_dx_peak_time_s']:.3f} / {1e3 * new['tip_dx_peak_m']:.4f} at {new['tip_dx_peak_time_s']:.3f} | "
            f"{100 * old['spring_back_fraction']:.1f} / {100 * new['spring_back_fraction']:.1f} % | "
            f"{1e3 * energy(old):.4f} / {1e3 * energy(new):.4f} | "
            f"{_fmt(None if early is None else 1e3 * early, '.2g')} / {_fmt(None if whole is None else 1e3 * whole, '.2g')} | "
            f"{checks(old)} / {checks(new)} of 3 | {old['wall_time_s']:.0f} / {new['wall_time_s']:.0f} | "
            f"{old['machine'].get('numba_threads')} / {new['machine'].get('numba_threads')} |")
    return lines


def _gate_extra(rungs, summaries):
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
                f"| {r.label} | {model}, {material} | {dp:.3g} | {1e3 * s['tip_x_peak_m']:.1f} | {s['tip_x_peak_time_s']:.3f} | "
                f"{smoothed} | "
                f"{100 * s['tip_x_peak_error']:+.1f} % | {100 * s['tip_x_rms_over_exp_peak']:.1f} % | "
                f"{1e3 * s['tip_z_peak_m']:.1f} | {s['tip_z_peak_time_s']:.3f} | {100 * s['tip_z_peak_error']:+.1f} % | "
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
                  "|---|---|---|---|---|---|---|---|---|---|---|---|---|", *antoci]
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


def _gate_plots(out_dir, rungs, summaries, plt):
    """Overlay of the free end against Antoci's data (every antoci_gate rung); the paper's Figs. 7-8 analogues."""
    made = []
    runs = [r for r in rungs if r.scene == "antoci_gate" and r.key in summaries]
    if runs:
        from .references import antoci_gate_tip
        fig, axes = plt.subplots(2, 1, figsize=(10, 6.5), sharex=True)
        for ax, comp, col in ((axes[0], "x", "tip_dx"), (axes[1], "z", "tip_dz")):
            te, ye = antoci_gate_tip(comp)
            ax.plot(te, ye * 1e3, "ko", label="Antoci et al. 2007 (experiment)")
            curves = []
            for i, r in enumerate(runs):
                rows = _series_rows(out_dir, r)
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
        fig.tight_layout()
        fig.savefig(Path(out_dir) / "antoci_gate_tip.png", dpi=120)
        plt.close(fig)
        made.append("antoci_gate_tip.png")
    runs = [r for r in rungs if r.scene == "elastic_gate" and r.key in summaries]
    if runs:
        fig, axes = plt.subplots(2, 1, figsize=(7, 6.5), sharex=True)
        for i, r in enumerate(runs):
            rows = _series_rows(out_dir, r)
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
        made.append(_save_panels(plt, fig, axes, Path(out_dir) / "elastic_gate_tip_and_energy.png", legend_size=7))
    return made


def _gate_snapshot_plots(out_dir, rungs, summaries, plt):
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


def _gate_span_plot(out_dir, rungs, summaries, plt):
    """Each gate_span run's free end beside its 36 mm counterpart's, and their difference."""
    pairs = []
    for r in rungs:
        if r.case == "gate_span" and r.key in summaries:
            rows = _series_rows(out_dir, r)
            _, old_rows = _counterpart_run(out_dir, r.counterpart)
            if rows and old_rows:
                pairs.append((r, rows, old_rows))
    if not pairs:
        return []
    fig, axes = plt.subplots(2, 1, figsize=(7, 6.5), sharex=True)
    for i, (r, rows, old_rows) in enumerate(pairs):
        for series, style, label in ((rows, "-", f"{r.label}, narrowest slab"),
                                     (old_rows, "--", f"{r.counterpart}, 36 mm")):
            axes[0].plot([float(x["time"]) for x in series], [1e3 * float(x["tip_dx"]) for x in series], style,
                         color=f"C{i}", label=label)
        gap = _free_end_gap(rows, old_rows)
        axes[1].plot([t for t, _ in gap], [1e3 * d for _, d in gap], "-", color=f"C{i}", label=r.label)
    axes[0].set_ylabel("free-end x displacement [mm]")
    axes[0].set_title("The paper's gate: the narrowest periodic slab against the paper's 36 mm")
    axes[1].set_ylabel("narrowest minus 36 mm [mm]")
    axes[1].set_xlabel("t [s]")
    return [_save_panels(plt, fig, axes, Path(out_dir) / "gate_span_free_end.png", legend_size=7)]


def _plots(out_dir, rungs, summaries):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    made = []
    # Error against wall time, one series per case (the Pareto view).
    fig, ax = plt.subplots(figsize=(6, 4.5))
    for case in sorted({r.case for r in rungs}):
        pts = [(summaries[r.key]["wall_time_s"], summaries[r.key]["error"], r.label) for r in rungs
               if r.case == case and r.key in summaries and summaries[r.key].get("error")]
        if pts:
            x, y, labels = zip(*pts)
            ax.loglog(x, y, "o-", label=case)
            for xi, yi, lab in pts:
                ax.annotate(lab, (xi, yi), fontsize=7, xytext=(3, 3), textcoords="offset points")
    ax.set_xlabel("wall time on this machine [s]")
    ax.set_ylabel("relative error against the reference")
    ax.set_title("Error against run time")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(Path(out_dir) / "error_vs_walltime.png", dpi=120)
    plt.close(fig)
    made.append("error_vs_walltime.png")
    # Frequency against beam length, like the paper's Fig. 5.
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
        ax.grid(True, alpha=0.3)
        ax.legend(fontsize=8)
        fig.tight_layout()
        fig.savefig(Path(out_dir) / "cantilever_frequency_vs_length.png", dpi=120)
        plt.close(fig)
        made.append("cantilever_frequency_vs_length.png")
    # The long run's free-end motion and energy, like the paper's Fig. 4.
    long_run = [r for r in rungs if r.case == "cantilever" and r.key in summaries]
    if long_run:
        rows = _series_rows(out_dir, long_run[0])
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
            made.append(_save_panels(plt, fig, (a1, a2), Path(out_dir) / "cantilever_tip_and_energy.png"))
    made += _clamp_effect_plot(out_dir, rungs, summaries, plt)
    made += _fluid_plots(out_dir, rungs, summaries, plt)
    made += _gate_plots(out_dir, rungs, summaries, plt)
    made += _gate_snapshot_plots(out_dir, rungs, summaries, plt)
    made += _gate_span_plot(out_dir, rungs, summaries, plt)
    made += spheric2.plot(out_dir, [r for r in rungs if r.case == spheric2.CASE], summaries, plt, _series_rows)
    return made


def made_by(out, rungs):
    """The command that makes this report: `sph-fsi validate [CASES] --out OUT` (no case names: all of them; OUT
    relative to the working directory when it lies inside it)."""
    from .cases import all_rungs
    cases = list(dict.fromkeys(r.case for r in rungs))
    every = list(dict.fromkeys(r.case for r in all_rungs()))
    try:
        shown = out.resolve().relative_to(Path.cwd().resolve())
    except ValueError:
        shown = out
    names = "" if cases == every else " " + " ".join(cases)
    return f"sph-fsi validate{names} --out {shown.as_posix()}"


def write_report(out_dir, rungs, summaries):
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    plots = _plots(out, rungs, summaries)
    machine = next((s["machine"] for s in summaries.values()), {})
    command = made_by(out, rungs)
    lines = [
        "# Validation: error against run time", "",
        f"Made by `{command}`; rebuild this page from the stored runs with `{command} --report-only`. Each row is one "
        "headless run; its full outputs (summary.json, timeseries.csv) are under `runs/CASE/RUN/`.", "",
        f"Machine: {machine.get('cpus')} CPUs, Python {machine.get('python')}, Numba {machine.get('numba')}, "
        f"NumPy {machine.get('numpy')}; report written {datetime.date.today().isoformat()}. Each run's Numba threads "
        f"and the commit it ran on are in its row (runs are kept and reported until rerun).", "",
        "Wall time includes setup (scene build, first force evaluation; Numba functions come from the on-disk "
        "cache). Particles: the moving ones' phases plus the solid's clamp (not the fluid's walls); steps: solid + "
        "fluid steps. Particle-steps/s counts every solid particle (clamp included) per solid step and every fluid "
        "particle per fluid step, over stepping "
        "time only; a value well below the benchmark's (`docs/performance/BENCH.md`) means the run shared the "
        "2 cores with other work and its wall time is inflated by the same factor.", "",
        "| case | run | dp [mm] | particles | steps | wall [s] | M particle-steps/s | measured | reference | "
        "error | stable | threads, commit |",
        "|---|---|---|---|---|---|---|---|---|---|---|---|",
    ]
    for r in rungs:
        lines.append(_row(r, summaries.get(r.key)))
    lines += _cantilever_extra(rungs, summaries)
    lines += _cantilever_shapes_extra(rungs, summaries)
    lines += _large_deflection_extra(rungs, summaries)
    lines += _solid_static_extra(rungs, summaries)
    lines += _clamp_effect_extra(out, rungs, summaries)
    lines += _hydrostatic_plate_extra(rungs, summaries)
    lines += _gate_static_extra(rungs, summaries)
    lines += _fluid_extra(rungs, summaries)
    lines += _gate_extra(rungs, summaries)
    lines += _solid_pressure_extra(out, rungs, summaries)
    lines += _gate_span_extra(out, rungs, summaries)
    if any(r.case == spheric2.CASE for r in rungs):
        lines += spheric2.table([r for r in rungs if r.case == spheric2.CASE], summaries)
    lines += ["", "## Plots", ""] + [f"![{p}]({p})" for p in plots]
    (out / "REPORT.md").write_text("\n".join(lines) + "\n")
    return out / "REPORT.md"


# the Lobovsky rungs that vary the scene's default (lifted, settled) in something other than the spacing
_LOBOVSKY_VARIANTS = ("fluid.density_tolerance", "fluid.cfl", "geometry.periodic_y")


def _lobovsky_plot(plt, out_dir, runs):
    """lobovsky_front.png: the front against Lobovsky et al. 2014's, the gate gone at t = 0 and lifted at the
    measured speed, each from zero pressure (solid lines) and settled (dashed), and the scene's default beside its
    variants (tolerance, step, 3D) over the window where the speed is fitted."""
    fig, axes = plt.subplots(1, 3, figsize=(17, 5.2))
    for a in axes:
        a.plot(*lobovsky_front(), "ko", ms=3, label="Lobovsky et al. 2014 (gate lifted at 4.53 m/s)")
    for r in runs:
        rows = _series_rows(out_dir, r)
        if rows is None:
            continue
        variant = any(k in r.overrides for k in _LOBOVSKY_VARIANTS)
        if variant or r.label.startswith("lifted_settled_H"):
            axes[2].plot([float(x["T"]) for x in rows], [float(x["front_Z"]) for x in rows],
                         ":" if variant else "-", label=r.label)
        if variant:
            continue
        axis = axes[0] if r.overrides.get("geometry.release") == "instant" else axes[1]
        axis.plot([float(x["T"]) for x in rows], [float(x["front_Z"]) for x in rows],
                  "--" if "settled" in r.label else "-", label=r.label)
    for a, title in ((axes[0], "gate gone at t = 0"), (axes[1], "gate lifted at 4.53 m/s"),
                     (axes[2], "lifted, settled: the default and its variants")):
        a.set_xlabel("T = t sqrt(g / H)")
        a.set_ylabel("Z = 1 + x / H")
        a.set_title(f"Lobovsky et al., H = 600 mm: {title}", fontsize=10)
        a.grid(True, alpha=0.3)
        a.legend(fontsize=6 if a is axes[2] else 7)
    for a in axes[:2]:
        a.set_xlim(0, 1.7)
        a.set_ylim(0.95, 2.8)
    axes[2].set_xlim(0.9, 1.65)   # the speed's window, T in [1, 1.6]
    axes[2].set_ylim(1.75, 2.75)
    fig.tight_layout()
    fig.savefig(Path(out_dir) / "lobovsky_front.png", dpi=120)
    plt.close(fig)
    return "lobovsky_front.png"
