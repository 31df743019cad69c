"""What a builder returns: the particles of each phase the scene has (None for the others), probes, domain."""
from dataclasses import dataclass, field, replace

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
    # a prescribed load on the solid (a case module's load: scenes/cases): force per particle at full load (N, 3),
    # ramped in over load_ramp_time (s); damping_rate (1/s) a mass-proportional damping that settles a static case
    solid_load: np.ndarray | None = None
    load_ramp_time: float = 0.0
    damping_rate: float = 0.0
    # a static coupled case (a case module's relaxation): the water's velocities relax at this rate (1/s)
    fluid_damping_rate: float = 0.0
    # wall particles that hold the water while it settles before t = 0 (fluid.settle_time) and are gone from
    # t = 0: a dam break's gate, a plug in the gap under a gate; None where the tank alone holds the water
    release_walls: WallState | None = None
    # or, with a velocity (m/s), a gate lifted from t = 0 at that velocity until it has moved release_travel (m)
    release_velocity: np.ndarray | None = None
    release_travel: float = 0.0
    # what the water starts with at t = 0, once settled (simulation.py): [(fluid rows, a field whose velocity(pos)
    # is added to theirs)], a water part's standing wave (answers/linear_waves.StandingWave)
    fluid_start: list = field(default_factory=list)
    # the wall parts that move (motion.py: linear, sinusoid, table, commanded), {part name: Motion}
    motions: dict = field(default_factory=dict)
    # a geometry scene's parts (scenes/geometry.py): {name: (phase, indices into that phase's particles)}, phase
    # 'fluid', 'walls', 'gate' (release_walls) or 'solid'
    parts: dict = field(default_factory=dict)
    # the solid particles a mirrored clamp keeps whatever their reach (the parts with unreached_clamp = keep)
    whole: np.ndarray = field(default_factory=lambda: np.zeros(0, dtype=np.int64))
    # what the build says about the scene: notes for the log (a part that took the water's sites, a free body) and
    # warnings for the run's (a scene that runs but cannot mean what it says: water that will only fall)
    notes: list = field(default_factory=list)
    warnings: list = field(default_factory=list)


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


def without_unreached_clamp(built, reach, water_density, lattice_scale):
    """`built` without the mirrored clamp's particles that no moving particle comes within `reach` of: returns
    (built, count left out).

    A mirrored clamp's particles carry no stress and move as their images (solid/stepper.py), so one that no moving
    particle's kernel reaches changes nothing in the body, yet every solid pass steps it. Antoci's gate hangs from
    68.5 mm of clamp (41 layers at 5/3 mm, 3 within the body's reach): 44 % of its solid particles. Those left out
    become wall particles where they were built (the rigid holder they stand for, as the water saw them before),
    with the mass the coupling gives a solid particle as the water's wall (coupling.solid_wall_mass); in a scene
    without water they are gone. Particles a probe follows stay, and those of a geometry scene's solid parts whose
    unreached_clamp is 'keep' (Built.whole). `reach`: the kernel's support 2h plus one
    spacing of margin for the root's strain (at the face the body's first layer is dp / 2 from it, a ghost d from
    it: reached while d + dp / 2 < 2h).

    The body's sums are the same, but the solid passes and the water's wall sums add in another order: the answers
    move by round-off (docs/method.md, "The clamp")."""
    from ..coupling.forces import solid_wall_mass
    from ..numerics.neighbours import NeighbourList
    solid = built.solid
    fixed = np.flatnonzero(~solid.movable)
    moving = np.flatnonzero(solid.movable)
    if not len(fixed) or not len(moving):
        return built, 0
    # distances across the periodic axes left out: never more than the true ones, so a particle left out is beyond
    # reach (and a slab narrower than twice the reach needs no periodic list)
    across = np.asarray(built.period) > 0.0
    fixed_at, fixed_site = np.unique(np.where(across, 0.0, solid.pos[fixed]), axis=0, return_inverse=True)
    moving_at = np.unique(np.where(across, 0.0, solid.pos[moving]), axis=0)
    near = NeighbourList(reach, 0.0, box_lo=built.domain_lo, box_hi=built.domain_hi)
    near.build(np.ascontiguousarray(fixed_at), np.ascontiguousarray(moving_at))
    keep = np.ones(solid.count, dtype=np.bool_)
    keep[fixed[(np.diff(near.start) == 0)[fixed_site.ravel()]]] = False
    for probe in built.probes:
        keep[_solid_indices(probe)] = True
    keep[built.whole] = True
    dropped = int(solid.count - keep.sum())
    if not dropped:
        return built, 0
    new_index = np.cumsum(keep) - 1
    new_index[~keep] = -1
    kept = SolidState(pos=np.ascontiguousarray(solid.pos[keep]), vel=solid.vel[keep], rho=solid.rho[keep],
                      stress=solid.stress[keep], mass=solid.mass[keep], movable=solid.movable[keep])
    changes = {"solid": kept}
    if built.clamp_mirror is not None:
        mirror = built.clamp_mirror[keep]
        changes["clamp_mirror"] = np.where(mirror >= 0, new_index[np.maximum(mirror, 0)], -1)
    if built.solid_load is not None:
        changes["solid_load"] = built.solid_load[keep]
    if built.fluid is not None:
        holder = WallState(pos=np.ascontiguousarray(solid.pos[~keep]),
                           mass=solid_wall_mass(solid.mass[~keep], solid.rho[~keep], water_density, lattice_scale),
                           rho0=float(water_density))
        changes["walls"] = holder if built.walls is None else WallState(
            pos=np.concatenate([built.walls.pos, holder.pos]), mass=np.concatenate([built.walls.mass, holder.mass]),
            rho0=built.walls.rho0)
    changes["probes"] = [_renumbered(p, new_index) for p in built.probes]
    changes["parts"] = {name: (phase, _kept(new_index[idx]) if phase == "solid" else idx)
                        for name, (phase, idx) in built.parts.items()}
    return replace(built, **changes), dropped


