"""Slow water on its lattice: why it sticks, and h / dp; a study run only when named (`sph-fsi validate water_lattice
--out docs/validation/studies/water_lattice`).

The water and the walls are built on one simple cubic lattice, and the density correction pushes a particle back
wherever eq. (1)'s sum over its neighbours rises past the tolerance. As a layer of water slides over the floor, or
over the layer below it, that sum rises and falls with the lattice it passes over: by 0.095 % of rho0 along a lattice
axis and 0.15 % along the diagonal at the default h / dp = 1.3, against 0.006 / 0.011 % at 1.25 and 0.002 / 0.065 %
at 1.5 (the M4 spline's spectrum at the lattice's wavenumbers; validation/lattice_corrugation.py, checked against
the density pass in test/test_water_lattice.py). A particle on the floor sits at the tolerance (the column's
weight compresses it there), so these bumps are felt in full: the correction puts the bottom layer back into the
floor's wells, and slow water sticks. The study runs two exact answers at three h / dp: water sliding as one along
a free-slip floor at 0.04 m/s (the speed a small wave has at the floor; config/sliding_water.yaml: its mean
velocity must stay), and at 0.2 m/s; and the default suite's small standing wave (config/standing_wave.yaml, d/dp
20: its frequency against linear theory, its loss per period, and its level's drift, the mean of the two
antinodes' heights at the end less the start's). A periodic slab must be at least twice the neighbour cutoff wide:
7 layers at 1.5 against 6.
"""
import csv
from pathlib import Path

from ..lattice_corrugation import corrugation
from ..report_tools import fmt
from ..rung import Rung

CASE = "water_lattice"
# (h / dp, layers across the periodic slab: twice the cutoff 2h + 0.1 h at least)
RATIOS = ((1.25, 6), (1.3, 6), (1.5, 7))
SLOW, FAST = 0.04, 0.2   # m/s, the sliding water's speeds
WAVE_END = 3.7           # s, the default suite's (five periods)


def _keys(ratio, layers):
    return {"numerics.smoothing_ratio": ratio, "geometry.span_layers": layers}


def rungs():
    out = [Rung(CASE, f"sliding_{SLOW:g}_h_{ratio:g}", "sliding_water",
                {**_keys(ratio, layers), "geometry.speed": SLOW}, end_time=0.5, judge="speed",
                resolution=f"h/dp {ratio:g}", note=f"water sliding at {SLOW:g} m/s, h / dp = {ratio:g}")
           for ratio, layers in RATIOS]
    out += [Rung(CASE, f"sliding_{FAST:g}_h_1.3", "sliding_water", {**_keys(1.3, 6), "geometry.speed": FAST},
                 end_time=0.5, judge="speed", resolution="h/dp 1.3",
                 note=f"water sliding at {FAST:g} m/s, h / dp = 1.3")]
    out += [Rung(CASE, f"standing_wave_h_{ratio:g}", "standing_wave", _keys(ratio, layers), end_time=WAVE_END,
                 judge="period", resolution=f"h/dp {ratio:g}", note=f"the standing wave at d/dp 20, h / dp = {ratio:g}")
            for ratio, layers in RATIOS]
    return out


def level_drift(out_dir, rung):
    """The standing wave's level at its end less its start's (m): the mean of its two antinodes' heights (opposite
    in a standing wave) over the last 0.5 s, less the first sample's; None without the run's time series."""
    path = Path(out_dir) / "runs" / rung.case / rung.label / "timeseries.csv"
    if not path.is_file():
        return None
    with path.open() as f:
        rows = [(float(r["time"]), 0.5 * (float(r["antinode_0"]) + float(r["antinode_half"])))
                for r in csv.DictReader(f)]
    end = rows[-1][0]
    last = [level for t, level in rows if t >= end - 0.5]
    return sum(last) / len(last) - rows[0][1]


def _cells(out_dir, rung, s):
    ratio = rung.overrides["numerics.smoothing_ratio"]
    judges = s["judges"]
    if rung.scene == "sliding_water":
        speed = judges["speed"]
        axis, diagonal = corrugation(ratio), corrugation(ratio, (1.0, 1.0, 0.0))
        return (f"{100 * speed['error_signed']:+.2f} %",
                f"mean velocity {speed['measured']:.4f} m/s of {speed['reference']:g}; the lattice's bumps "
                f"{100 * axis:.3f} % (axis), {100 * diagonal:.3f} % (diagonal)")
    drift = level_drift(out_dir, rung)
    return (f"{100 * judges['period']['error_signed']:+.2f} % / {100 * judges['period_half']['error_signed']:+.2f} %",
            f"loses {100 * judges['loss']['measured']:.1f} / {100 * judges['loss_half']['measured']:.1f} % a period; "
            f"level {'-' if drift is None else f'{1e3 * drift:+.2f} mm'}")


