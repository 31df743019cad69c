"""REPORT.md and PNG plots of `sph-fsi validate`, made from the rungs' summary.json files (no simulation here)."""
import csv
import datetime
import math
from pathlib import Path

import numpy as np

from .references import read_reference_csv


def _fmt(x, spec=".3g"):
    if x is None or (isinstance(x, float) and not math.isfinite(x)):
        return "-"
    return format(x, spec)


def _row(rung, s):
    if s is None:
        return f"| {rung.case} | {rung.label} | not run | | | | | | | | |"
    d = s["diverged"]
    stable = "yes" if s["stable"] else f"no: {d['check']} at {d['time']:.4g} s"
    measured = ref = "-"
    if s.get("frequency_hz") is not None:
        measured = f"{s['frequency_hz']:.3f} ± {s['frequency_uncertainty_hz']:.3f} Hz"
        ref = f"{s['reference_hz']:.3f} Hz ({s['fe3d_source']})"
    err = f"{100 * s['error']:.2f} %" if s.get("error") is not None else "-"
    return (f"| {rung.case} | {rung.label} | {s['settings']['numerics.spacing'] * 1e3:.3g} | "
            f"{s['particles']['solid']} | {s['solid_steps']} | {s['wall_time_s']:.1f} | "
            f"{_fmt(s['particle_steps_per_second'] / 1e6, '.3f')} | {measured} | {ref} | {err} | {stable} |")


def _cantilever_extra(rungs, summaries):
    lines = []
    for r in rungs:
        s = summaries.get(r.key)
        if s is None or r.case not in ("cantilever", "cantilever_ladder", "cantilever_length"):
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
                    label="sph_fsi, dp = 1 mm")
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
        path = Path(out_dir) / "runs" / long_run[0].case / long_run[0].label / "timeseries.csv"
        if path.is_file():
            rows = list(csv.DictReader(path.open()))
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
            for a in (a1, a2):
                a.grid(True, alpha=0.3)
            fig.tight_layout()
            fig.savefig(Path(out_dir) / "cantilever_tip_and_energy.png", dpi=120)
            plt.close(fig)
            made.append("cantilever_tip_and_energy.png")
    return made


def write_report(out_dir, rungs, summaries):
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    plots = _plots(out, rungs, summaries)
    machine = next((s["machine"] for s in summaries.values()), {})
    lines = [
        "# Validation: error against run time", "",
        "Made by `sph-fsi validate` (`make validate`); rebuild this page from the stored runs with "
        "`sph-fsi validate --report-only`. Each row is one headless run; its full outputs (summary.json, "
        "timeseries.csv) are under `runs/CASE/RUN/`.", "",
        f"Machine: {machine.get('cpus')} CPUs, {machine.get('numba_threads')} Numba threads, Python "
        f"{machine.get('python')}, Numba {machine.get('numba')}, NumPy {machine.get('numpy')}; commit "
        f"{machine.get('commit')}; report written {datetime.date.today().isoformat()}.", "",
        "Wall time includes setup (scene build, first force evaluation; Numba functions come from the on-disk "
        "cache). Particle-steps/s counts every solid particle (clamp included) per solid step, over stepping "
        "time only; a value well below the benchmark's (`docs/performance/BENCH.md`) means the run shared the "
        "2 cores with other work and its wall time is inflated by the same factor.", "",
        "| case | run | dp [mm] | particles | solid steps | wall [s] | M particle-steps/s | measured | reference | "
        "error | stable |",
        "|---|---|---|---|---|---|---|---|---|---|---|",
    ]
    for r in rungs:
        lines.append(_row(r, summaries.get(r.key)))
    lines += _cantilever_extra(rungs, summaries)
    lines += ["", "## Plots", ""] + [f"![{p}]({p})" for p in plots]
    (out / "REPORT.md").write_text("\n".join(lines) + "\n")
    return out / "REPORT.md"
