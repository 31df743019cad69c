"""Lobovsky et al. (2014)'s dam break (config/lobovsky_dam_break.yaml): a square water column H = L = 600 mm
released along a floor as its gate lifts, its surge front against the experiment (reference_data/
lobovsky2014_front_H600.csv, Fig. 12, series ETSIN). What its file cannot say: the refusals of a column and gate that
do not fit the tank, the front's distance x from the gate at every sample, and the judgement:

Z = 1 + x/H, x the front's distance from the gate (the foremost particle's x plus dp/2 less L), against
T = t sqrt(g/H): the RMS relative error of Z over the experiment's points with T >= 1 less the last three (at the far
wall), the best-fit time shift (the simulated front moved later by it) and the RMS after it, and the front speed
dZ/dT fitted on T in [1, 1.6] (to the experiment's last point before the far wall, T = 1.58) against the
experiment's, fitted the same way (1.339; the paper's Table 1: 1.34).
"""
import math

import numpy as np

from ...answers.references import lobovsky_front
from .. import tank
from . import Case
from .dam_break import front_position
from .hydrostatic import check_walls_and_span

JUDGED_FROM_T = 1.0     # judged from T = 1; the experiment's points at the far wall left out
WALL_POINTS = 3
SPEED_WINDOW_T = (1.0, 1.6)


def check(values):
    tank.check_column_in_tank(values, gate_layers=values["geometry.wall_layers"])
    check_walls_and_span(values)


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


CASE = Case("lobovsky_dam_break", check=check, sample_fluid=sample_fluid, evaluate=evaluate)
