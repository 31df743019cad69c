"""The cantilever's first bending frequency from assembled stiffness matrices (validation/linear_modes.py): the
quadratic fit's plain sum against its own time-stepped runs (the module's cross-check), and total-Lagrangian SPH on
the same beams against 3D FE (a candidate for the default scheme).

    python -m sph_fsi_core.validation.linear_modes_table --out docs/validation/linear_modes

writes REPORT.md there (about 8 minutes on one core).
"""
import argparse
import json
import time
from pathlib import Path

from .cases.cantilever_shapes import CANTILEVER_SHAPE_POISSON, CANTILEVER_SHAPE_SLENDERNESS
from .linear_modes import (cantilever_frequency, clamped_plate_deflection, default_scheme_stable_cfl,
                           gate_loaded_deflection, implicit_step_iterations)

# The quadratic_plain beams time-stepped (solid.scheme = quadratic_plain: the fixed clamp with its 5-layer margin,
# explicit pressure, 2.25 periods), Hz: docs/validation/studies/schemes/REPORT.md, rows
# cantilever_plain_ladder/H_over_dp_{4,6,8} (L = 40 mm) and cantilever_plain_length/L{60,80,100,120} (dp = 1 mm)
TIME_STEPPED_QUADRATIC_PLAIN = {(4, 40): 16.672, (6, 40): 17.057, (8, 40): 17.208, (4, 60): 7.451, (4, 80): 4.201,
                                (4, 100): 2.691, (4, 120): 1.870}

# The default scheme's static answers time-stepped (explicit pressure, the mirrored clamp), error against
# plane-strain FE, %: docs/validation/studies/solid_static/REPORT.md (quadratic_gradient_mirrored_t_over_dp_{4,6,8,10})
# and docs/validation/studies/gate_static/REPORT.md (loaded_gradient_mirrored_dp{1.67,1.25}mm)
TIME_STEPPED_PLATE = {4: 2.64, 6: 1.23, 8: 0.73, 10: 0.50}
TIME_STEPPED_GATE = {(0.005 / 3, "5/3"): 1.69, (0.00125, "1.25"): 1.09}

# Ganzenmueller's hourglass coefficient: TrixiParticles' PenaltyForceGanzenmueller default
HOURGLASS_ALPHA = 0.1

SHAPES_RUNS = Path("docs/validation/studies/cantilever_shapes/runs/cantilever_shapes")


def _row(overrides, **kw):
    start = time.perf_counter()
    r = cantilever_frequency(overrides, **kw)
    r["wall_s"] = time.perf_counter() - start
    return r


def _default_scheme_error(nu, ratio):
    """The default scheme's time-stepped error against 3D FE on the same beam (case cantilever_shapes, its kept
    run), per cent, or None."""
    path = SHAPES_RUNS / f"nu{nu:g}_L_over_H_{ratio}" / "summary.json"
    if not path.exists():
        return None
    summary = json.loads(path.read_text())
    return summary.get("error_vs_fe3d_percent")


