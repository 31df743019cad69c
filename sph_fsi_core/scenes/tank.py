"""What the water's scenes share: a column at rest (its breathing mode, its relaxation, its compression as the density
correction holds it) and the tank scenes' refusals and checks (whole layers, a column that fits its tank, water
that crossed a wall). The geometry builder compresses a water part with it (geometry.water_start); the case modules
(scenes/cases) judge and relax with it.

A tank scene's inside is x in [0, length], z >= 0 and, across, y in [0, span]: periodic along y (a slab of `span`
with no side walls) or closed by walls at y = 0 and y = span.
"""
import math

import numpy as np

from ..schema import SceneError


def breathing_period(height, gravity, tolerance):
    """T_b = 4 H / c_b, c_b = sqrt(g H / tolerance), s: a column's first mode as a quarter-wave resonator whose
    compressibility is what the density tolerance allows (the density correction acts only above it). It sets
    the water's relaxation rate in the static cases (the hydrostatic plate, Antoci's gate at rest); without
    gravity, 9.81 m/s^2 (the rate only shortens the way to rest)."""
    g = math.sqrt(sum(x * x for x in gravity)) or 9.81
    return 4.0 * height / math.sqrt(g * height / tolerance)


def water_relaxation_rate(values, height):
    """2 zeta omega_b (1/s), the static scenes' relaxation of the water's velocities (hydrostatic_plate,
    antoci_gate_static, hydrostatic): zeta = geometry.water_damping_ratio, omega_b the breathing mode of a column
    `height` deep (breathing_period)."""
    period = breathing_period(height, values["scene.gravity"], values["fluid.density_tolerance"])
    return 2.0 * values["geometry.water_damping_ratio"] * 2.0 * math.pi / period


# geometry.water_start of the static scenes (hydrostatic, hydrostatic_plate): the water built on its lattice with no
# pressure (the paper's start), or compressed as the density correction holds it at rest (compress_column)
WATER_STARTS = ("lattice", "compressed")


def bottom_compression(tolerance, tolerance_on):
    """The relative compression the density correction holds at the bottom of a column at rest: the tolerance
    where it governs the largest compression; twice it where it governs the mean (compression linear in depth)."""
    return tolerance * (2.0 if tolerance_on == "mean" else 1.0)


def compress_column(z, floor, height, compression):
    """Heights z (m) of lattice sites over `floor` moved down as a water column at rest is compressed: the relative
    compression linear in depth, `compression` at the floor and none at the surface (floor + height), so a layer
    at depth d is spaced dp (1 - compression d / height). Sites above the surface (a wall's top) move with it.

    Not in the paper, which starts the water on its lattice with no pressure: that column first falls into the
    correction's band and settles, and beside a free-slip wall of fixed particles its first layer slides down past
    the wall's layers, falls out of register with them by half a spacing at depth and breaks into a zigzag
    (docs/validation/OPEN.md 1.0). Built compressed, with the walls beside it compressed the same way, the water
    is at rest from the start and stays in register."""
    u = np.minimum(np.maximum(z - floor, 0.0), height)
    return z - compression * (height * u - 0.5 * u * u) / height


def whole_layers(extent, spacing, key, at_least=1):
    """Number of lattice layers in `extent`, or SceneError if it is not a whole number of spacings."""
    n = extent / spacing
    if abs(n - round(n)) > 1e-6 * max(n, 1.0):
        raise SceneError(f"{key} = {extent:g} m is not a whole number of spacings (numerics.spacing = "
                         f"{spacing:g} m); allowed: a multiple of the spacing")
    n = int(round(n))
    if n < at_least:
        raise SceneError(f"numerics.spacing = {spacing:g} m is too coarse for {key} = {extent:g} m; allowed: at "
                         f"most {extent / at_least:g} m ({at_least} particle layers)")
    return n


def column_sites(values):
    """(nx, nz, ntank) of a column-in-tank scene: the column's sites along x and z (whole spacings, at least 2 each)
    and the tank's inside along x (geometry.tank_length rounded to whole spacings)."""
    dp = values["numerics.spacing"]
    return (whole_layers(values["geometry.column_width"], dp, "geometry.column_width", at_least=2),
            whole_layers(values["geometry.column_height"], dp, "geometry.column_height", at_least=2),
            int(round(values["geometry.tank_length"] / dp)))


def check_column_in_tank(values, gate_layers=0):
    """SceneError unless the tank is longer than the column by its gate's `gate_layers` and two more sites, and its
    walls reach the column's top."""
    from ..schema import SceneError
    dp = values["numerics.spacing"]
    nx = column_sites(values)[0]
    room = nx + gate_layers + 2
    if values["geometry.tank_length"] < room * dp:
        beyond = "the column and its gate" if gate_layers else "the column"
        raise SceneError(f"geometry.tank_length = {values['geometry.tank_length']:g} m: not longer than {beyond}; "
                         f"allowed: at least {room * dp:g} m")
    if values["geometry.wall_height"] < values["geometry.column_height"]:
        raise SceneError(f"geometry.wall_height = {values['geometry.wall_height']:g} m: below the column; allowed: "
                         f"at least geometry.column_height")


def outside_tank(pos, length, span, periodic_y, spacing):
    """Mask of fluid particles that crossed a wall: whose centre is past the centres of the wall's first particle
    layer (dp/2 beyond the wall's surface) below the floor, behind an end wall or (closed) a side wall.

    Not the surface itself: a free-surface particle (the surge's tip) has a truncated kernel, so it reaches rho0,
    and is pushed back, only a little closer to the wall than a particle in the bulk; tips dip about dp/4 below
    the floor's surface line while staying above the wall particles.
    """
    m = 0.5 * spacing
    out = (pos[:, 2] < -m) | (pos[:, 0] < -m) | (pos[:, 0] > length + m)
    if not periodic_y:
        out |= (pos[:, 1] < -m) | (pos[:, 1] > span + m)
    return out
