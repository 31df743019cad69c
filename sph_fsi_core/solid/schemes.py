"""The solid's named schemes: one word in a scene file (`solid: {scheme: gray2001}`) for a validated combination of
the detailed keys below (the velocity gradient, the nodal integration, Gray's artificial stress, the time-step
factor, the clamp, how the pressure advances and how the quadratic fit follows the motion).

A scheme only fills in values: the detailed keys stay in the schema, and one set explicitly (in the scene file, by
`--set` or as a ROS parameter) overrides its scheme's value. Changing `solid.scheme` later re-expands it and keeps
the explicitly set keys (scene.py resolves both). Which validation cases validated each scheme, and with which
error: docs/method.md, "Solid schemes". Plain data, no Numba: the schema reads it to declare `solid.scheme`.
"""
from dataclasses import dataclass, field

# The detailed keys a scheme sets (every scheme sets all seven).
SCHEME_KEYS = ("solid.velocity_gradient", "solid.nodal_integration", "solid.artificial_stress_epsilon", "solid.cfl",
               "solid.clamp", "solid.pressure", "solid.fit_refresh")


@dataclass(frozen=True)
class Scheme:
    name: str
    summary: str                                  # one line: what it is and where it holds
    values: dict = field(default_factory=dict)    # {detailed key: value}, every key of SCHEME_KEYS


SCHEMES = {s.name: s for s in (
    Scheme("quadratic_gradient",
           "quadratic fit with the strain-gradient nodal integration, the mirrored clamp, the implicit pressure and the fit "
           "turned with the body: a 4-layer beam's bending stiffness in full, the static plate converging at second "
           "order; a step set by the shear waves (6x fewer steps at nu = 0.49); needs 3 particles through the body "
           "(every scene's)",
           {"solid.velocity_gradient": "quadratic", "solid.nodal_integration": "gradient",
            "solid.artificial_stress_epsilon": 0.0, "solid.cfl": 0.25, "solid.clamp": "mirrored",
            "solid.pressure": "implicit", "solid.fit_refresh": "rotate"}),
    Scheme("quadratic_plain",
           "quadratic fit with the plain nodal sum (each particle's strain at its centre): half the cost, a 4-layer "
           "beam 6 % short in bending stiffness",
           {"solid.velocity_gradient": "quadratic", "solid.nodal_integration": "plain",
            "solid.artificial_stress_epsilon": 0.0, "solid.cfl": 0.25, "solid.clamp": "fixed",
            "solid.pressure": "explicit", "solid.fit_refresh": "remake"}),
    Scheme("quadratic_plain_artificial_stress",
           "quadratic_plain with Gray's artificial stress, as Antoci's gate (nu = 0.4) was validated; at nu >= 0.45 "
           "it feeds a growing mode",
           {"solid.velocity_gradient": "quadratic", "solid.nodal_integration": "plain",
            "solid.artificial_stress_epsilon": 0.15, "solid.cfl": 0.25, "solid.clamp": "fixed",
            "solid.pressure": "explicit", "solid.fit_refresh": "remake"}),
    Scheme("gray2001",
           "the paper's: Gray, Monaghan & Swift 2001's SPH gradient with their artificial stress; too stiff for "
           "slender bodies (+24 % in frequency at L/H = 15)",
           {"solid.velocity_gradient": "sph", "solid.nodal_integration": "plain",
            "solid.artificial_stress_epsilon": 0.15, "solid.cfl": 0.5, "solid.clamp": "fixed",
            "solid.pressure": "explicit", "solid.fit_refresh": "remake"}),
)}

# The schema's default and every scene's: chosen by the verification cases (docs/method.md, "Solid schemes").
DEFAULT_SCHEME = "quadratic_gradient"


def expansion_text(name):
    """'velocity_gradient quadratic, nodal_integration gradient, artificial_stress_epsilon 0, cfl 0.25'."""
    values = SCHEMES[name].values
    return ", ".join(f"{k.split('.', 1)[1]} {values[k]:g}" if isinstance(values[k], float)
                     else f"{k.split('.', 1)[1]} {values[k]}" for k in SCHEME_KEYS)


def scheme_values(name):
    """{detailed key: value} that scheme `name` sets (KeyError for an unknown name; the schema refuses those)."""
    return dict(SCHEMES[name].values)

