"""Where the solid's static error comes from, on case clamp_effect's strips (config/clamped_plate.yaml): each rung's
error split by least squares over the ladder into parts that depend on the strip's length in known ways.

For each rung the plane-strain FE (fe_reference.strip_static, elements of t / 16) gives three numbers:
- the reference read where the SPH probe is: the mean over the probe's particles' initial positions (the mid-span
  probe averages two columns dp / 2 either side of the centre, which bend 0.5 % less than the centre at L / t = 5);
- the shear fraction phi = 1 - w_EB / w_FE: the part of the deflection that Euler-Bernoulli bending leaves out
  (shear and the clamp's 2D stress state), about (t / L)^2;
- the clamp offset's sensitivity s = d ln w / d delta per particle spacing: how much the deflection grows when
  each clamp face moves back by delta (the strip longer by delta at each clamp, unloaded there), about
  8 dp / L clamped at both ends and 4 dp / L as a cantilever (beam theory).
The error against the probe's reference is then fitted as e = a + g phi + d s over the rungs of one support: a
is an error of the bending stiffness that does not depend on the length (the section's), g a relative error of
the shear-like part, d the clamp's offset in spacings. What the cantilever has beyond these is its free end's.
"""
from pathlib import Path

import numpy as np

from ..answers.fe_reference import (cantilever_beam_deflection, clamped_plate_beam_deflection, displacement_at,
                                    strip_static)

ELEMENTS_THROUGH = 16


def strip_terms(values, probe_points):
    """(reference at the probe, phi, s) for one clamped_plate rung (its scene values; the probe's initial
    particle positions as (x, z) pairs from the clamp face x = 0 and the bottom z = 0)."""
    span, t, dp = values["geometry.span"], values["geometry.thickness"], values["numerics.spacing"]
    e, nu, rho = values["solid.young_modulus"], values["solid.poisson_ratio"], values["solid.density"]
    both = values["geometry.supports"] == "clamped_clamped"
    p0, grad = values["geometry.load_pressure"], values["geometry.load_gradient"]
    weight = -rho * values["scene.gravity"][2] * t       # the own weight per area, as a pressure for the offset
    size = t / ELEMENTS_THROUGH

    def solve(offset, weight_as_pressure):
        """u_z(x, z) on the strip with each clamp face moved back by `offset` (unloaded there); the own weight
        as a body force, or as a pressure on the span (a body force cannot be left off the extension)."""
        total = span + (2.0 if both else 1.0) * offset
        extra = weight if weight_as_pressure else 0.0

        def pressure(x):
            on = (x >= offset - 1e-12 * total) & (x <= offset + span + 1e-12 * total)
            return np.where(on, p0 + grad * (x - offset) + extra, 0.0)
        body = (0.0, 0.0) if weight_as_pressure else (0.0, rho * values["scene.gravity"][2])
        u, basis, *_ = strip_static(total, t, e, nu, pressure, body, both, size)
        return lambda x, z: displacement_at(u, basis, x + offset, z)[1]

    as_loaded = solve(0.0, False)
    reference = float(np.mean([as_loaded(x, z) for x, z in probe_points]))
    x_probe = 0.5 * span if both else span - 0.5 * dp
    sensitivity = (solve(0.5 * dp, True)(x_probe, 0.5 * t) / solve(0.0, True)(x_probe, 0.5 * t) - 1.0) / 0.5
    q = p0 + grad * 0.5 * span + weight
    if both:
        euler_bernoulli = -clamped_plate_beam_deflection(span, t, e, nu, q, shear=False)
    else:
        rigidity = e * t ** 3 / (12.0 * (1.0 - nu * nu))
        euler_bernoulli = -cantilever_beam_deflection(span, rigidity, q, x_probe)
    phi = 1.0 - euler_bernoulli / as_loaded(x_probe, 0.5 * t) if grad == 0.0 else float("nan")
    return reference, phi, sensitivity


def fit(errors, phis, sensitivities, with_offset=True):
    """Least squares e = a + g phi (+ d s): returns (a, g, d or None, residuals)."""
    columns = [np.ones(len(errors)), np.asarray(phis)] + ([np.asarray(sensitivities)] if with_offset else [])
    matrix = np.column_stack(columns)
    coef, *_ = np.linalg.lstsq(matrix, np.asarray(errors), rcond=None)
    residuals = np.asarray(errors) - matrix @ coef
    return float(coef[0]), float(coef[1]), (float(coef[2]) if with_offset else None), residuals


