"""The periodic box: the one minimum image that the neighbour search and every pair pass take.

An axis with a positive period wraps (period <= 0: open). The neighbour lists refuse a period below twice their
cutoff, and every build checks that its particles lie within 1.5 periods less a skin of each other along each
periodic axis (neighbours.NeighbourList: the fluid wraps its positions into the box after every step, the solid's
bodies stay where they were built), so one shift by the period is always enough: no division, no floor. Measured
in one process against the multiply-and-floor form d - P floor(d / P + 1/2): the tank's fluid passes 0.87x with
the floor, Gray's solid passes on the paper's gate at 2 mm 1.00x (docs/method.md, "Performance design").
"""
from numba import njit


@njit(cache=True, fastmath=False, error_model="numpy", inline="always")
def minimum_image(d, period, half_period):
    """The shortest periodic separation along one axis for a separation d with |d| <= 1.5 period as stored;
    half_period = period / 2 (0.5 * period, once per pass). d itself where the axis is open or |d| <= period / 2,
    so a row whose pairs all stay within half a period as stored may skip the image and keep the same bits."""
    if period > 0.0:
        if d > half_period:
            return d - period
        if d < -half_period:
            return d + period
    return d


@njit(cache=True, fastmath=False, error_model="numpy", inline="always")
def minimum_image_if(d, period, half_period, periodic):
    """d through minimum_image when `periodic` (a constant at every call site, so the test compiles away), d itself
    otherwise: the pair loops compile their rows once per set of axes they take the image on (xz_periodic_marker)."""
    if periodic:
        return minimum_image(d, period, half_period)
    return d


@njit(cache=True, fastmath=False, error_model="numpy", inline="always")
def pair_separation(pos, a, b, period, half_period, wrap):
    """r_a - r_b, through minimum_image on each axis when `wrap` (the row's NeighbourList.crossing flag), else the
    plain differences (the same bits wherever the flag is off)."""
    rx = pos[a, 0] - pos[b, 0]
    ry = pos[a, 1] - pos[b, 1]
    rz = pos[a, 2] - pos[b, 2]
    if wrap:
        rx = minimum_image(rx, period[0], half_period[0])
        ry = minimum_image(ry, period[1], half_period[1])
        rz = minimum_image(rz, period[2], half_period[2])
    return rx, ry, rz


def xz_periodic_marker(period):
    """The pair loops' `xz_periodic` argument for a period: None when neither x nor z is periodic (the scenes'
    spanwise slabs, periodic along y, and scenes with no periodic axis), True otherwise.

    minimum_image's tests cost the fluid's pressure pass 1.2-1.3x even on an axis that is not periodic, so the
    fluid's pair loops and the list scan take the image along y only unless this says otherwise. Numba compiles a
    function once per argument type and drops an `if xz_periodic is None` branch that cannot be taken, so a run
    compiles only its own rows."""
    return None if (period[0] <= 0.0 and period[2] <= 0.0) else True