READING = (
    "Reading it. At the default h / dp = 1.3 water sliding at 0.04 m/s along a free-slip floor loses 31 % of its speed "
    "in half a second: its bottom layer sticks in the floor's wells and drags the rest, while at 0.2 m/s it passes "
    "over them (0.7 % lost). At 1.25 and 1.5, where the bumps along the lattice's axes are 16-50x smaller, it keeps "
    "its speed within 1 %. The same lattice gives the water a stiffness against shear that water has not: the small "
    "standing wave oscillates 11-25 % fast at 1.3 (the two antinodes), 6-8 % at 1.25 and 2-3 % at 1.5. Its loss "
    "per period does not follow: 39-62 % at every h / dp. In each run the level sinks by 0.3-0.6 spacings within "
    "the first period, the simple cubic lattice of the water collapsing into a denser packing under the wave's first "
    "strain (the water's potential energy falls by 1-5 times the wave's energy over the run). A "
    "water started disordered (each particle moved at random by up to 0.1 dp and settled for 1 s before t = 0, "
    "`python docs/validation/studies/water_lattice/jittered_start.py [0.1 [KEY=VALUE ...]]`, 1 thread) does not "
    "collapse (its level within 0.03 mm) and oscillates +5.20 / +5.48 % fast at 1.3 and +2.07 / +2.00 % at 1.5, but "
    "still loses 42.0 / 49.3 % and 46.1 / 46.4 % a period. So h / dp sets the frequency and the floor's grip, and the "
    "loss is the correction's own on particles moving past one another (docs/validation/OPEN.md 7). The wave is "
    "chaotic to round-off once its lattice collapses: the default suite's run of the 1.3 rung on 1 thread (the same "
    "physics, its sums in another order) read +19.83 % and 50.4 % a period.")

# The study's experiment scripts beside its page (no scene key runs them; each prints its own numbers, 2 threads)
EXPERIMENTS = (
    "What takes the wave's energy: gravity, not the free surface. Taylor-Green cells between a free-slip floor and "
    "lid (`cell_flow.py`: no free surface, an exact steady flow whatever the gravity; h / dp 1.5, U = 0.04 m/s, the "
    "water moved at random by up to 0.1 dp and settled for 1 s) keep 0.998 U at 0.25 s without gravity and 0.273 U "
    "with it (a strain U k t of 0.39); at 1 s 0.665 / 0.805 / 0.357 / 0.022 U at g = 0 / 0.6 / 2.45 / 9.81 m/s^2 "
    "(1.6 / 3.2 / 10.5 / 31.5 correction iterations a step). The same at 1 ms steps (0.281 U at 0.25 s), so not the "
    "step. The disordered water at rest is still without gravity and stirred by the correction with it: an RMS speed "
    "of 13.6 mm/s 0.25 s after its settling, 6.3 mm/s at 1.5 s, against the small wave's 37 mm/s at the floor. On "
    "the lattice the cells keep 0.986 U at 0.25 s under gravity, until the lattice collapses (kinetic energy 2.26 "
    "times the start's) and takes them by 0.75 s. Ruled out as cures, each measured: the last step's correction "
    "carried into the next step's predictor (a warm start, `cell_flow.py ... WARM`: 24.2 / 17.7 iterations a step "
    "instead of 31.5 at a half / the whole of it, the cells at 0.277 / 0.285 U at 0.25 s); particle shifting "
    "(Lind et al. 2012, `particle_shifting.py`), which cures the disordered Taylor-Green vortex without gravity "
    "(`taylor_green.py 1.5 0.04 0.1 5`: 0.969 U at 1 s against 0.557 U unshifted; at 1.3 0.953 against 0.363) but "
    "not the wave (`jittered_start.py 0.1 --shift 2` at h / dp 1.5: +0.94 / +1.62 % in frequency and 44.2 / 45.7 % "
    "lost a period, against +2.07 / +2.00 % and 46.1 / 46.4 % unshifted), and under gravity stirs the water further "
    "(the cells' kinetic energy 9.3 times the start's at 0.25 s with A = 5); the pressure gradient in its difference "
    "form, sum V_b (p_b - p_a) grad W, which a uniform pressure leaves without force (an experiment on a copy of "
    "fluid/okaji.py): without gravity the cells are kept with shifting (0.961 U at 1.5 s), under gravity the water "
    "boils (an RMS speed of 75-144 mm/s with shifting A = 2 or 5, its kinetic energy 27 times the start's at 0.25 s "
    "without); the correction's velocity taken from its kernel-smoothed displacement, the rest a move without "
    "velocity (a prototype, not kept): 0.175 U at 0.25 s.")

