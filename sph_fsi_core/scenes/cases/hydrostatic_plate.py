"""Water at rest on a plate clamped at both ends (config/hydrostatic_plate.yaml): the standard FSI verification case
(Fourey et al. 2017), coupled. What its file cannot say: the refusals, the relaxation rates of both phases, the
water's force on the whole solid, and the reference.

Fourey, Hermange, Le Touzé & Oger 2017 (Comput. Phys. Commun. 217:66-81), used by DualSPHysics, SPHinXsys and
TrixiParticles; data and peers' results: ../shared/reference/hydrostatic_plate_fourey2017.csv. The plate (span
L = 1 m between clamps, thickness t = 0.05 m, E = 67.5 GPa, nu = 0.3, rho_s = 2700 kg/m^3, its own weight included)
carries a water column 1 m wide and 2 m high (rho_f = 1000 kg/m^3, g = 9.81 m/s^2), across a periodic slab in y
(plane strain). Settled, the plate's mid-span deflects as under the water's hydrostatic pressure: the same answer
as config/clamped_plate.yaml, which loads the plate with that pressure directly. The two together separate the
solid's error from the load transfer's.

Layout, on one cubic lattice of spacing dp with sites at (i + 1/2) dp: the plate x in [0, L], z in [0, t] with
`clamp_layers` layers of fixed solid beyond each end (the clamp faces are x = 0 and x = L, as in clamped_plate);
the water x in [0, L], z in [t, t + H]; the tank's side walls (`wall_layers` fixed wall particles) stand on the
clamps, x < 0 and x > L, from z = t up to `wall_height` above the plate. Open top, periodic along y.

Settling: started from a lattice at rho0, the column first falls until the density correction holds it (the
correction acts above fluid.density_tolerance), then breathes in its first mode: a quarter wave in a column whose
compressibility is the tolerance's, period T_b = 4 H / sqrt(g H / tolerance), 0.18 s for 2 m at 1 %, with little
damping of its own (the 2 m tank's floor pressure still swings +-8 % after 0.4 s). Both phases are relaxed to rest
as a static solver would: the plate by the mass-proportional damping of clamped_plate (`damping_ratio` of its first
dry mode's critical damping), the water's velocities at the rate 2 zeta omega_b of its breathing mode
(`water_damping_ratio` = zeta), each applied per outer step. Neither changes the static answer.

Probe 'midspan': the movable particles nearest mid-span and mid-thickness, as clamped_plate's. Judged on its mean
vertical displacement over the last half of the run against the project's plane-strain FE value for the same
plate under rho_f g H and its own weight (answers/fe_reference.py), with the beam value beside it, and on the
water's total vertical force on the plate against rho_f g H L W (the weight of the column, exact at rest).
"""
import math

import numpy as np

from ...schema import SceneError
from .. import tank
from . import Case, clamped_plate
from .hydrostatic import check_walls_and_span

# evaluate() averages over the last half of the run: the water's push comes in pulses at the fluid step and its
# mean over 50 ms still varies by a few per cent (docs/validation/OPEN.md, 1.0); settled well before (0.15 s at 0.3 s)
SETTLED_FRACTION = 0.5


def layer_counts(values):
    """The plate's (clamped_plate.layer_counts) and the water's and walls' layer counts."""
    c = clamped_plate.layer_counts(values)
    dp = values["numerics.spacing"]
    c["nh"] = tank.whole_layers(values["geometry.water_height"], dp, "geometry.water_height", at_least=2)
    c["nw"] = int(math.ceil(values["geometry.wall_height"] / dp - 1e-9))
    return c


def check(values):
    c = layer_counts(values)
    check_walls_and_span({**values, "geometry.periodic_y": True, "geometry.span_layers": c["ny"]})
    if values["geometry.wall_height"] < values["geometry.water_height"]:
        raise SceneError(f"geometry.wall_height = {values['geometry.wall_height']:g} m: below the water "
                         f"(geometry.water_height = {values['geometry.water_height']:g} m); allowed: at least "
                         f"geometry.water_height")


def relaxation(values, built):
    """The plate's mass-proportional damping (damping_ratio of its first dry mode's critical) and the water's
    relaxation at 2 zeta omega_b of the column's breathing mode (water_damping_ratio = zeta)."""
    return (2.0 * values["geometry.damping_ratio"] * clamped_plate.first_mode_omega(values),
            tank.water_relaxation_rate(values, values["geometry.water_height"]))


def sample_fluid(sim):
    """Extra time-series column: the water's vertical force on the whole solid, clamps included (the pairs that
    reach them past the corners), N, + up, from the last fluid step ('pressure' model; the force on the span alone,
    averaged over the outer step, is the common column coupling_force_z)."""
    coupling = sim.coupling
    if coupling.model != "pressure":     # 'seed' pushes the span's surface only
        return {"water_force_z_all": float((sim.solid.mass * coupling.acc[:, 2]).sum())}
    return {"water_force_z_all": float(coupling.force[:, 2].sum())}


def evaluate(series, values):
    """Mid-span deflection, settled, against plane-strain FE under rho_f g H (clamped_plate's reference), and the
    water's settled vertical force on the plate against the column's weight rho_f g H L W."""
    dp = values["numerics.spacing"]
    c = layer_counts(values)
    height, span = c["nh"] * dp, c["nx"] * dp
    g = -values["scene.gravity"][2]
    pressure = values["fluid.density"] * g * height
    plate_values = {**values, "geometry.load_pressure": pressure, "geometry.load_gradient": 0.0}
    out = clamped_plate.evaluate(series, plate_values, settled_fraction=SETTLED_FRACTION)
    t = series["time"]
    settled = t >= t[-1] * (1.0 - SETTLED_FRACTION)
    weight = values["fluid.density"] * g * height * span * c["ny"] * dp
    force = float(np.mean(series["coupling_force_z"][settled]))
    out["water_load_blocks_n"] = [-f for f in clamped_plate.block_means(series["coupling_force_z"][settled])]
    out.update({
        "hydrostatic_pressure_pa": pressure,
        "water_load_n": -force,
        "water_weight_n": weight,
        "water_load_error": -force / weight - 1.0,
        "water_load_all_n": -float(np.mean(series["water_force_z_all"][settled])),
        "beam_theory_note": "plane-strain Euler-Bernoulli, clamped-clamped, q L^4 / (384 D) with q = rho_f g H + "
                            "rho_s g t (the benchmark's -7.048e-5 m leaves out the plate's weight and shear)",
        "error_metric": "relative error of the settled mid-span deflection against plane-strain FE under rho_f g H "
                        "and the plate's weight",
    })
    return out


CASE = Case("hydrostatic_plate", check=check, relaxation=relaxation, sample_fluid=sample_fluid,
            evaluate=evaluate)
