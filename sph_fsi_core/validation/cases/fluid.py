"""The water alone: the hydrostatic tank (scenes/hydrostatic.py), Martin & Moyce's dam break (scenes/dam_break.py)
and Lobovsky et al. 2014's (scenes/lobovsky_dam_break.py), each judged by its scene's evaluate (floor pressure
against rho g H; the surge front against the experiment); one table and a plot per case."""
from pathlib import Path

import numpy as np

from ...answers.references import lobovsky_front, read_reference_csv
from ..report_tools import fmt, save_panels, series_rows
from ..rung import Rung


def rungs():
    """Hydrostatic tank, Martin & Moyce's and Lobovsky et al.'s dam breaks, each over a resolution ladder (fixed end
    times)."""
    rungs = []
    # Hydrostatic: 0.6 s, judged on the last 30 %; dp = 5 mm is CI's. The step is held at 2.5 mm: the iterations per
    # step grow as (dt / dp)^2 (docs/method.md), so the finer tank takes a proportionally finer step.
    for dp, quick, extra in ((0.005, True, {}), (0.0025, False, {"fluid.time_step": 0.0025})):
        rungs.append(Rung("hydrostatic", f"dp_{dp * 1e3:g}mm", "hydrostatic", {"numerics.spacing": dp, **extra},
                          end_time=0.6, quick=quick, bound=0.02,
                          note=f"H / dp = {0.1 / dp:.0f}; floor pressure against rho g H"))
    # Dam break to T = 3.15 at a / dp = 10, 20, 30.
    a = 0.05715
    for ratio, quick in ((10, True), (20, False), (30, False)):
        rungs.append(Rung("dam_break", f"a_over_dp_{ratio}", "dam_break", {"numerics.spacing": a / ratio},
                          end_time=0.17, quick=quick, bound=0.15,
                          note=f"dp = {a / ratio * 1e3:.3f} mm; front vs Martin & Moyce, RMS over T <= 3"))
    # Lobovsky et al. 2014's 600 mm column at H / dp = 30, 60, 90: both releases (the gate gone at t = 0,
    # or lifted at the measured 4.53 m/s), each from the lattice at zero pressure and settled behind its gate for
    # 0.3 s (fluid.settle_time; about three of the column's breathing periods); RMS of Z over T >= 1.
    height = 0.6
    for ratio in (30, 60, 90):
        for release in ("instant", "lifted"):
            for settle in (0.0, 0.3):
                label = f"{release}{'_settled' if settle else ''}_H_over_dp_{ratio}"
                rungs.append(Rung("lobovsky_dam_break", label, "lobovsky_dam_break",
                                  {"numerics.spacing": height / ratio, "geometry.release": release,
                                   "fluid.settle_time": settle}, end_time=0.4, quick=ratio == 30, bound=0.05,
                                  note=f"dp = {height / ratio * 1e3:.3g} mm, gate {release}, "
                                       f"{'settled 0.3 s' if settle else 'from zero pressure'}; front vs Lobovsky "
                                       f"et al. 2014, RMS over T >= 1"))
    # the front's speed against the water's compressibility (the tolerance measured on the fronts too): the
    # scene's default (lifted, settled) with the density tolerance 0.3 % and 0.1 % instead of 1 %
    for ratio in (30, 60):
        for tolerance, tag in ((0.003, "0.3pct"), (0.001, "0.1pct")):
            rungs.append(Rung("lobovsky_dam_break", f"lifted_settled_tol{tag}_H_over_dp_{ratio}", "lobovsky_dam_break",
                              {"numerics.spacing": height / ratio, "geometry.release": "lifted",
                               "fluid.settle_time": 0.3, "fluid.density_tolerance": tolerance}, end_time=0.4,
                              note=f"dp = {height / ratio * 1e3:.3g} mm, gate lifted, settled 0.3 s, "
                                   f"fluid.density_tolerance = {tolerance:g}"))
    # the front's speed against the fluid's time step: the scene's default with fluid.cfl halved and quartered
    for ratio in (30, 60, 90):
        for cfl in (0.1, 0.05):
            rungs.append(Rung("lobovsky_dam_break", f"lifted_settled_cfl{cfl:g}_H_over_dp_{ratio}",
                              "lobovsky_dam_break",
                              {"numerics.spacing": height / ratio, "geometry.release": "lifted",
                               "fluid.settle_time": 0.3, "fluid.cfl": cfl}, end_time=0.4,
                              quick=ratio == 30 and cfl == 0.05,
                              note=f"dp = {height / ratio * 1e3:.3g} mm, gate lifted, settled 0.3 s, "
                                   f"fluid.cfl = {cfl:g}"))
    # the experiment's tank in 3D at the coarse spacing: 600 mm wide (30 layers), closed by free-slip side walls
    rungs.append(Rung("lobovsky_dam_break", "lifted_settled_3d_H_over_dp_30", "lobovsky_dam_break",
                      {"numerics.spacing": height / 30, "geometry.release": "lifted", "fluid.settle_time": 0.3,
                       "geometry.periodic_y": False, "geometry.span_layers": 30}, end_time=0.4,
                      note="dp = 20 mm, the 600 mm wide tank in 3D with side walls, gate lifted, settled 0.3 s"))
    return rungs