def _kept(indices):
    """A part's solid indices after some were left out: the new index of each kept one."""
    return indices[indices >= 0]


def _solid_indices(probe):
    """The solid particles a probe follows (a built-in scene's group, a point probe, a force probe on a solid)."""
    if getattr(probe, "kind", None) == "point":
        return np.array([probe.index])
    if probe.phase == "solid":
        return np.asarray(probe.indices)
    return np.zeros(0, dtype=np.int64)


def _renumbered(probe, new_index):
    """A probe with its solid particles' indices after some were left out (those it follows are kept)."""
    if getattr(probe, "kind", None) == "point":
        return replace(probe, index=int(new_index[probe.index]))
    if probe.phase == "solid":
        return replace(probe, indices=new_index[probe.indices])
    return probe


def check_layout(built, spacing):
    """Refuse a built scene whose bodies overlap or leave its domain, before anything is computed.

    Builders place every body on one lattice, so a valid scene has no two particles closer than one spacing and
    all of them inside the domain box; a combination of geometry keys no builder check foresaw (or a builder bug)
    would otherwise start with particles on top of each other, i.e. infinite pressures at t = 0. The check uses the
    same cell lists as the physics, with a cutoff of half a spacing, so it costs one neighbour build.
    """
    from ..errors import SceneError, plain
    from ..numerics.neighbours import NeighbourList
    bodies = [(name, state.pos) for name, state in (("solid", built.solid), ("fluid", built.fluid),
                                                    ("wall", built.walls), ("release wall", built.release_walls))
              if state is not None and len(state.pos)]
    if not bodies:
        raise SceneError("the scene has no particles; allowed: at least one body (check the geometry.* keys)")
    pos = np.concatenate([p for _, p in bodies])
    offsets = np.cumsum([0] + [len(p) for _, p in bodies])

    def name_of(k):
        b = int(np.searchsorted(offsets, k, side="right")) - 1
        return f"{bodies[b][0]} particle {k - offsets[b]} at {plain(pos[k])} m"

    periodic = built.period > 0.0
    slack = 0.5 * spacing
    outside = np.flatnonzero(np.any(((pos < built.domain_lo - slack) | (pos > built.domain_hi + slack))
                                    & ~periodic, axis=1))
    if len(outside):
        raise SceneError(f"{len(outside)} particle(s) outside the scene's domain {plain(built.domain_lo)} .. "
                         f"{plain(built.domain_hi)} m, e.g. {name_of(outside[0])}; allowed: bodies inside the domain "
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