def report():
    lines = ["# A solid's stiffness assembled: beams, static plates and gates, the stable step", "",
             "Made by `python -m sph_fsi_core.validation.linear_modes_table --out docs/validation/linear_modes`. "
             "Each row assembles a particle solid's small-strain stiffness K = B^T (V C) B on the beam as built "
             "(the cantilever scene, its clamp's particles fixed) and solves K phi = omega^2 M phi for its lowest "
             "modes (validation/linear_modes.py): the frequency its time stepping converges to at small amplitude "
             "and step. Wall: assembly and eigensolve, one core. The 3D FE reference of each beam: "
             "answers/references.py (the project's extrapolated meshes).", "",
             "## Cross-check: the quadratic fit's plain sum against its time-stepped runs", "",
             "The fixed clamp with its 5-layer margin, as `solid.scheme: quadratic_plain` ran "
             "(docs/validation/studies/schemes/REPORT.md, cantilever_plain_ladder and cantilever_plain_length).", "",
             "| H/dp | L [mm] | assembled [Hz] | time-stepped [Hz] | difference | vs 3D FE (assembled) | wall [s] |",
             "|---|---|---|---|---|---|---|"]
    for (through, length), stepped in TIME_STEPPED_QUADRATIC_PLAIN.items():
        r = _row([f"numerics.spacing={0.004 / through!r}", f"geometry.length={length * 1e-3!r}"],
                 weights="quadratic_fit")
        lines.append(f"| {through} | {length} | {r['frequency_hz']:.4f} | {stepped:.3f} | "
                     f"{100 * (r['frequency_hz'] / stepped - 1):+.3f} % | {100 * r['error']:+.2f} % | "
                     f"{r['wall_s']:.1f} |")
    lines += ["", "## Total-Lagrangian SPH on the paper's beam (L = 40 mm, 4 x 6 mm, nu = 0.49)", "",
              "The kernel gradient corrected on the reference configuration (O'Connor & Rogers 2021; TrixiParticles, "
              "SPHinXsys, DualSPHysics flexstruc), the variationally consistent force, the clamp's particles fixed "
              "behind the root only (no margin: the mirrored clamp's lesson, docs/validation/studies/clamp_effect); "
              f"with and without Ganzenmueller's hourglass penalty (alpha = {HOURGLASS_ALPHA:g}, TrixiParticles' "
              "default). Beside it the quadratic fit's plain sum on the same beam and clamp. Spurious: modes below "
              "the first bending mode.", "",
              "| H/dp | TL-SPH | spurious | TL-SPH, hourglass | spurious | quadratic fit, plain sum | wall [s] |",
              "|---|---|---|---|---|---|---|"]
    for through in (4, 6, 8):
        base = [f"numerics.spacing={0.004 / through!r}", "geometry.clamp_margin=0"]
        bare = _row(base)
        hg = _row(base, hourglass_alpha=HOURGLASS_ALPHA)
        quad = _row(base, weights="quadratic_fit")
        lines.append(f"| {through} | {bare['frequency_hz']:.3f} Hz ({100 * bare['error']:+.2f} %) | "
                     f"{bare['spurious_modes_below']} | {hg['frequency_hz']:.3f} Hz ({100 * hg['error']:+.2f} %) | "
                     f"{hg['spurious_modes_below']} | {quad['frequency_hz']:.3f} Hz ({100 * quad['error']:+.2f} %) | "
                     f"{bare['wall_s'] + hg['wall_s'] + quad['wall_s']:.1f} |")
    lines += ["", "## Over shapes and materials at 4 particles through", "",
              "The cantilever_shapes beams (4 x 6 mm section, dp = 1 mm), each against its own 3D FE: "
              "total-Lagrangian SPH (the clamp's particles fixed behind the root, hourglass alpha = "
              f"{HOURGLASS_ALPHA:g}), and the default scheme (`quadratic_gradient`: the quadratic fit with the "
              "strain-gradient integration, the mirrored clamp) assembled here and time-stepped (case "
              "cantilever_shapes, its kept runs: explicit pressure, 2.25 periods; its frequency is the implicit "
              "pressure's to 0.01 %, docs/validation/studies/solid_pressure).", "",
              "The last column: the default scheme with the strain-gradient term's volumetric part too (the energy "
              "of each cell's strain gradient in full, not only its deviator; not the scheme's: docs/method.md, "
              "\"Strain-gradient nodal integration\").", "",
              "| nu | L/H | TL-SPH | default scheme, assembled | default scheme, time-stepped | with the volumetric "
              "gradient, assembled | wall [s] |",
              "|---|---|---|---|---|---|---|"]
    for nu in CANTILEVER_SHAPE_POISSON:
        for ratio in CANTILEVER_SHAPE_SLENDERNESS:
            beam = [f"geometry.length={ratio * 0.004!r}", f"solid.poisson_ratio={nu!r}"]
            tl = _row(beam + ["geometry.clamp_margin=0"], hourglass_alpha=HOURGLASS_ALPHA)
            default = _row(beam, weights="quadratic_fit", nodal_integration="gradient", clamp="mirrored")
            full = _row(beam, weights="quadratic_fit", nodal_integration="gradient", clamp="mirrored",
                        volumetric_gradient=True)
            stepped = _default_scheme_error(nu, ratio)
            shown = f"{stepped:+.2f} %" if stepped is not None else "not run"
            lines.append(f"| {nu:g} | {ratio} | {tl['frequency_hz']:.4g} Hz ({100 * tl['error']:+.2f} %) | "
                         f"{default['frequency_hz']:.4g} Hz ({100 * default['error']:+.3f} %) | {shown} | "
                         f"{100 * full['error']:+.3f} % | {tl['wall_s'] + default['wall_s'] + full['wall_s']:.1f} |")
    lines += ["", "## Under a static load: the default scheme, and with the volumetric gradient", "",
              "The static verification cases' solids alone (docs/validation/OPEN.md 1.0), K u = f assembled and "
              "solved: clamped_plate (the hydrostatic plate's plate under its water's exact pressure and its own "
              "weight, a periodic slab) and antoci_gate_loaded (Antoci's gate under its water's exact pressure at "
              "g = 1 m/s^2), each against its plane-strain FE; the time-stepped runs beside (docs/validation/"
              "studies/solid_static, gate_static). The time-stepped gate deflects 5 % of its length, where this "
              "answer is linear.", "",
              "| case | spacing | default scheme, assembled | time-stepped | with the volumetric gradient, assembled | "
              "wall [s] |", "|---|---|---|---|---|---|"]
    for through, stepped in TIME_STEPPED_PLATE.items():
        start = time.perf_counter()
        base = clamped_plate_deflection([f"numerics.spacing={0.05 / through!r}"])
        full = clamped_plate_deflection([f"numerics.spacing={0.05 / through!r}"], volumetric_gradient=True)
        lines.append(f"| the plate | {through} through | {100 * base['error']:+.3f} % | {stepped:+.2f} % | "
                     f"{100 * full['error']:+.3f} % | {time.perf_counter() - start:.1f} |")
    for (dp, label), stepped in TIME_STEPPED_GATE.items():
        start = time.perf_counter()
        base = gate_loaded_deflection([f"numerics.spacing={dp!r}"])
        full = gate_loaded_deflection([f"numerics.spacing={dp!r}"], volumetric_gradient=True)
        lines.append(f"| Antoci's gate | {label} mm | {100 * base['error']:+.3f} % | {stepped:+.2f} % | "
                     f"{100 * full['error']:+.3f} % | {time.perf_counter() - start:.1f} |")
    lines += ["", "## The default scheme's stable step", "",
              "The largest `solid.cfl` (dt = cfl h / c_dev, c_dev = sqrt(4 G / 3 rho): solid/solver.py) at which the "
              "default scheme's explicit part (the deviatoric stress and its gradient; the pressure is implicit) is "
              "linearly stable on the beam at rest: 2 / omega_max of its deviatoric stiffness, the mirrored clamp's "
              "ghosts following their images. The scheme runs at 0.25. With `solid.volumetric_gradient` the strain "
              "gradient's volumetric part is stepped explicitly too (its limit in the last column; solid/solver.py's "
              "VOLUMETRIC_GRADIENT_WAVE keeps the step's margin from it).", "",
              "| nu | H/dp | largest stable cfl | with the volumetric gradient | wall [s] |", "|---|---|---|---|---|"]
    for nu in (*CANTILEVER_SHAPE_POISSON[:2], 0.45, CANTILEVER_SHAPE_POISSON[2]):
        for through in (4, 6):
            start = time.perf_counter()
            beam = [f"solid.poisson_ratio={nu!r}", f"numerics.spacing={0.004 / through!r}"]
            cfl = default_scheme_stable_cfl(beam)
            full = default_scheme_stable_cfl(beam, volumetric_gradient=True)
            lines.append(f"| {nu:g} | {through} | {cfl:.3f} | {full:.3f} | {time.perf_counter() - start:.1f} |")
    start = time.perf_counter()
    iterations = implicit_step_iterations((1, 4, 8, 16, 22))
    lines += ["", "## A solid step as long as the fluid's, implicit", "",
              "The paper's gate takes 22 solid steps per fluid step (docs/validation/OPEN.md 5). One implicit step "
              "(Newmark's average acceleration) of the default scheme's deviatoric stiffness on the paper's beam, "
              "(M + dt^2 / 4 K) x = b, solved by Jacobi-preconditioned conjugate gradients to 1e-4 from zero: each "
              "iteration applies the stiffness once, as one explicit step does "
              f"({time.perf_counter() - start:.1f} s).", "",
              "| step / explicit step | iterations | explicit steps it replaces |", "|---|---|---|"]
    lines += [f"| {ratio} | {count} | {ratio} |" for ratio, count in iterations.items()]
    return "\n".join(lines) + "\n"


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", type=Path, default=Path("docs/validation/linear_modes"))
    args = parser.parse_args(argv)
    text = report()
    args.out.mkdir(parents=True, exist_ok=True)
    (args.out / "REPORT.md").write_text(text)
    print(text)


if __name__ == "__main__":
    main()
