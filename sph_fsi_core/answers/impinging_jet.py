"""A plane jet striking a flat wall normally: the free-streamline (hodograph) solution of an ideal, weightless jet, the
exact answer of config/jet_on_wall.yaml (Milne-Thomson, "Theoretical Hydrodynamics", 5th ed., 1968, ch. XI, the
jet against a wall; Birkhoff & Zarantonello, "Jets, Wakes, and Cavities", 1957, ch. II).

A jet of width b and speed U, along x onto the wall x = 0, splits into two sheets of width b / 2 along the wall. With
t = (u - i v) / U the complex velocity over U, the flow's half above its axis is the quarter disc |t| < 1,
-pi / 2 < arg t < 0 (the axis t in (0, 1), the wall t in (0, -i), the free streamline |t| = 1); mapping it and the
potential's strip 0 < psi < U b / 2 onto one half plane gives

    w = (U b / pi) log((1 - t^2) / (1 + t^2)),    z = -(2 b / pi) (artanh t + arctan t),

the stagnation point at z = 0. On the axis (t = q real) a point a distance d from the wall moves at q U,

    d = (2 b / pi) (artanh q + arctan q) = (4 b / pi) (q + q^5 / 5 + q^9 / 9 + ...),

and on the wall (t = -i v) the point at a height y moves along it at v U, y = (2 b / pi) (arctan v + artanh v).
Bernoulli's pressure is p = 1/2 rho U^2 (1 - q^2) (the stagnation pressure 1/2 rho U^2 at z = 0), and the force on
the wall, its integral over y, is the jet's momentum flux rho U^2 b per span (the sheets leave with no x momentum).
"""
import math


def axis_distance(q, width):
    """d, m: the distance from the wall of the point on the jet's axis that moves at q U (0 <= q < 1)."""
    return 2.0 * width / math.pi * (math.atanh(q) + math.atan(q))


def wall_height(v, width):
    """y, m: the height above the stagnation point of the point on the wall the water passes at v U (0 <= v < 1)."""
    return 2.0 * width / math.pi * (math.atan(v) + math.atanh(v))


def _speed_at(distance, width):
    """The speed over U (in [0, 1)) at which (arctan s + artanh s) (2 b / pi) = distance, by bisection."""
    if distance <= 0.0:
        return 0.0
    lo, hi = 0.0, 1.0
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        if axis_distance(mid, width) < distance:
            lo = mid
        else:
            hi = mid
    return 0.5 * (lo + hi)


def stagnation_pressure(density, speed):
    """1/2 rho U^2, Pa."""
    return 0.5 * density * speed * speed


def axis_pressure(distance, width, density, speed):
    """p, Pa, on the jet's axis `distance` m from the wall: 1/2 rho U^2 (1 - q^2)."""
    q = _speed_at(distance, width)
    return stagnation_pressure(density, speed) * (1.0 - q * q)


def wall_pressure(height, width, density, speed):
    """p, Pa, on the wall `height` m from the stagnation point (either side): 1/2 rho U^2 (1 - v^2)."""
    v = _speed_at(abs(height), width)
    return stagnation_pressure(density, speed) * (1.0 - v * v)


def force_per_span(density, speed, width):
    """rho U^2 b, N/m: the water's force on the wall per span (the jet's momentum flux)."""
    return density * speed * speed * width
