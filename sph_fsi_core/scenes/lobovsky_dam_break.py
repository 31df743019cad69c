"""Lobovsky et al. (2014)'s dam break: a square water column H = L = 600 mm released along a floor, its surge
front against the experiment (reference_data/lobovsky2014_front_H600.csv, Fig. 12, series ETSIN).

Column: L along x (from the tank's upstream wall at x = 0) by H along z, on the floor z = 0; tank 1.61 m long
(the far wall 1.01 m from the gate); a periodic slab of `span_layers` particle layers across y (a thin slab of the
experiment's 600 mm wide tank, i.e. 2D; `periodic_y: false` closes it with side walls).

Release (`geometry.release`): `lifted` (the default), the gate (a wall `wall_layers` thick at the column's face, as
high as the walls) moving up at `geometry.gate_speed` (the experiment's median 4.53 m/s) from t = 0, the gate's first
motion, until its foot is a column height plus two smoothing lengths above the floor; or `instant`, the gate gone at t
= 0 (the water released at once, as Martin & Moyce's reduction assumes). With fluid.settle_time (default here 0.3 s,
about three of the column's breathing periods) the water first settles behind the gate to hydrostatic pressure
(simulation.py), as the experiment's water was at rest behind its gate.

Judged (evaluate) on Z = 1 + x/H, x the front's distance from the gate (the foremost particle's x plus dp/2 less
L), against T = t sqrt(g/H): the RMS relative error of Z over the experiment's points with T >= 1 less the last
three (at the far wall), the best-fit time shift (the simulated front moved later by it) and the RMS after it, and
the front speed dZ/dT fitted on T in [1, 1.6] (to the experiment's last point before the far wall, T = 1.58)
against the experiment's, fitted the same way (1.339; the paper's Table 1: 1.34).
"""
import math
from dataclasses import replace

import numpy as np

from ..schema import Param
from ..answers.references import lobovsky_front
from . import tank
from .dam_break import front_position
from .hydrostatic import check_walls_and_span

PHASES = ("fluid", "walls")
CONSERVATIVE = False

COLUMN = 0.6            # m, H = L (Lobovsky et al. 2014, the H = 600 mm series)
JUDGED_FROM_T = 1.0     # judged from T = 1; the experiment's points at the far wall left out
WALL_POINTS = 3
SPEED_WINDOW_T = (1.0, 1.6)

GEOMETRY = [
    Param("geometry.column_width", COLUMN, "m", "Column length L along x (Lobovsky et al.: 600 mm)", low=0.0,
          low_inclusive=False, high=100.0),
    Param("geometry.column_height", COLUMN, "m", "Column height H along z (600 mm)", low=0.0, low_inclusive=False,
          high=100.0),
    Param("geometry.tank_length", 1.61, "m", "Tank length along x (rounded to whole spacings; the experiment's "
          "1.61 m)", low=0.0, low_inclusive=False, high=1000.0),
    Param("geometry.wall_height", 0.7, "m", "Height of the tank's walls and of the gate above the floor", low=0.0,
          low_inclusive=False, high=1000.0),
    Param("geometry.span_layers", 6, "1", "Particle layers across the slab (y)", kind="int", low=1, high=10000),
    Param("geometry.periodic_y", True, "", "Periodic along y (else side walls close the slab)", kind="bool"),
    Param("geometry.wall_layers", 3, "1", "Layers of wall particles (their thickness must reach 2h)", kind="int",
          low=1, high=20),
    Param("geometry.release", "lifted", "", "How the column is released at t = 0: 'lifted' (the gate moving up at "
          "geometry.gate_speed, the experiment's) or 'instant' (the gate gone)", kind="str",
          choices=("instant", "lifted")),
    Param("geometry.gate_speed", 4.53, "m/s", "The lifted gate's speed (Lobovsky et al.: a median 4.53 m/s)",
          low=0.0, low_inclusive=False, high=1000.0),
]

# the experiment's procedure: the water at rest behind the gate (settled: docs/method.md, "The start"), the gate
# lifted at the measured speed
DEFAULTS = {"scene.end_time": 0.4, "scene.gravity": (0.0, 0.0, -9.81), "numerics.spacing": COLUMN / 60,
            "fluid.settle_time": 0.3, "output.timeseries_interval": 2.5e-3, "output.snapshot_interval": 0.02}


def check(values):
    tank.check_column_in_tank(values, gate_layers=values["geometry.wall_layers"])
    check_walls_and_span(values)


def particle_counts(values):
    return tank.column_in_tank_counts(values, *tank.column_sites(values))


