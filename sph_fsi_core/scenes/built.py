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
    # solid.clamp = mirrored: for each solid particle, the moving particle at its mirror image across the clamp
    # face (-1: none, and for moving particles); None if the scene has no plane clamp face
    clamp_mirror: np.ndarray | None = None
    # a prescribed load on the solid (scenes/clamped_plate.py): force per particle at full load (N, (N, 3)), ramped
    # in over load_ramp_time (s); damping_rate (1/s) a mass-proportional damping that settles a static case
    solid_load: np.ndarray | None = None
    load_ramp_time: float = 0.0
    damping_rate: float = 0.0
    # a static coupled case (scenes/hydrostatic_plate.py): the water's velocities relax at this rate (1/s)
    fluid_damping_rate: float = 0.0
    # wall particles that hold the water while it settles before t = 0 (fluid.settle_time) and are gone from
    # t = 0: a dam break's gate, a plug in the gap under a gate; None where the tank alone holds the water
    release_walls: WallState | None = None
    # or, with a velocity (m/s), a gate lifted from t = 0 at that velocity until it has moved release_travel (m)
    release_velocity: np.ndarray | None = None
    release_travel: float = 0.0
    # a geometry scene's parts (scenes/geometry.py): {name: (phase, indices into that phase's particles)}, phase
    # 'fluid', 'walls', 'gate' (release_walls) or 'solid'; empty for the built-in scenes
    parts: dict = field(default_factory=dict)


def clamp_mirror_across(pos, movable, axis, face, spacing):
    """Index of the moving particle at each fixed particle's mirror image across the plane pos[:, axis] = face.

    -1 for moving particles and for fixed ones whose image is not a moving particle (e.g. clamp particles beside
    the body rather than behind it). Builders place bodies on one lattice, so images land on sites exactly; the
    match is on positions rounded to a hundredth of a spacing.
    """
    image = pos.copy()
    image[:, axis] = 2.0 * face - pos[:, axis]
    grid = 0.01 * spacing
    lo = np.minimum(pos.min(axis=0), image.min(axis=0))
    site = np.round((pos - lo) / grid).astype(np.int64)
    site_image = np.round((image - lo) / grid).astype(np.int64)
    span = np.maximum(site.max(axis=0), site_image.max(axis=0)) + 1
    flat = (site[:, 0] * span[1] + site[:, 1]) * span[2] + site[:, 2]
    flat_image = (site_image[:, 0] * span[1] + site_image[:, 1]) * span[2] + site_image[:, 2]
    moving = np.flatnonzero(movable)
    order = np.argsort(flat[moving])
    sorted_keys = flat[moving][order]
    fixed = np.flatnonzero(~np.asarray(movable))
    slot = np.clip(np.searchsorted(sorted_keys, flat_image[fixed]), 0, max(len(sorted_keys) - 1, 0))
    mirror = np.full(len(pos), -1, dtype=np.int64)
    if len(sorted_keys):
        hit = sorted_keys[slot] == flat_image[fixed]
        mirror[fixed[hit]] = moving[order[slot[hit]]]
    return mirror


def ghosts_beyond_reach(pos, clamp_mirror, reach):
    """The ghosts (clamp_mirror >= 0) farther than `reach` from the clamp face (half the way to their image).

    A ghost moves as its image's reversed displacement, so a clamp taller than the kernel's reach moves far from the
    face as the body does far from it: Antoci's gate hangs from 68.5 mm of clamp beside the water, whose top ghosts
    mirror the free end. The body's sums never reach them; the water must see the rigid holder they stand for."""
    mirror = np.asarray(clamp_mirror)
    ghost = np.flatnonzero(mirror >= 0)
    to_face = 0.5 * np.linalg.norm(pos[ghost] - pos[mirror[ghost]], axis=1)
    return ghost[to_face > reach]


def check_layout(built, spacing):
    """Refuse a built scene whose bodies overlap or leave its domain, before anything is computed.

    Builders place every body on one lattice, so a valid scene has no two particles closer than one spacing and
    all of them inside the domain box; a combination of geometry keys no builder check foresaw (or a builder bug)
    would otherwise start with particles on top of each other, i.e. infinite pressures at t = 0. The check uses the
    same cell lists as the physics, with a cutoff of half a spacing, so it costs one neighbour build.
    """
    from ..numerics.neighbours import NeighbourList
    from ..schema import SceneError
    bodies = [(name, state.pos) for name, state in (("solid", built.solid), ("fluid", built.fluid),
                                                    ("wall", built.walls), ("release wall", built.release_walls))
              if state is not None and len(state.pos)]
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