def beam_terms(values, probe_points, cache=None):
    """(the 3D FE deflection at the probe, down positive; phi) for one cantilever_loaded rung: the mean of u_z over
    the free end's particle layer under the distributed dead load, elements of dp / 2
    (fe_reference.cantilever_fe_static_deflection; a minute or more for a long beam, so kept in `cache`, a JSON
    file, when given). phi = 1 - w_EB / w_FE at the layer (x = L - dp / 2). `probe_points`: the layer's particles
    as the scene places them (the section centred on y = z = 0)."""
    import json
    from ..scenes.cases.cantilever_loaded import total_load
    from ..answers.fe_reference import cantilever_fe_static_deflection
    length, thickness, width = (values[f"geometry.{k}"] for k in ("length", "thickness", "width"))
    e, nu, dp = values["solid.young_modulus"], values["solid.poisson_ratio"], values["numerics.spacing"]
    force = total_load(values)
    # the scene centres the section on y = z = 0; the FE box is [0, L] x [0, W] x [0, H]
    probe_points = np.asarray(probe_points, dtype=float) + np.array([0.0, 0.5 * width, 0.5 * thickness])
    inputs = {"length": length, "thickness": thickness, "width": width, "young_modulus": e, "poisson_ratio": nu,
              "body_force_z": -force / (length * width * thickness), "element_size": 0.5 * dp,
              "points": [list(map(float, p)) for p in probe_points]}
    stored = json.loads(Path(cache).read_text()) if cache and Path(cache).is_file() else None
    if stored is None or stored.get("inputs") != inputs:
        fe = cantilever_fe_static_deflection(**{k: v for k, v in inputs.items()})
        stored = {"inputs": inputs, "mean_uz_m": fe["mean_uz_m"], "elements": fe["elements"], "dofs": fe["dofs"],
                  "solve_time_s": fe["solve_time_s"]}
        if cache:
            Path(cache).write_text(json.dumps(stored, indent=1) + "\n")
    down = -stored["mean_uz_m"]
    x = float(np.mean([p[0] for p in probe_points]))
    euler_bernoulli = cantilever_beam_deflection(length, e * width * thickness ** 3 / 12.0, force / length, x)
    return down, 1.0 - euler_bernoulli / down


def decompose(rungs, summaries, out_dir=None):
    """Case clamp_effect's rungs that have run: per support (and per 3D beam, "beam3d" and "beam3d_wide"), its rows
    (L / t, the error against FE at the probe, phi, s; the beams without s) and the fits: the strips e = a + g phi
    + d s, with and without d (3 rungs or more); the beams e = a + b H / L and e = a + g phi (2 or more).
    {supports: {"rows": [...], "fit": (a, g, d, residuals), "fit_no_offset": (...)}, "beam3d": {"rows": [...],
    "fit_length": (a, b, residuals), "fit_phi": (a, g, residuals)}}. `out_dir`: where the runs are (the beams' FE
    values are kept there)."""
    from ..scene import load_scene
    from ..scenes import BUILDERS
    from ..scenes.cases import probe_named
    out = {}
    for r in rungs:
        s = summaries.get(r.key)
        if r.case != "clamp_effect" or s is None or s.get("error_signed") is None:
            continue
        spec = load_scene(r.scene, list(r.overrides.items()))
        values = spec.values
        if r.scene == "cantilever_loaded":
            built, _ = spec.build()
            points = built.solid.pos[probe_named(built.probes, "tip").indices]
            cache = Path(out_dir) / "runs" / r.case / r.label / "fe3d_static.json" if out_dir else None
            reference, phi = beam_terms(values, points, cache)
            ratio = values["geometry.length"] / values["geometry.thickness"]
            out.setdefault(r.label.split("_L_over_H_")[0], {"rows": []})["rows"].append(
                (ratio, s["tip_deflection_m"] / reference - 1.0, phi, float("nan")))
            continue
        built = BUILDERS[spec.builder].build(values)
        probe = built.probes[0]                        # the plate's one: midspan, or free_end for a cantilever
        points = [(x, z) for x, _, z in built.solid.pos[probe.indices]]
        reference, phi, sensitivity = strip_terms(values, points)
        measured = s["midspan_deflection_m"] if "midspan_deflection_m" in s else s["free_end_deflection_m"]
        ratio = values["geometry.span"] / values["geometry.thickness"]
        out.setdefault(values["geometry.supports"], {"rows": []})["rows"].append(
            (ratio, measured / reference - 1.0, phi, sensitivity))
    for name, entry in out.items():
        rows = sorted(entry["rows"])
        entry["rows"] = rows
        ratios, errors, phis, sens = (np.array(c) for c in zip(*rows))
        if name.startswith("beam3d") and len(rows) >= 2:
            a, b, _, res = fit(errors, 1.0 / ratios, sens, with_offset=False)
            entry["fit_length"] = (a, b, res)
            a, g, _, res = fit(errors, phis, sens, with_offset=False)
            entry["fit_phi"] = (a, g, res)
        elif not name.startswith("beam3d") and len(rows) >= 3:
            entry["fit"] = fit(errors, phis, sens)
            entry["fit_no_offset"] = fit(errors, phis, sens, with_offset=False)
    return out
