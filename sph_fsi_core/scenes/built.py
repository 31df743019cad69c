"""What a builder returns: the particles of each phase the scene has (None for the others), probes, domain."""
from dataclasses import dataclass, field

import numpy as np

from ..state import FluidState, SolidState, WallState


@dataclass
class Built:
    solid: SolidState | None = None
    fluid: FluidState | None = None
    walls: WallState | None = None
    probes: list = field(default_factory=list)
    domain_lo: np.ndarray = None   # particles leaving this box stop the run as diverged
    domain_hi: np.ndarray = None
    period: np.ndarray = field(default_factory=lambda: np.zeros(3))


def check_layout(built, spacing):
    """Refuse a built scene whose bodies overlap or leave its domain, before anything is computed.

    Builders place every body on one lattice, so a valid scene has no two particles closer than one spacing and
    all of them inside the domain box; a combination of geometry keys no builder check foresaw (or a builder bug)
    would otherwise start with particles on top of each other, i.e. infinite pressures at t = 0. The check uses the
    same cell lists as the physics, with a cutoff of half a spacing, so it costs one neighbour build.
    """
    from ..neighbours import NeighbourList
    from ..schema import SceneError
    bodies = [(name, state.pos) for name, state in (("solid", built.solid), ("fluid", built.fluid),
                                                    ("wall", built.walls)) if state is not None and len(state.pos)]
    if not bodies:
        raise SceneError("the scene has no particles; allowed: at least one body (check the geometry.* keys)")
    pos = np.concatenate([p for _, p in bodies])
    offsets = np.cumsum([0] + [len(p) for _, p in bodies])

    def name_of(k):
        b = int(np.searchsorted(offsets, k, side="right")) - 1
        return f"{bodies[b][0]} particle {k - offsets[b]} at {np.round(pos[k], 6)} m"

    periodic = built.period > 0.0
    slack = 0.5 * spacing
    outside = np.flatnonzero(np.any(((pos < built.domain_lo - slack) | (pos > built.domain_hi + slack))
                                    & ~periodic, axis=1))
    if len(outside):
        raise SceneError(f"{len(outside)} particle(s) outside the scene's domain {built.domain_lo} .. "
                         f"{built.domain_hi} m, e.g. {name_of(outside[0])}; allowed: bodies inside the domain "
                         f"(check the geometry.* keys)")
    close = NeighbourList(0.5 * spacing, 0.0, period=built.period, box_lo=built.domain_lo, box_hi=built.domain_hi,
                          half=True)
    close.build(pos, pos)
    if close.pairs:
        a = int(np.flatnonzero(np.diff(close.start))[0])
        b = int(close.index[close.start[a]])
        raise SceneError(f"bodies overlap: {close.pairs} particle pair(s) closer than half numerics.spacing = "
                         f"{0.5 * spacing:g} m, e.g. {name_of(a)} and {name_of(b)}; allowed: bodies at least one "
                         f"spacing apart (check the geometry.* keys)")