def table(out_dir, rungs, summaries):
    """Every fluid run's correction iterations, throughput and its case's errors."""
    lines = []
    for r in rungs:
        s = summaries.get(r.key)
        if s is None or r.case not in ("hydrostatic", "dam_break", "lobovsky_dam_break") or not s.get("fluid_steps"):
            continue
        if r.case == "hydrostatic":
            detail = (f"floor p (fit) {fmt(100 * s['floor_pressure_error'], '+.2f')} %, bottom layer "
                      f"{fmt(100 * s['bottom_layer_error'], '+.2f')} %, "
                      f"floor load {fmt(100 * s['floor_load_error'], '+.2f')} %, "
                      f"profile RMS {fmt(100 * s['pressure_profile_rms_over_rho_g_h'], '.2f')} %, "
                      f"outside walls {s['max_particles_outside_walls']}, mass change {s['mass_change_kg']:g} kg")
        elif r.case == "lobovsky_dam_break":
            detail = (f"RMS over T >= 1 {fmt(100 * s['front_rms_relative_error'], '.2f')} %; best delay dT = "
                      f"{fmt(s['front_time_shift_T'], '.3f')} leaves "
                      f"{fmt(100 * s['front_rms_after_time_shift'], '.2f')} %; "
                      f"speed dZ/dT on T in [1, 1.6] {fmt(s['front_speed_dZdT'], '.3f')} (experiment "
                      f"{fmt(s['front_speed_dZdT_experiment'], '.3f')}, "
                      f"{fmt(100 * s['front_speed_error'], '+.1f')} %); "
                      f"outside walls {s['max_particles_outside_walls']}")
        else:
            pts = ", ".join(f"T={p['T']:.2f}: {100 * p['relative_error']:+.1f} %" for p in s["front_points"])
            detail = (f"{pts}; RMS {100 * s['front_rms_relative_error']:.1f} %; best delay dT = "
                      f"{fmt(s['front_time_shift_T'], '.3f')} leaves "
                      f"{fmt(100 * s['front_rms_after_time_shift'], '.1f')} %; "
                      f"speed dZ/dT {fmt(s['front_speed_dZdT'], '.3f')} "
                      f"(experiment {fmt(s['front_speed_dZdT_experiment'], '.3f')}); "
                      f"outside walls {s['max_particles_outside_walls']}")
        lines.append(f"| {r.key} | {s['particles'].get('fluid')} | {s['fluid_steps']} | "
                     f"{fmt(s.get('fluid_iterations_per_step'), '.1f')} | {s.get('iterations_max', '-')} | "
                     f"{s.get('fluid_capped_steps', 0)} | "
                     f"{fmt((s.get('fluid_particle_iterations_per_second') or 0) / 1e6, '.3f')} | "
                     f"{s['wall_time_s']:.1f} | {detail} |")
    if not lines:
        return []
    return ["", "### Fluid: iterations, throughput and errors", "",
            "Iterations: density-correction iterations per fluid step (mean over the run, largest in any step); "
            "capped: steps that reached fluid.max_iterations. M particle-iterations/s: fluid particles x iterations "
            "over stepping time (whole steps, neighbour builds included).", "",
            "| run | fluid particles | fluid steps | iterations / step | max | capped | M particle-iterations/s | "
            "wall [s] | errors |", "|---|---|---|---|---|---|---|---|---|", *lines]


def plot(out_dir, rungs, summaries, plt):
    """dam_break_front.png, lobovsky_front.png and hydrostatic_pressure.png, each where its case has runs."""
    made = []
    runs = [r for r in rungs if r.case == "dam_break" and r.key in summaries]
    if runs:
        fig, (a1, a2) = plt.subplots(2, 1, figsize=(6.5, 7))
        ref = read_reference_csv("martin_moyce_1952_a57mm.csv")
        a1.plot([row["T"] for row in ref], [row["Z"] for row in ref], "ko", label="Martin & Moyce 1952")
        for r in runs:
            rows = series_rows(out_dir, r)
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
        made.append(save_panels(plt, fig, (a1, a2), Path(out_dir) / "dam_break_front.png", legend_size=8))
    runs = [r for r in rungs if r.case == "lobovsky_dam_break" and r.key in summaries]
    if runs:
        made.append(_lobovsky_plot(plt, out_dir, runs))
    runs = [r for r in rungs if r.case == "hydrostatic" and r.key in summaries]
    if runs:
        fig, (a1, a2) = plt.subplots(2, 1, figsize=(6.5, 6), sharex=True)
        for r in runs:
            rows = series_rows(out_dir, r)
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
        made.append(save_panels(plt, fig, (a1, a2), Path(out_dir) / "hydrostatic_pressure.png", legend_size=8))
    return made


_LOBOVSKY_VARIANTS = ("fluid.density_tolerance", "fluid.cfl", "geometry.periodic_y")


def _lobovsky_plot(plt, out_dir, runs):
    """lobovsky_front.png: the front against Lobovsky et al. 2014's, the gate gone at t = 0 and lifted at the
    measured speed, each from zero pressure (solid lines) and settled (dashed), and the scene's default beside its
    variants (tolerance, step, 3D) over the window where the speed is fitted."""
    fig, axes = plt.subplots(1, 3, figsize=(17, 5.2))
    for a in axes:
        a.plot(*lobovsky_front(), "ko", ms=3, label="Lobovsky et al. 2014 (gate lifted at 4.53 m/s)")
    for r in runs:
        rows = series_rows(out_dir, r)
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
    return save_panels(plt, fig, [], Path(out_dir) / "lobovsky_front.png")
