"""Water at rest in a tank: the hydrostatic pressure p = rho g depth, with no particle crossing a wall.

Water: `width` (x) by `depth` (z) on a floor, across a slab of `span_layers` particle layers in y, periodic along y
by default (no side walls: a 2D column with 3D kernels). Walls: `wall_layers` layers of fixed particles under the
floor and beyond both end walls, up to `wall_height`. Gravity -9.81 m/s^2 in z. Judged after settling (the last
30 % of the run) on the pressure at the floor against rho g H, H = depth (the water's height from its volume).
`water_damping_ratio` relaxes the water to rest as scenes/hydrostatic_plate.py does (off by default): with it the
tank is that scene's column on a rigid floor, the fluid's part of the coupled case alone. `water_start: compressed`
builds the water and its end walls as that scene does by default (tank.compress_column).
"""
import math

import numpy as np

from ..schema import Param, SceneError
from . import tank

PHASES = ("fluid", "walls")
CONSERVATIVE = False     # gravity does work while the water settles

GEOMETRY = [
    Param("geometry.width", 0.05, "m", "Water (and tank) width along x", low=0.0, low_inclusive=False, high=10.0),
    Param("geometry.depth", 0.1, "m", "Water depth H along z", low=0.0, low_inclusive=False, high=10.0),
    Param("geometry.wall_height", 0.12, "m", "Height of the tank's end walls above the floor", low=0.0,
          low_inclusive=False, high=20.0),
    Param("geometry.span_layers", 6, "1", "Particle layers across the slab (y)", kind="int", low=1, high=10000),
    Param("geometry.periodic_y", True, "", "Periodic along y (else side walls close the slab)", kind="bool"),
    Param("geometry.wall_layers", 3, "1", "Layers of wall particles (their thickness must reach 2h)", kind="int",
          low=1, high=20),
    Param("geometry.water_damping_ratio", 0.0, "1", "The water's velocity relaxation, as a fraction of the critical "
          "damping of the column's breathing mode (0: none; hydrostatic_plate's relaxation, for the same column "
          "on a rigid floor)", low=0.0, high=100.0),
    Param("geometry.water_start", "lattice", "", "How the water is built: 'lattice' on its lattice with no pressure "
          "(the paper's; it first falls into the correction's band), 'compressed' as the density correction holds "
          "it at rest (compression linear in depth to the tolerance at the floor) with the end walls beside it "
          "compressed the same way (tank.compress_column)", kind="str", choices=tank.WATER_STARTS),
]

DEFAULTS = {"scene.end_time": 1.0, "scene.gravity": (0.0, 0.0, -9.81), "numerics.spacing": 0.0025,
            "output.timeseries_interval": 5.0e-3, "output.snapshot_interval": 0.1}

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
    the neighbour cutoff (2h + skin) wide."""
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


def _sites(values):
    """(nx, nz): the water's sites along x (the tank's inside too) and z."""
    dp = values["numerics.spacing"]
    return (tank.whole_layers(values["geometry.width"], dp, "geometry.width"),
            tank.whole_layers(values["geometry.depth"], dp, "geometry.depth"))


def particle_counts(values):
    """The particles build() makes, per phase, without making them (the memory guard's estimate)."""
    nx, nz = _sites(values)
    return tank.column_in_tank_counts(values, nx, nz, nx)


def build(values):
    dp = values["numerics.spacing"]
    nx, nz = _sites(values)
    wall_top = math.ceil(values["geometry.wall_height"] / dp - 1e-9) * dp
    built = tank.column_in_tank(values, nx, nz, nx, margin=0.5 * wall_top)
    tank.build_water_start(values, 0.0, nz * dp, built.fluid.pos, built.walls.pos)
    built.fluid_damping_rate = tank.water_relaxation_rate(values, nz * dp)
    return built


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