def lift_travel(values):
    """How far the lifted gate moves: its foot a column height plus 2h (the kernel's reach) above the floor, m."""
    dp = values["numerics.spacing"]
    return tank.column_sites(values)[1] * dp + 2.0 * values["numerics.smoothing_ratio"] * dp


def build(values):
    dp = values["numerics.spacing"]
    nx, nz, ntank = tank.column_sites(values)
    wall_top = math.ceil(values["geometry.wall_height"] / dp - 1e-9) * dp
    if values["geometry.release"] == "instant":
        return tank.column_in_tank(values, nx, nz, ntank, margin=wall_top)
    travel = lift_travel(values)
    built = tank.column_in_tank(values, nx, nz, ntank, margin=wall_top + travel)   # the lifted gate stays inside
    return replace(built, release_velocity=np.array([0.0, 0.0, values["geometry.gate_speed"]]),
                   release_travel=travel)


def sample_fluid(sim):
    """Time-series columns: the front's distance from the gate x [m], Z = 1 + x/H, T = t sqrt(g/H), particles
    outside the tank."""
    v = sim.spec.values
    dp = v["numerics.spacing"]
    nx, nz, ntank = tank.column_sites(v)
    height = nz * dp
    g = abs(v["scene.gravity"][2])
    x = front_position(sim.fluid.pos, dp) - nx * dp
    outside = tank.outside_tank(sim.fluid.pos, ntank * dp, v["geometry.span_layers"] * dp, v["geometry.periodic_y"],
                                dp)
    return {"front_x": x, "front_Z": 1.0 + x / height, "T": sim.time * math.sqrt(g / height),
            "outside_walls": int(outside.sum())}


def _judged_points(t_run):
    ref_t, ref_z = lobovsky_front()
    keep = np.arange(len(ref_t)) < len(ref_t) - WALL_POINTS
    use = keep & (ref_t >= JUDGED_FROM_T) & (ref_t <= t_run[-1])
    return ref_t[use], ref_z[use]


def _slope(t, z, window):
    sel = (t >= window[0]) & (t <= window[1])
    return float(np.polyfit(t[sel], z[sel], 1)[0]) if sel.sum() >= 2 else float("nan")


def evaluate(series, values):
    """The front against the experiment: RMS relative error of Z over T >= 1 (the far wall's points left out), the
    best time shift in [-0.5, 0.5] (steps of 0.002) and the RMS after it, and dZ/dT on T in [1, 1.6]."""
    t_run, z_run = np.asarray(series["T"]), np.asarray(series["front_Z"])
    ref_t, ref_z = _judged_points(t_run)
    if len(ref_t) == 0:
        return {"front_rms_relative_error": None, "error": None,
                "error_metric": "not judged: the run ends before T = 1"}
    z_sim = np.interp(ref_t, t_run, z_run)
    rel = (z_sim - ref_z) / ref_z
    rms = float(np.sqrt(np.mean(rel ** 2)))
    best = (float("inf"), 0.0)
    for shift in np.arange(-0.5, 0.5 + 1e-9, 0.002):
        z = np.interp(ref_t - shift, t_run, z_run)
        best = min(best, (float(np.sqrt(np.mean(((z - ref_z) / ref_z) ** 2))), float(shift)))
    all_t, all_z = lobovsky_front()
    exp_t, exp_z = all_t[:-WALL_POINTS], all_z[:-WALL_POINTS]
    window = (SPEED_WINDOW_T[0], min(SPEED_WINDOW_T[1], exp_t[-1]))   # up to the experiment's last free point
    speed, speed_exp = _slope(t_run, z_run, window), _slope(exp_t, exp_z, window)
    return {"front_points": [{"T": float(t), "Z_experiment": float(ze), "Z_simulated": float(zs),
                              "relative_error": float(e)} for t, ze, zs, e in zip(ref_t, ref_z, z_sim, rel)],
            "front_rms_relative_error": rms, "front_time_shift_T": round(best[1], 3),
            "front_rms_after_time_shift": best[0], "front_speed_dZdT": speed,
            "front_speed_dZdT_experiment": speed_exp, "front_speed_error": speed / speed_exp - 1.0,
            "release": values["geometry.release"], "error": rms,
            "max_particles_outside_walls": int(np.max(series["outside_walls"])),
            "error_metric": "RMS relative error of the surge front Z = 1 + x/H against Lobovsky et al. 2014 "
                            "(H = 600 mm) over T >= 1, the far wall's points left out"}
