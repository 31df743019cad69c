"""Shared geometry of the fluid scenes: lattice blocks and the wall particles of an open-topped tank.

Everything sits on one cubic lattice of spacing dp with sites at (i + 1/2) dp, so the fluid at rest and the walls
continue each other's lattice and the summation density (1) of a fluid particle next to a wall is rho0, as in the
bulk. The tank's inside is x in [0, length], z >= 0 and, across, y in [0, span]: periodic along y (a slab of
`span` with no side walls) or closed by walls at y = 0 and y = span.
"""
import math

import numpy as np

from ..schema import SceneError


def breathing_period(height, gravity, tolerance):
    """T_b = 4 H / c_b, c_b = sqrt(g H / tolerance), s: a column's first mode as a quarter-wave resonator whose
    compressibility is what the density tolerance allows (the density correction acts only above it). It sets
    the water's relaxation rate in the static cases (scenes/hydrostatic_plate.py, antoci_gate_static.py); without
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


def build_water_start(values, floor, height, *points):
    """geometry.water_start: with 'compressed', the heights of each (N, 3) array in `points` (the water and the walls
    beside it) moved in place by compress_column over `floor`, `height` deep, at the bottom compression the scene's
    tolerance holds; with 'lattice', nothing."""
    if values["geometry.water_start"] != "compressed":
        return
    compression = bottom_compression(values["fluid.density_tolerance"], values["fluid.tolerance_on"])
    for p in points:
        p[:, 2] = compress_column(p[:, 2], floor, height, compression)


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


def lattice(nx, ny, nz, spacing, offset=(0.0, 0.0, 0.0)):
    """Sites (i + 1/2) dp + offset for i < nx, j < ny, k < nz, x slowest (neighbours stay close in memory)."""
    axes = [(np.arange(n) + 0.5) * spacing + o for n, o in zip((nx, ny, nz), offset)]
    return np.stack(np.meshgrid(*axes, indexing="ij"), axis=-1).reshape(-1, 3)


def tank_walls(nx, ny, nz_wall, layers, spacing, periodic_y):
    """Wall sites of a tank whose inside is nx x ny cells wide and nz_wall high, `layers` thick below and around.

    Periodic in y: floor and end walls span the slab's ny sites only. Closed: side walls at y < 0 and y > span too.
    """
    pad_y = 0 if periodic_y else layers
    i = np.arange(-layers, nx + layers)
    j = np.arange(-pad_y, ny + pad_y)
    k = np.arange(-layers, nz_wall)
    ii, jj, kk = np.meshgrid(i, j, k, indexing="ij")
    outside = (ii < 0) | (ii >= nx) | (kk < 0)
    if not periodic_y:
        outside |= (jj < 0) | (jj >= ny)
    sites = np.stack([ii[outside], jj[outside], kk[outside]], axis=-1)
    return (sites + 0.5) * spacing


def tank_wall_count(nx, ny, nz_wall, layers, periodic_y):
    """len(tank_walls(...)) without making them: the padded block less the tank's inside."""
    pad_y = 0 if periodic_y else layers
    return (nx + 2 * layers) * (ny + 2 * pad_y) * (nz_wall + layers) - nx * ny * nz_wall


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