SPLIT = (
    "Where it goes: the symmetric gradient's background part. Eq. (2)'s pair term m_b (q_a + q_b) grad W (q = p / "
    "rho^2) is the difference form's m_b (q_b - q_a) grad W, which a uniform pressure leaves without force, plus "
    "m_b 2 q_a grad W, a particle's own pressure times its arrangement's error, large under the column's weight. "
    "Moving the particles by the whole term but keeping that part out of their velocity (`background_split.py "
    "SHARE SMOOTH SCRIPT`, as the transport-velocity formulation keeps a background pressure out of the momentum) "
    "keeps the cells under gravity at 0.932 U at 0.25 s and 0.475 U at 1.5 s (0.273 and -0.016 U in the default), "
    "the water stirred at 49-61 mm/s RMS; with the velocity's correction also kernel-averaged (SMOOTH 1), 0.945 and "
    "0.378 U, stirred at 28-32 mm/s, which is the cells' own speed: gravity then takes no more than it takes without "
    "gravity. Without gravity the cells keep 0.962 U at 1.5 s. Two defects: the water at rest under gravity is "
    "stirred at 22-23 mm/s RMS that does not decay (the default's 13.6 mm/s falls to 6.3), and the standing wave "
    "(the default scene, `background_split.py 1 1 config/standing_wave.yaml`) keeps its frequency and about 88 % of "
    "its amplitude a period for a period and a half (its kinetic energy's peaks 1.15, 0.81, 0.84, 0.75 mJ at 0, 0.35, "
    "0.7, 1.1 s) and then turns to noise (4-6 mJ from 1.8 s). Not a cure yet; the direction of one.")


