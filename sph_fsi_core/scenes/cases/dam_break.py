"""Martin & Moyce 1952's collapsing water column (config/dam_break.yaml): the surge front against their measured
positions. What its file cannot say: the refusals of a column that does not fit its tank, the front (the foremost
particle's x plus dp/2, the edge of its volume, so Z(0) = 1) and Z = x_front / a, T = t sqrt(2 g / a) at every sample,
and the judgement of Z(T) against reference_data/martin_moyce_1952_a57mm.csv up to T = 3: relative error per point and
their RMS, with the start delay and the front speed as diagnostics.
"""
import math

import numpy as np

from ...answers.references import martin_moyce_front
from .. import tank
from . import Case
from .hydrostatic import check_walls_and_span

EVALUATE_UP_TO_T = 3.0   # judged up to T = 3; later the surge reaches the far wall of a short tank


def check(values):
    tank.check_column_in_tank(values)
    check_walls_and_span(values)


def front_position(pos, spacing):
    """The surge front: the foremost fluid particle's x plus dp/2 (its volume's edge)."""
    return float(pos[:, 0].max()) + 0.5 * spacing


def sample_fluid(sim):
    """Time-series columns: front x [m], Z = x_front / a, T = t sqrt(2 g / a), particles outside the tank."""
    v = sim.spec.values
    a = v["geometry.column_width"]
    g = abs(v["scene.gravity"][2])
    dp = v["numerics.spacing"]
    front = front_position(sim.fluid.pos, dp)
    length = round(v["geometry.tank_length"] / dp) * dp
    outside = tank.outside_tank(sim.fluid.pos, length, v["geometry.span_layers"] * dp, v["geometry.periodic_y"], dp)
    return {"front_x": front, "front_Z": front / a, "T": sim.time * math.sqrt(2.0 * g / a),
            "outside_walls": int(outside.sum())}


def evaluate(series, values):
    """Z(T) interpolated at Martin & Moyce's T <= 3 (within the run): relative error per point and RMS."""
    ref_t, ref_z = martin_moyce_front()
    t_run = series["T"]
    use = (ref_t <= min(EVALUATE_UP_TO_T, t_run[-1]))
    z_sim = np.interp(ref_t[use], t_run, series["front_Z"])
    rel = (z_sim - ref_z[use]) / ref_z[use]
    points = [{"T": float(t), "Z_experiment": float(ze), "Z_simulated": float(zs), "relative_error": float(e)}
              for t, ze, zs, e in zip(ref_t[use], ref_z[use], z_sim, rel)]
    rms = float(np.sqrt(np.mean(rel ** 2))) if len(rel) else float("nan")
    shift, rms_shifted = _best_time_shift(t_run, series["front_Z"], ref_t[use], ref_z[use])
    slope_sim, slope_exp = _front_speed(t_run, series["front_Z"], ref_t, ref_z)
    return {"front_points": points, "front_rms_relative_error": rms,
            "front_time_shift_T": shift, "front_rms_after_time_shift": rms_shifted,
            "front_speed_dZdT": slope_sim, "front_speed_dZdT_experiment": slope_exp,
            "front_max_relative_error": float(np.max(np.abs(rel))) if len(rel) else float("nan"),
            "max_particles_outside_walls": int(series["outside_walls"].max()),
            "iterations_mean": float(np.mean(series["iterations_mean"][1:])) if len(t_run) > 1 else 0.0,
            "iterations_max": int(np.max(series["iterations_max"])),
            "capped_steps": int(np.sum(series["capped_steps"])),
            "error_metric": "RMS relative error of the surge front Z = x/a against Martin & Moyce 1952 "
                            "(reference_data/martin_moyce_1952_a57mm.csv), T <= 3",
            "error": rms}


def _best_time_shift(t_run, z_run, ref_t, ref_z):
    """Diagnostic, not the score: the delay dT (0..1, step 0.005) by which the simulated Z(T) must be shifted
    later to fit the experiment best, and the RMS relative error after it. Martin & Moyce's column started as the
    gate was withdrawn, which the simulation does not model; a constant lead shows up here."""
    if len(ref_t) == 0:
        return float("nan"), float("nan")
    best = (float("inf"), 0.0)
    for shift in np.arange(0.0, 1.0 + 1e-9, 0.005):
        z = np.interp(ref_t - shift, t_run, z_run)
        rms = float(np.sqrt(np.mean(((z - ref_z) / ref_z) ** 2)))
        best = min(best, (rms, float(shift)))
    return best[1], best[0]


def _front_speed(t_run, z_run, ref_t, ref_z, window=(1.5, 3.0)):
    """Mean front speed dZ/dT over T in `window`: least-squares slope of the simulated Z(T) and of the
    experimental points in that window (independent of the start delay)."""
    sim = (t_run >= window[0]) & (t_run <= window[1])
    exp = (ref_t >= window[0]) & (ref_t <= window[1] + 0.5)
    s_sim = float(np.polyfit(t_run[sim], z_run[sim], 1)[0]) if sim.sum() >= 2 else float("nan")
    s_exp = float(np.polyfit(ref_t[exp], ref_z[exp], 1)[0]) if exp.sum() >= 2 else float("nan")
    return s_sim, s_exp


CASE = Case("dam_break", check=check, sample_fluid=sample_fluid, evaluate=evaluate)
