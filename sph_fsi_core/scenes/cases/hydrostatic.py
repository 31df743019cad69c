"""Water at rest in a tank (config/hydrostatic.yaml): the hydrostatic pressure p = rho g depth, no particle crossing
a wall. What its file cannot say: the refusals of widths that are not whole spacings, the floor pressure fitted
through the water at every sample, the water's relaxation rate from its column's breathing mode, and the judgement
of the settled floor pressure against rho g H (the last 30 % of the run).

`water_damping_ratio` relaxes the water to rest as the hydrostatic plate does (off by default): with it the tank is
that scene's column on a rigid floor, the fluid's part of the coupled case alone.
"""
import math

import numpy as np

from ...schema import SceneError
from .. import tank
from . import Case

SETTLED_FRACTION = 0.3   # evaluate() averages over the last 30 % of the run


def check(values):
    dp = values["numerics.spacing"]
    tank.whole_layers(values["geometry.width"], dp, "geometry.width", at_least=2)
    tank.whole_layers(values["geometry.depth"], dp, "geometry.depth", at_least=2)
    check_walls_and_span(values)
    if values["geometry.wall_height"] < values["geometry.depth"]:
        raise SceneError(f"geometry.wall_height = {values['geometry.wall_height']:g} m: below the water depth "
                         f"{values['geometry.depth']:g} m; allowed: at least geometry.depth")


def check_walls_and_span(values):
    """Walls at least 2h thick (else the kernel reaches past them and water leaks); a periodic slab at least twice
    the neighbour cutoff (2h + skin) wide (the tanks' keys geometry.wall_layers, span_layers and periodic_y)."""
    dp = values["numerics.spacing"]
    h = values["numerics.smoothing_ratio"] * dp
    need = math.ceil(2.0 * h / dp - 1e-9)
    if values["geometry.wall_layers"] < need:
        raise SceneError(f"geometry.wall_layers = {values['geometry.wall_layers']}: thinner than the kernel's reach "
                         f"2h = {2 * h / dp:.3g} dp; allowed: at least {need}")
    if values["geometry.periodic_y"]:
        cutoff = (2.0 + values["numerics.neighbour_skin"]) * h
        need = math.ceil(2.0 * cutoff / dp - 1e-9)
        if values["geometry.span_layers"] < need:
            raise SceneError(f"geometry.span_layers = {values['geometry.span_layers']}: a periodic slab must be at "
                             f"least twice the neighbour cutoff (2h + skin) wide; allowed: at least {need}")


def depth_built(values):
    """The water's depth as built, whole layers, m."""
    return tank.whole_layers(values["geometry.depth"], values["numerics.spacing"], "geometry.depth") \
        * values["numerics.spacing"]


def relaxation(values, built):
    """No solid; the water's velocities relax at 2 zeta omega_b of its column (tank.water_relaxation_rate)."""
    return 0.0, tank.water_relaxation_rate(values, depth_built(values))


def floor_pressure_fit(pos, pressure, width, depth, h):
    """Least-squares line p = p_floor + slope z through the particles at least 2h from the floor, the surface and
    the end walls (where the kernel is cut); returns (p_floor, slope). NaN if too few particles."""
    x, z = pos[:, 0], pos[:, 2]
    inner = (z > 2.0 * h) & (z < depth - 2.0 * h) & (x > 2.0 * h) & (x < width - 2.0 * h)
    if inner.sum() < 3 or np.ptp(z[inner]) <= 0.0:
        return float("nan"), float("nan")
    slope, intercept = np.polyfit(z[inner], pressure[inner], 1)
    return float(intercept), float(slope)


def sample_fluid(sim):
    """Time-series columns: floor pressure (line fit, extrapolated to z = 0), the bottom layer's mean pressure,
    the floor's load per area (the walls' push on the water, sum m a_correction / area), the pressure profile's
    RMS deviation from rho g (H - z) over rho g H, particles outside the tank, total mass."""
    v = sim.spec.values
    f = sim.fluid
    dp, depth, width = v["numerics.spacing"], v["geometry.depth"], v["geometry.width"]
    g = abs(v["scene.gravity"][2])
    rho0 = v["fluid.density"]
    p_floor, slope = floor_pressure_fit(f.pos, f.pressure, width, depth, sim.h)
    bottom = f.pos[:, 2] < dp
    dt = sim.fluid_phase.last_dt
    area = width * v["geometry.span_layers"] * dp
    load = (float((f.mass * f.correction_displacement[:, 2]).sum()) / (dt * dt * area)) if dt > 0 else 0.0
    inner = (f.pos[:, 0] > 2.0 * sim.h) & (f.pos[:, 0] < width - 2.0 * sim.h)
    ref = rho0 * g * (depth - f.pos[inner, 2])
    rms = float(np.sqrt(np.mean((f.pressure[inner] - ref) ** 2))) / (rho0 * g * depth)
    outside = tank.outside_tank(f.pos, width, v["geometry.span_layers"] * dp, v["geometry.periodic_y"], dp)
    return {"floor_pressure": p_floor, "pressure_slope": slope,
            "bottom_layer_pressure": float(f.pressure[bottom].mean()), "floor_load_pressure": load,
            "pressure_profile_rms": rms, "outside_walls": int(outside.sum()), "fluid_mass": float(f.mass.sum())}


def evaluate(series, values):
    """Floor pressure against rho g H after settling; the profile; wall crossings; mass."""
    g = abs(values["scene.gravity"][2])
    rho0, depth, dp = values["fluid.density"], values["geometry.depth"], values["numerics.spacing"]
    ref = rho0 * g * depth
    t = series["time"]
    settled = t >= (1.0 - SETTLED_FRACTION) * t[-1]
    p_floor = float(np.mean(series["floor_pressure"][settled]))
    bottom = float(np.mean(series["bottom_layer_pressure"][settled]))
    load = float(np.mean(series["floor_load_pressure"][settled]))
    slope = float(np.mean(series["pressure_slope"][settled]))
    mass = series["fluid_mass"]
    return {
        "reference_floor_pressure_pa": ref, "floor_pressure_pa": p_floor,
        "floor_pressure_error": (p_floor - ref) / ref,
        "bottom_layer_pressure_pa": bottom, "bottom_layer_reference_pa": rho0 * g * (depth - 0.5 * dp),
        "bottom_layer_error": (bottom - rho0 * g * (depth - 0.5 * dp)) / ref,
        "floor_load_pressure_pa": load, "floor_load_error": (load - ref) / ref,
        "pressure_gradient_over_rho_g": -slope / (rho0 * g),
        "pressure_profile_rms_over_rho_g_h": float(np.mean(series["pressure_profile_rms"][settled])),
        "max_particles_outside_walls": int(series["outside_walls"].max()),
        "mass_change_kg": float(np.max(np.abs(mass - mass[0]))),
        "iterations_mean": float(np.mean(series["iterations_mean"][1:])) if len(t) > 1 else 0.0,
        "iterations_max": int(np.max(series["iterations_max"])),
        "error_metric": "relative error of the floor pressure (line fit of p(z), settled) against rho g H",
        "error": abs(p_floor - ref) / ref,
    }


CASE = Case("hydrostatic", check=check, relaxation=relaxation, sample_fluid=sample_fluid, evaluate=evaluate)