KERNEL = (
    "Whose loss it is: the pressure gradient's on disordered water, not the correction's; and the kernel's share. The "
    "cells under gravity as above (h / dp 1.5 unless said). A pressure solved as a field instead of the correction "
    "(`iisph_step.py 0.15 0.5 1 cell_flow.py 1.5 9.81 0.1`: the IISPH prototype of studies/partial_iteration, its "
    "Jacobi relaxed at 0.15, as 0.3 diverges from a disordered start; 19 evaluations a step) loses them as fast: 0.226 "
    "U at 0.25 s and about none from 0.5 s, their energy kept as noise (0.78-0.89 of the start's, 25-27 mm/s RMS); the "
    "water at rest is stirred at 18-20 mm/s that does not decay. The velocity's correction from a first-order "
    "consistent gradient of the step's summed pressure instead of the displacement (`corrected_velocity.py 0.5 "
    "cell_flow.py 1.5 9.81 0.1`, Bonet & Lok 1999, over the water alone): exact for the column's linear pressure, but "
    "the summed pressure scatters by 51 Pa RMS about the column's (5 % of its largest) and is not linear next to the "
    "floor and the lid (a diagnosis of the first steps, not kept: 17 mm/s of noise a step, the floor's and lid's layers"
    " pushed 37 and 78 % more than g dt); the water boils (0.596 U and 297 mm/s RMS at 0.25 s). The split only where "
    "the kernel is full of water (`background_split.py 1 1 --full C cell_flow.py 1.5 9.81 0.1 0`, the default's "
    "velocity at the walls) stirs the water at rest as much: at C = 0.9 / 0.97 27.7 / 23.6 mm/s at 1.5 s, rising. The "
    "kernel (Wendland's C2 kernel with the same support 2h, free of the cubic spline's pairing instability; run from a "
    "patch of numerics/kernels.py, now the scene key `fluid.kernel: wendland_c2`, which `cell_flow.py ... --kernel "
    "wendland_c2` takes and which gives these cells' numbers to the digit): the cells keep 0.446 / 0.747 / 0.693 / "
    "0.685 U at 0.25 s and 0.122 / 0.517 / 0.583 / 0.663 U at 1 s at h / dp 1.5 / 1.75 / 2 / 2.5 (28.7 / 21.7 / 18.4 / "
    "15.4 iterations a step); the cubic spline at 1.8 keeps 0.088 U at 0.25 s. At h / dp 2 without gravity they keep "
    "0.997 and 0.882 U, and the water at rest is stirred at 4.9 mm/s falling to 3.8 (the cubic spline at 1.5: 13.6 to "
    "6.3); from the lattice they keep 0.797 and 0.338 U, shifted (A = 2) 0.684 and 0.586 U: neither order nor shifting "
    "is what is missing. With the split (SHARE 1, SMOOTH 1) at h / dp 2 they keep 0.906 / 0.783 / 0.703 U at 0.25 / 1 /"
    " 1.5 s, near what they keep without gravity, but in bursts (their kinetic energy twice the start's at 0.25 s), and"
    " the water at rest is stirred at 8-35 mm/s (the cubic spline's split: 22-23); with the smoothing's own term "
    "weighted by the patched kernel's W(0) instead of the spline's (1.31 times it; kernel_pairs.py now keeps the "
    "spline's) they kept 0.925 / 0.799 / 0.709 U and 5-10 mm/s: the split's noise turns on its smoothing's details. The"
    " wave does not follow the cells: at h / dp 2 (`sph-fsi run config/standing_wave.yaml` with the patch, now "
    "fluid.kernel=wendland_c2, and numerics.smoothing_ratio=2.0, geometry.span_layers=9 and geometry.wall_layers=5; "
    "22,680 water particles, 332 s on 2 threads against the default's 161 s) it loses 48.8 / 40.2 % a period and "
    "oscillates 5.4 / 5.2 % slow, from a disordered start (`jittered_start.py 0.1` with the same keys) 38.3 / 40.5 % "
    "and 7.6 / 9.9 % slow. Its first period is the cleanest yet (kinetic energy peaks 1.72, 1.51, 1.42 mJ at 0, 0.37, "
    "0.73 s: about 10 % of the amplitude a period), then the loss grows (0.95, 0.65, 0.46 mJ at 1.08, 1.46, 1.84 s). "
    "Twice the amplitude (a / d = 0.1) loses a smaller share, 38.7 / 28.3 % a period (-2.3 / -1.9 % in frequency; the "
    "cubic spline at 1.3: 47.5 / 43.8 %, +5.4 / +4.7 %): part of the loss does not scale with the wave's energy, as a "
    "noise floor's would not. With the split (`background_split.py 1 1 config/standing_wave.yaml` with the same keys "
    "and the patch; 32 minutes; both wave runs with the smoothing's own term weighted by the patched kernel's W(0), not"
    " rerun) the wave keeps about 98 % of its amplitude over its first half period (kinetic energy 1.72, 0.07, 1.66 mJ "
    "at 0, 0.2, 0.4 s) and then turns to noise (1.1-2.9 mJ from 0.7 s, against the wave's 1.72), as the cubic spline's "
    "split does from 1.4 s; with the split only where the kernel is full (`--full 0.95`) the noise comes as soon and "
    "stronger (1.3-3.2 mJ from 0.6 s). The free surface takes a share of the cells, not the most: with the lid taken "
    "off (`cell_flow.py 2.0 9.81 0.1 --kernel wendland_c2 --free-surface`; the cells' w is 0 at the top and their "
    "dynamic pressure would lift it by 0.04 mm) they keep 0.598 / 0.418 U at 0.25 / 1 s (15.3 iterations a step), and "
    "with the cubic spline at 1.5 (`cell_flow.py 1.5 9.81 0.1 --free-surface`) 0.286 U at 0.25 s and none from 0.5 s, "
    "as with the lid.")


def table(out_dir, rungs, summaries):
    runs = [r for r in rungs if r.case == CASE]
    if not runs:
        return []
    doc = __doc__.split("\n\n", 1)[1].strip().replace("\n", " ")
    lines = ["", "## Slow water on its lattice: h / dp", "", doc, "",
             "| rung | h/dp | measure | beside | fluid steps | iterations / step | wall [s] | threads | commit |",
             "|---|---|---|---|---|---|---|---|---|"]
    for r in runs:
        s = summaries.get(r.key)
        ratio = f"{r.overrides['numerics.smoothing_ratio']:g}"
        if s is None:
            lines.append(f"| {r.label} | {ratio} | not run | | | | | | |")
            continue
        measure, beside = _cells(out_dir, r, s)
        machine = s.get("machine", {})
        lines.append(f"| {r.label} | {ratio} | {measure} | {beside} | {s.get('fluid_steps', 0)} | "
                     f"{fmt(s.get('fluid_iterations_per_step'), '.1f')} | {s['wall_time_s']:.0f} | "
                     f"{machine.get('numba_threads', '-')} | {machine.get('commit', '-')} |")
    return lines + ["", READING, "", EXPERIMENTS, "", SPLIT, "", KERNEL]
