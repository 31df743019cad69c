"""A scene from geometry, no code: parts (water, walls, elastic solids, gates) of boxes, cylinders, spheres and
closed meshes placed in the world, probes at named places and judges of the time series, all in the scene file.
Every scene is one, the built-in ones too (config/*.yaml).

    scene: {builder: geometry, end_time: 1.0}
    numerics: {spacing: 0.02}
    geometry:
      depth: {value: 0.55, unit: m, range: "(0, 10]", description: "The water's depth"}
    parts:
      - {name: tank, role: wall, shape: box, size: [3.22, 1.0, 1.0], position: [1.61, 0.0, 0.5], side: outside,
         open: "+z"}
      - {name: water, role: water, shape: box, size: [1.228, 1.0, depth], position: [2.606, 0.0, depth / 2]}
    probes:
      - {name: H2, kind: water_height, position: [0.992, 0.0, 0.0]}

The file declares its own parameters and derived quantities under `geometry:` (geometry/declared.py), and its
lists' numbers and this builder's own keys may be expressions in them (geometry/expressions.py; scene.py evaluates
them before anything here runs). What a file cannot say is its case module's (scenes/cases, `scene.case`): checked
with the scene, its load and relaxation applied to what is built here.

Every part sits on one cubic lattice (geometry/lattice.py): its sites at geometry.lattice_origin + (i + 1/2) dp
(counted from its lattice_offset, moved by its move, numbered in its order, cut to the periodic slab:
geometry/fill.py), those its shape holds by its role. Walls, gates and solids take the water's sites where they
overlap (water poured around an obstacle: _take_from_water) and may not share a site with each other. A solid's
clamp is its part inside its clamp box, or a holder part wholly inside one (_clamp_faces); a solid needs three
particle layers through for the quadratic fit (the default scheme's; where it has fewer, the linear fit). The
build's notes (what a part took, a free body) and warnings (water outside every tank, a probe that can never read)
go to the log and summary.json. The phases follow from the parts (geometry/parts.py): a scene without a solid part
has no solid arrays, passes, topics or channels. Probes (probes.py) and judges (answers/judges.py) are declared
beside the parts; the summary reports each judge's measure and error.
"""
import math

import numpy as np

from ..answers.judges import check_judges, evaluate_judges
from ..answers.linear_waves import StandingWave
from ..answers.references import cantilever_mode_velocity
from ..geometry.fill import (cut_to_period, estimated_sites, moved_sites, part_lattice, parts_of, placed_sites,
                             resolve_files)
from ..geometry.lattice import Lattice, filled, site_keys
from ..geometry.part_motion import part_motion
from ..geometry.parts import ABSENT_SECTIONS, list_entries, list_params, parse_order, phases_of
from ..motion import Commanded, Table
from ..numerics.kernels import KERNELS, SUPPORT_RADIUS_IN_H, lattice_density_scale, water_kernel
from ..probes import ProbeSpec, probe_columns
from ..errors import plain
from ..schema import Param, SceneError, check_own_smoothing_ratio, widest_smoothing_ratio
from ..state import FluidState, Probe, SolidState, WallState
from .builder import Builder
from .built import Built, clamp_mirror_across
from .cases import CASES
from .tank import WATER_STARTS, bottom_compression, compress_column

PHASES = ("solid", "fluid", "walls", "coupling")   # the most a geometry scene has; its own: phases_of(its keys)

GEOMETRY = [
    Param("geometry.lattice_origin", (0.0, 0.0, 0.0), "m", "The lattice: sites at lattice_origin + (i + 1/2) "
          "numerics.spacing along each axis", kind="vec3"),
    Param("geometry.domain_margin", 0.0, "m", "How far the domain reaches beyond the parts (0: a tenth of their "
          "largest extent, at least 10 h); water that leaves it is held still and counted (watchdog.max_fluid_lost)",
          low=0.0, high=1.0e3),
    Param("geometry.water_start", "lattice", "", "How the water is built: 'lattice' on its lattice with no pressure "
          "(the paper's), 'compressed' each water part as the density correction holds a column at rest (compression "
          "linear in depth to the tolerance at its floor), the wall sites beside it compressed the same way "
          "(scenes/tank.py compress_column)", kind="str", choices=WATER_STARTS),
    Param("geometry.compressed_walls", "beside", "", "With water_start = compressed, the wall sites moved with each "
          "water column: 'beside' it (within the kernel's reach of its footprint, above its floor) or 'all' above its "
          "floor (a wall farther off kept level with the water's layers too)", kind="str",
          choices=("beside", "all")),
    Param("geometry.period", (0.0, 0.0, 0.0), "m", "The period along each axis (0: not periodic): the domain wraps "
          "over [lattice_origin, lattice_origin + period] along it (whole spacings, at least twice the neighbour "
          "cutoff 2h + skin), and every part is cut to that slab: a tank across it has no walls there, water or a "
          "plate across it runs on into its image", kind="vec3"),
    Param("geometry.domain_lo", (0.0, 0.0, 0.0), "m", "The domain box's low corner, with domain_hi (both [0, 0, 0]: "
          "the parts' box and domain_margin beyond it, along a periodic axis the period); water that leaves it is "
          "held still and counted, and along a periodic axis it places the neighbour lists' cells", kind="vec3"),
    Param("geometry.domain_hi", (0.0, 0.0, 0.0), "m", "The domain box's high corner (see domain_lo)", kind="vec3"),
    Param("scene.case", "", "", "The case module (sph_fsi_core/scenes/cases/) with what the file cannot say: its "
          "own reference, columns computed from the state, a prescribed load, relaxation rates ('': none)",
          kind="str", choices=("",) + tuple(CASES)),
]

DEFAULTS = {"scene.gravity": (0.0, 0.0, -9.81), "scene.end_time": 1.0, "output.timeseries_interval": 1.0e-3,
            "output.snapshot_interval": 0.05}

# time-series columns a judge may name besides the probes' (simulation.Simulation.sample)
RUN_COLUMNS = ("time", "kinetic_energy", "strain_energy", "fluid_kinetic_energy", "coupling_force_x",
               "coupling_force_y", "coupling_force_z", "iterations_mean", "density_error_max", "density_error_mean",
               "fluid_velocity_x", "fluid_velocity_y", "fluid_velocity_z", "fluid_momentum_x", "fluid_momentum_y",
               "fluid_momentum_z")


# a reading of each probe kind with every quantity, for the names of its columns (probes.probe_columns)
_ANY_READING = {"displacement": (0.0, 0.0, 0.0), "velocity": (0.0, 0.0, 0.0), "pressure": 0.0, "height": 0.0,
                "force": (0.0, 0.0, 0.0)}


def declared_columns(values):
    """The time-series columns of the scene's probes (probes.probe_columns names them)."""
    out = set()
    for name, keys in list_entries(values, "probes").items():
        reading = dict(_ANY_READING) if keys["kind"] == "point" else {k: v for k, v in _ANY_READING.items()
                                                                      if k != "velocity"}
        if keys["kind"] == "displacement":
            reading = {"displacement": _ANY_READING["displacement"]}
        out |= set(probe_columns(keys["kind"], name, reading))
    return out


def case_of(values):
    """The scene's case module (scenes/cases), or None."""
    return CASES[values["scene.case"]] if values["scene.case"] else None


def check(values):
    """Everything that can be refused before building: the case's own checks, the periodic axes, the parts (sizes,
    meshes, walls, clamps), the probes and the judges, each naming its key."""
    case = case_of(values)
    if case is not None and case.check is not None:
        case.check(values)
    _check_period(values)
    parts = parts_of(values)
    roles = {p.role for p in parts}
    by_name = {p.name: p for p in parts}
    for part in parts:
        part_lattice(part, values)                 # checks its offset and its move
        moved_sites(part, values)
        parse_order(part.key("order"), part.keys["order"])
        if part.role in ("wall", "gate"):
            estimated_sites(part, values)          # checks layers and open faces
        if part.role == "wall":
            part_motion(part.name, part.keys)      # checks its motion keys and reads its table
        if part.role == "solid":
            lo, hi = np.asarray(part.keys["clamp_lo"]), np.asarray(part.keys["clamp_hi"])
            if (lo != hi).any() and not (lo < hi).all():
                raise SceneError(f"{part.key('clamp_hi')} = {plain(hi)}: not above clamp_lo = {plain(lo)} on every "
                                 f"axis; allowed: a box with clamp_lo < clamp_hi (or both equal: no clamp)")
        if part.role == "gate" and part.keys["release"] == "lifted" and not np.any(part.keys["lift_velocity"]):
            raise SceneError(f"{part.key('lift_velocity')} = [0, 0, 0]: a lifted gate must move; allowed: a non-zero "
                             f"velocity (or release = instant)")
    for phase, role in (("solid", "solid"), ("fluid", "water")):
        if f"{phase}.density" in values and role not in roles:
            raise SceneError(f"parts: every {role} part is left out (its `when`), yet the scene lists one and has its "
                             f"'{phase}' section; allowed: a {role} part in the scene, or when: false written as such")
    for part in parts:
        if part.role == "water":
            _check_standing_wave(part, values)
    gates = [p for p in parts if p.role == "gate"]
    if len({(p.keys["release"], tuple(p.keys["lift_velocity"]) if p.keys["release"] == "lifted" else ())
            for p in gates}) > 1:
        raise SceneError(f"parts.{gates[1].name}.release: every gate of a scene is released alike (one release and "
                         f"one lift velocity); allowed: the same as parts.{gates[0].name}'s")
    for name, keys in list_entries(values, "probes").items():
        kind = keys["kind"]
        if kind in ("point", "displacement") and "solid" not in roles:
            raise SceneError(f"probes.{name}.kind = {kind!r}: the scene has no solid part; allowed: a {kind} probe on "
                             f"a scene with a solid")
        if kind in ("pressure", "water_height") and "water" not in roles:
            raise SceneError(f"probes.{name}.kind = {kind!r}: the scene has no water part; allowed: a water probe on "
                             f"a scene with water")
        if kind in ("pressure", "water_height"):
            check_own_smoothing_ratio(f"probes.{name}.smoothing_ratio", keys["smoothing_ratio"])
        if kind == "pressure" and keys["part"]:
            target = by_name.get(keys["part"])
            allowed = [p.name for p in parts if p.role == "wall" and p.keys.get("motion", "none") != "none"]
            if target is None or target.role != "wall" or target.keys.get("motion", "none") == "none":
                raise SceneError(f"probes.{name}.part = {keys['part']!r}: not a moving wall part; allowed: '' (a probe "
                                 f"that stays)" + "".join(f", {a!r}" for a in allowed))
        if kind == "force":
            target = by_name.get(keys["part"])
            allowed = [p.name for p in parts if p.role in ("wall", "gate", "solid")]
            if target is None or target.role not in ("wall", "gate", "solid"):
                raise SceneError(f"probes.{name}.part = {keys['part']!r}: not a wall, gate or solid part; allowed: one "
                                 f"of " + ", ".join(repr(a) for a in allowed))
            if "water" not in roles:
                raise SceneError(f"probes.{name}.kind = 'force': the scene has no water part; allowed: a force probe "
                                 f"on a scene with water")
    check_judges(values, set(declared_columns(values)) | set(RUN_COLUMNS))


def _check_standing_wave(part, values):
    """SceneError for a water part's standing wave without its length, or under gravity not straight down (linear
    theory's wave stands on a level floor under g along -z)."""
    if part.keys["standing_wave_amplitude"] == 0.0:
        return
    if part.keys["standing_wave_length"] == 0.0:
        raise SceneError(f"{part.key('standing_wave_length')} = 0: a standing wave of amplitude "
                         f"{part.keys['standing_wave_amplitude']:g} m needs its length; allowed: a length > 0 m (or "
                         f"{part.key('standing_wave_amplitude')} = 0: none)")
    g = np.asarray(values["scene.gravity"], dtype=np.float64)
    if not (g[2] < 0.0 and g[0] == 0.0 and g[1] == 0.0):
        raise SceneError(f"{part.key('standing_wave_amplitude')} = {part.keys['standing_wave_amplitude']:g} m: "
                         f"scene.gravity = {plain(g)} is not straight down; allowed: a standing wave under gravity "
                         f"along -z (or standing_wave_amplitude = 0: none)")


def _check_period(values):
    """SceneError for a period that is not whole spacings or narrower than the neighbour lists allow (one image is
    enough only across at least twice the cutoff)."""
    dp = values["numerics.spacing"]
    cutoff = (2.0 + values["numerics.neighbour_skin"]) * widest_smoothing_ratio(values) * dp
    for axis, period in enumerate(values["geometry.period"]):
        if period == 0.0:
            continue
        n = period / dp
        if period < 0.0 or abs(n - round(n)) > 1e-6 * max(n, 1.0):
            raise SceneError(f"geometry.period = {plain(values['geometry.period'])}: {period:g} m along "
                             f"{'xyz'[axis]} is not a whole number of spacings (numerics.spacing = {dp:g} m); "
                             f"allowed: 0 (not periodic) or a multiple of the spacing")
        if round(n) * dp < 2.0 * cutoff - 1e-9 * dp:
            need = math.ceil(2.0 * cutoff / dp - 1e-9)
            raise SceneError(f"geometry.period = {plain(values['geometry.period'])}: {round(n)} layers along "
                             f"{'xyz'[axis]}, narrower than twice the neighbour cutoff (2h + skin); allowed: at least "
                             f"{need} spacings ({need * dp:g} m)")


def particle_counts(values):
    """About how many particles each phase will have (the memory guard's count: from the parts' volumes and
    surfaces, nothing built)."""
    counts = {}
    phase = {"water": "fluid", "solid": "solid", "wall": "walls", "gate": "walls"}
    for part in parts_of(values):
        counts[phase[part.role]] = counts.get(phase[part.role], 0) + estimated_sites(part, values)
    return counts


def _overlap(names, sites):
    """The first two parts that claim the same lattice site: (name a, name b, sites they share, one of them, how many
    pairs of parts overlap); None if none do."""
    everything = np.concatenate(sites)
    lo = everything.min(axis=0)
    counts = everything.max(axis=0) - lo + 1
    keys = site_keys(everything, lo, counts)
    owner = np.repeat(np.arange(len(sites)), [len(s) for s in sites])
    order = np.argsort(keys, kind="stable")
    same = np.flatnonzero(keys[order][1:] == keys[order][:-1])
    if len(same):
        first = order[same[0]], order[same[0] + 1]
        a, b = names[owner[first[0]]], names[owner[first[1]]]
        pairs = {(names[owner[order[i]]], names[owner[order[i + 1]]]) for i in same}
        shared = sum(1 for i in same if (names[owner[order[i]]], names[owner[order[i + 1]]]) == (a, b))
        return a, b, shared, everything[first[0]], len(pairs)
    return None


def _claimed(part, placed, values):
    """The sites a wall, gate or solid part keeps water out of: its own, and for a body (a solid, or a wall or gate
    built inside its surface: an obstacle, hollow beyond the kernel's reach) every site inside its surface."""
    if part.role == "solid" or part.keys["side"] == "outside":
        return placed.sites
    return np.concatenate([placed.sites, cut_to_period(filled(placed.lattice, part.shape) + placed.shift, values)])


def _take_from_water(parts, placed, values):
    """(sites, notes): the parts' sites with those that walls, gates and solids claim (_claimed) taken from the water
    parts, as DualSPHysics's GenCase lets a later shape take an earlier one's; a note per part that took any. So
    water poured around an obstacle fills only what is left; the water parts' sites stay in their order. SceneError
    naming a water part left with none."""
    sites = [p.sites for p in placed]
    water = [i for i, p in enumerate(parts) if p.role == "water"]
    others = [i for i, p in enumerate(parts) if p.role != "water"]
    if not water or not others:
        return sites, []
    claims = {i: _claimed(parts[i], placed[i], values) for i in others}
    everything = np.concatenate([sites[w] for w in water] + list(claims.values()))
    lo = everything.min(axis=0)
    counts = everything.max(axis=0) - lo + 1
    water_keys = {w: site_keys(sites[w], lo, counts) for w in water}
    kept = {w: np.ones(len(sites[w]), dtype=bool) for w in water}
    notes = []
    for i in others:
        claimed = site_keys(claims[i], lo, counts)
        for w in water:
            hit = np.isin(water_keys[w], claimed)
            if hit.any():
                notes.append(f"parts.{parts[i].name} took {int(hit.sum())} of the {len(hit)} lattice sites of "
                             f"parts.{parts[w].name} (a wall, gate or solid takes the water's sites it overlaps, an "
                             f"obstacle's or a solid's every site inside its surface)")
                kept[w] &= ~hit
    out = list(sites)
    for w in water:
        if not kept[w].all():
            out[w] = sites[w][kept[w]]
        if not len(out[w]):
            takers = [f"parts.{parts[i].name}" for i in others
                      if np.isin(water_keys[w], site_keys(claims[i], lo, counts)).any()]
            raise SceneError(f"parts.{parts[w].name}: holds no lattice site once {', '.join(takers)} took theirs; "
                             f"allowed: water that reaches beyond the walls, gates and solids inside it")
    return out, notes


def _clamp_mask(part, pos):
    """The part's particles inside its clamp box, or None for a part without one (clamp_lo = clamp_hi)."""
    lo, hi = np.asarray(part.keys["clamp_lo"]), np.asarray(part.keys["clamp_hi"])
    if not (lo < hi).all():
        return None
    clamped = np.all((pos > lo) & (pos < hi), axis=1)
    if not clamped.any():
        raise SceneError(f"{part.key('clamp_lo')}: the clamp box [{plain(lo)}, {plain(hi)}] holds none of the part's "
                         f"particles; allowed: a box around the part's clamped end")
    return clamped


def _clamp_face(part, clamped, free):
    """(axis, face position, side +-1) of the clamp box face the moving particles `free` leave it through: halfway
    between the clamp's last layer (`clamped`, its positions) and the body's first; side is the direction from the
    clamp into the body. SceneError unless exactly one face."""
    lo, hi = np.asarray(part.keys["clamp_lo"]), np.asarray(part.keys["clamp_hi"])
    faces = []
    for axis in range(3):
        for side, bound in ((-1, lo[axis]), (1, hi[axis])):
            beyond = free[:, axis] > bound if side > 0 else free[:, axis] < bound
            if beyond.any():
                faces.append((axis, side))
    if len(faces) != 1:
        raise SceneError(f"{part.key('clamp_lo')}: the body leaves the clamp box [{plain(lo)}, {plain(hi)}] through "
                         f"{len(faces)} faces; allowed: one (the clamp face: the box must reach past the body on its "
                         f"other sides)")
    axis, side = faces[0]
    if side > 0:
        face = 0.5 * (clamped[:, axis].max() + free[:, axis].min())
    else:
        face = 0.5 * (clamped[:, axis].min() + free[:, axis].max())
    return axis, face, side


def _clamp_faces(parts, positions, clamped, dp):
    """({part: its clamp face}, {part: the holder part whose face holds it}). A part partly inside its clamp box is
    held by its own clamp; a part wholly inside its box is a holder (a clamp of its own shape, a beam's root block
    taller than the beam), whose face is the one the other parts' moving particles touching it (within 1.5 dp of its
    particles' box) leave it through."""
    faces, held_by = {}, {}
    for k, part in enumerate(parts):
        c = clamped[k]
        if c is None:
            continue
        if not c.all():
            faces[k] = _clamp_face(part, positions[k][c], positions[k][~c])
            held_by[k] = k
            continue
        lo, hi = positions[k].min(axis=0) - 1.5 * dp, positions[k].max(axis=0) + 1.5 * dp
        touching, free = [], []
        for j, pos in enumerate(positions):
            moving = pos if clamped[j] is None else pos[~clamped[j]]
            near = moving[np.all((moving >= lo) & (moving <= hi), axis=1)] if j != k else moving[:0]
            if len(near):
                touching.append(j)
                free.append(near)
        if not touching:
            raise SceneError(f"{part.key('clamp_lo')}: the clamp box holds all of the part's particles, and no moving "
                             f"solid particle of another part touches it; allowed: a box around the part's clamped end "
                             f"only, or a part wholly clamped (a holder) against another solid part")
        faces[k] = _clamp_face(part, positions[k], np.concatenate(free))
        held_by[k] = k
        for j in touching:
            held_by.setdefault(j, k)
    return faces, held_by


def _solid(parts, placed, values, notes, warnings):
    """The solid's state, clamp mirror map and {part: indices}; a note for each part that no clamp holds (a free
    body), a warning where nothing can hold one up. A body under three layers through runs on the linear fit where
    the quadratic one is not determined, and the solid's phase says so (solid/phase.py)."""
    dp = values["numerics.spacing"]
    positions = [p.positions() for p in placed]
    clamped = [_clamp_mask(part, pos) for part, pos in zip(parts, positions)]
    faces, held_by = _clamp_faces(parts, positions, clamped, dp)
    offsets = np.cumsum([0] + [len(p) for p in positions])
    velocities, movables, index = [], [], {}
    for k, (part, pos) in enumerate(zip(parts, positions)):
        movable = np.ones(len(pos), dtype=bool) if clamped[k] is None else ~clamped[k]
        face = faces.get(held_by.get(k, -1))
        if k not in held_by:
            notes.append(f"parts.{part.name}: no clamp box (clamp_lo = clamp_hi): a free body"
                         + (" (solid.clamp = mirrored mirrors only the parts with one)"
                            if values["solid.clamp"] == "mirrored" else ""))
            warning = _unheld(part, values)
            if warning:
                warnings.append(warning)
        vel = np.tile(np.asarray(part.keys["velocity"], dtype=np.float64), (len(pos), 1))
        tip = np.asarray(part.keys["mode_tip_velocity"], dtype=np.float64)
        if tip.any():
            if face is None:
                raise SceneError(f"{part.key('mode_tip_velocity')}: a cantilever's mode needs a clamp; allowed: "
                                 f"clamp_lo and clamp_hi around the clamped end (or mode_tip_velocity = [0, 0, 0])")
            axis, plane, side = face
            along = side * (pos[:, axis] - plane)
            length = part.keys["mode_length"] or float(along[movable].max()) + 0.5 * dp
            speed = float(np.linalg.norm(tip))
            profile = cantilever_mode_velocity(np.clip(along, 0.0, None), length, speed)
            vel[movable] += profile[movable, None] * (tip / speed)
        vel[~movable] = 0.0
        movables.append(movable)
        velocities.append(vel)
        index[part.name] = np.arange(offsets[k], offsets[k + 1])
    pos = np.concatenate(positions)
    movable = np.concatenate(movables)
    solid = SolidState.at_rest(pos, movable, values["solid.density"], dp)
    solid.vel[:] = np.concatenate(velocities)
    mirror = np.full(len(pos), -1, dtype=np.int64)
    for k, (axis, plane, _) in faces.items():
        rows = slice(offsets[k], offsets[k + 1])
        mirror[rows] = clamp_mirror_across(pos, movable, axis, plane, dp)[rows]
    return solid, (mirror if (mirror >= 0).any() else None), index


def _unheld(part, values):
    """A warning for a free body under gravity that the water cannot hold up (it is as dense, or there is none):
    no solid touches a wall (walls act on the water only), so it falls through the walls and out of the domain."""
    if not np.any(values["scene.gravity"]):
        return None
    water = values.get("fluid.density")
    if water is not None and values["solid.density"] < water:
        return None
    return (f"parts.{part.name}: a free body (no clamp_lo, clamp_hi) under scene.gravity "
            + (f"at least as dense as the water (solid.density = {values['solid.density']:g} kg/m^3)"
               if water is not None else "with no water to carry it")
            + ": nothing holds it up (the walls push on the water only, not on a solid), so it falls through them "
              "and leaves the domain; give it a clamp box, or a density below the water's")


def _compress(values, water, walls):
    """geometry.water_start = compressed: (water positions, wall positions) with each water part's column compressed
    as it sits at rest, and the wall sites beside it (within the kernel's reach of its footprint, above its floor; or
    all above its floor: geometry.compressed_walls) moved the same way. `water`, `walls`: each part's fill.Placed; a
    column's floor and height are its sites' bottom face and its whole layers."""
    dp = values["numerics.spacing"]
    compression = bottom_compression(values["fluid.density_tolerance"], values["fluid.tolerance_on"])
    reach = 2.0 * values["numerics.smoothing_ratio"] * dp + dp
    water_pos = [p.positions() for p in water]
    wall_pos = [p.positions() for p in walls]
    for placed, pos in zip(water, water_pos):
        floor = placed.floor()
        height = (int(placed.sites[:, 2].max()) - int(placed.sites[:, 2].min()) + 1) * dp
        lo, hi = pos[:, :2].min(axis=0) - reach, pos[:, :2].max(axis=0) + reach
        for w in wall_pos:
            beside = w[:, 2] > floor
            if values["geometry.compressed_walls"] == "beside":
                beside &= np.all((w[:, :2] > lo) & (w[:, :2] < hi), axis=1)
            w[beside, 2] = compress_column(w[beside, 2], floor, height, compression)
        pos[:, 2] = compress_column(pos[:, 2], floor, height, compression)
    return water_pos, wall_pos


def build(values):
    dp = values["numerics.spacing"]
    lattice = Lattice(dp, values["geometry.lattice_origin"])
    parts = parts_of(values)
    placed = [placed_sites(p, values) for p in parts]
    sites, notes = _take_from_water(parts, placed, values)
    placed = [p.with_sites(s) for s, p in zip(sites, placed)]
    overlap = _overlap([p.name for p in parts], sites)
    if overlap is not None:
        a, b, shared, where, pairs = overlap
        more = f" (and {pairs - 1} more pair(s) of parts)" if pairs > 1 else ""
        raise SceneError(f"parts.{b}: overlaps parts.{a} at {shared} lattice site(s), e.g. "
                         f"{plain(lattice.positions(where[None])[0])} m{more}; allowed: parts that share "
                         f"no site at numerics.spacing = {dp:g} m (move or shrink one)")
    by_role = {role: [(p, q) for p, q in zip(parts, placed) if p.role == role]
               for role in ("water", "wall", "gate", "solid")}
    scale = lattice_density_scale(values["numerics.smoothing_ratio"], water_kernel(values))
    built = Built()
    index = {}
    water = by_role["water"]
    walls = by_role["wall"] + by_role["gate"]
    if water and values["geometry.water_start"] == "compressed":
        water_pos, wall_pos = _compress(values, [q for _, q in water], [q for _, q in walls])
    else:
        water_pos = [q.positions() for _, q in water]
        wall_pos = [q.positions() for _, q in walls]
    if water:
        rho0 = values["fluid.density"]
        built.fluid = FluidState.at_rest(np.concatenate(water_pos), rho0, dp, mass_scale=scale)
        offset = 0
        for (part, _), pos in zip(water, water_pos):
            built.fluid.vel[offset:offset + len(pos)] = np.asarray(part.keys["velocity"])
            index[part.name] = ("fluid", np.arange(offset, offset + len(pos)))
            offset += len(pos)
        for part, placed_water in water:
            wave = _standing_wave(part, placed_water, values, built.warnings)
            if wave is not None:
                built.fluid_start.append((index[part.name][1], wave))
    rho0 = values.get("fluid.density", 1000.0)
    fixed = [(p, pos) for (p, _), pos in zip(walls, wall_pos) if p.role == "wall"]
    released = [(p, pos) for (p, _), pos in zip(walls, wall_pos) if p.role == "gate"]
    if fixed:
        built.walls = WallState.lattice(np.concatenate([pos for _, pos in fixed]), rho0, dp, mass_scale=scale)
        offset = 0
        for part, pos in fixed:
            index[part.name] = ("walls", np.arange(offset, offset + len(pos)))
            offset += len(pos)
            motion = part_motion(part.name, part.keys)
            if motion is not None:
                built.motions[part.name] = motion
    if released:
        built.release_walls = WallState.lattice(np.concatenate([pos for _, pos in released]), rho0, dp,
                                                mass_scale=scale)
        first = released[0][0]
        if first.keys["release"] == "lifted":
            built.release_velocity = np.asarray(first.keys["lift_velocity"], dtype=np.float64)
            built.release_travel = first.keys["lift_travel"] or _lift_travel(built, values)
        offset = 0
        for part, pos in released:
            index[part.name] = ("gate", np.arange(offset, offset + len(pos)))
            offset += len(pos)
    if by_role["solid"]:
        built.solid, built.clamp_mirror, solid_index = _solid([p for p, _ in by_role["solid"]],
                                                              [q for _, q in by_role["solid"]], values, notes,
                                                              built.warnings)
        index.update({name: ("solid", idx) for name, idx in solid_index.items()})
        whole = [solid_index[p.name] for p, _ in by_role["solid"] if p.keys["unreached_clamp"] == "keep"]
        built.whole = np.concatenate(whole) if whole else np.zeros(0, dtype=np.int64)
    built.parts = index
    built.notes = notes
    built.period = np.array(values["geometry.period"], dtype=np.float64)
    built.probes = _probes(values, built, index)
    built.domain_lo, built.domain_hi = _domain(values, built)
    built.warnings += _falling_water(values, built) + _dry_probes(values, built)
    case = case_of(values)
    if case is not None and case.load is not None and built.solid is not None:
        built.solid_load, built.load_ramp_time = case.load(values, built)
    if case is not None and case.relaxation is not None:
        built.damping_rate, built.fluid_damping_rate = case.relaxation(values, built)
    return built


def _standing_wave(part, placed, values, warnings):
    """The water part's standing wave (answers/linear_waves.StandingWave) from its standing_wave_* keys, over its
    sites' floor and whole layers (its depth d, as the column was built), or None without one. SceneError if the
    amplitude reaches the floor; a warning where the field is not a mode of the water along x (the period, or the
    part's length between walls, not a whole number of wavelengths, or of half wavelengths)."""
    amplitude = part.keys["standing_wave_amplitude"]
    if amplitude == 0.0:
        return None
    dp = values["numerics.spacing"]
    depth = (int(placed.sites[:, 2].max()) - int(placed.sites[:, 2].min()) + 1) * dp
    if amplitude >= depth:
        raise SceneError(f"{part.key('standing_wave_amplitude')} = {amplitude:g} m: not below the water's depth "
                         f"{depth:g} m, so its troughs would reach the floor; allowed: a small amplitude (linear "
                         f"theory's: a few per cent of the depth)")
    length = part.keys["standing_wave_length"]
    period = values["geometry.period"][0]
    across = period if period > 0.0 else (int(np.ptp(placed.sites[:, 0])) + 1) * dp
    unit = length if period > 0.0 else 0.5 * length
    if abs(across / unit - round(across / unit)) > 1e-6 * max(across / unit, 1.0):
        warnings.append(f"{part.key('standing_wave_length')} = {length:g} m: the water's "
                        + (f"period along x, {period:g} m, is not a whole number of wavelengths"
                           if period > 0.0 else f"length along x, {across:g} m, is not a whole number of half "
                                                f"wavelengths")
                        + ": the standing wave started is not a mode of the water, and others start with it")
    return StandingWave(amplitude, length, depth, float(placed.floor()), part.keys["standing_wave_antinode"],
                        float(np.linalg.norm(values["scene.gravity"])))


def _supports(built):
    """Every wall, gate and solid particle's position (what holds water up and what a pressure probe sits on)."""
    held = [s.pos for s in (built.walls, built.release_walls, built.solid) if s is not None]
    return np.concatenate(held) if held else np.zeros((0, 3))


def _falling_water(values, built):
    """Warnings for water parts with particles under which, along scene.gravity, no wall, gate or solid stands
    within a spacing of their line: water outside every tank, which will only fall out of the domain."""
    g = np.asarray(values["scene.gravity"], dtype=np.float64)
    if built.fluid is None or not g.any():
        return []
    dp = values["numerics.spacing"]
    down = g / np.linalg.norm(g)
    across = np.linalg.svd(down[None, :])[2][1:]            # two unit vectors normal to the gravity
    support = _supports(built)
    out = []
    for name, (phase, idx) in built.parts.items():
        if phase != "fluid":
            continue
        water = built.fluid.pos[idx]
        held = np.zeros(len(water), dtype=bool)
        if len(support):
            held = _held_up(water, support, down, across, dp)
        if not held.all():
            out.append(f"parts.{name}: {int((~held).sum())} of its {len(water)} particles have no wall, gate or solid "
                       f"below them along scene.gravity (water outside every tank): that water will only fall, and "
                       f"leave the domain")
    return out


def _held_up(water, support, down, across, dp):
    """Which water particles have a support particle below them (along `down`) within about a spacing of the line
    through them: the supports binned on the plane normal to `down` in cells of a spacing, each cell's lowest
    support, looked up in the water particle's cell and its eight neighbours."""
    def cells(pos):
        return np.floor(pos @ across.T / dp).astype(np.int64)

    support_cells, depth = cells(support), support @ down       # depth grows downwards
    keys = support_cells[:, 0] * (1 << 32) + support_cells[:, 1]
    order = np.argsort(keys, kind="stable")
    keys, depth = keys[order], depth[order]
    unique, first = np.unique(keys, return_index=True)
    deepest = np.maximum.reduceat(depth, first)
    water_cells, water_depth = cells(water), water @ down
    held = np.zeros(len(water), dtype=bool)
    for di in (-1, 0, 1):
        for dj in (-1, 0, 1):
            look = (water_cells[:, 0] + di) * (1 << 32) + water_cells[:, 1] + dj
            at = np.clip(np.searchsorted(unique, look), 0, len(unique) - 1)
            held |= (unique[at] == look) & (deepest[at] > water_depth)
    return held


def _dry_probes(values, built):
    """Warnings for probes that can never read what they say: a pressure probe farther than the kernel's reach (2h)
    from every wall, gate, solid and water particle (in mid-air, not on a wall), a water-height probe whose vertical
    line passes within 2h of none, a probe outside the domain box, a point probe farther than 2h from the solid it
    follows (it follows the nearest moving particle, wherever that is)."""
    h = values["numerics.smoothing_ratio"] * values["numerics.spacing"]
    reach = SUPPORT_RADIUS_IN_H * h
    everything = np.concatenate([_supports(built)] + ([built.fluid.pos] if built.fluid is not None else []))
    out = []
    for probe, (name, keys) in zip(built.probes, list_entries(values, "probes").items()):
        at = np.asarray(keys.get("position", (0.0, 0.0, 0.0)), dtype=np.float64)
        key = f"probes.{name}.position = {plain(at)}"
        if keys["kind"] == "point":
            away = float(np.linalg.norm(probe.reference_position - at))
            if away > reach:
                out.append(f"{key}: {away:.3g} m from the nearest moving particle of the solid, farther than 2h = "
                           f"{reach:.3g} m; it follows that particle, at {plain(probe.reference_position)} m")
            continue
        if keys["kind"] not in ("pressure", "water_height"):
            continue
        if np.any(at < built.domain_lo) or np.any(at > built.domain_hi):
            out.append(f"{key}: outside the domain box {plain(built.domain_lo)} .. {plain(built.domain_hi)} m, "
                       f"where no water ever is: it can never read")
            continue
        offset = everything - at
        if keys["kind"] == "pressure":
            nearest = float(np.sqrt((offset ** 2).sum(axis=1).min())) if len(offset) else math.inf
            if nearest > reach:
                out.append(f"{key}: in mid-air, {nearest:.3g} m from the nearest wall, gate, solid or water particle "
                           f"(a pressure probe reads the water within 2h = {reach:.3g} m of a point on a wall): it "
                           f"reads 0 until water passes by")
        else:
            beside = np.sqrt(offset[:, 0] ** 2 + offset[:, 1] ** 2) <= reach
            if not (beside & (offset[:, 2] >= -reach)).any():
                out.append(f"{key}: no wall, gate, solid or water within 2h = {reach:.3g} m of its vertical line "
                           f"(a water-height probe reads the water standing on a floor there): it can never read")
    return out


def _lift_travel(built, values):
    """A lifted gate's travel when the scene does not give it: until its lowest particle is 2h above the water's top
    (lobovsky_dam_break's rule) if it rises; otherwise its own largest extent plus 2h, out of its way."""
    h = values["numerics.smoothing_ratio"] * values["numerics.spacing"]
    direction = built.release_velocity / np.linalg.norm(built.release_velocity)
    gate = built.release_walls.pos
    if direction[2] > 1e-3 and built.fluid is not None:
        rise = built.fluid.pos[:, 2].max() + 2.0 * h - gate[:, 2].min()
        return float(max(rise, 0.0) / direction[2])
    return float(np.ptp(gate, axis=0).max() + 2.0 * h)


def _domain(values, built):
    """The domain box: geometry.domain_lo .. domain_hi where the scene gives them, else every particle's box (a
    lifted gate's whole travel and the moving walls' sweep included: _swept) and `geometry.domain_margin` beyond it
    (0: a tenth of its largest extent, at least 10 h), along a periodic axis the period from the lattice's origin.
    Along a periodic axis the box places the neighbour lists' cells (numerics/neighbours.cell_grid), so its bits
    are the run's."""
    pos = [s.pos for s in (built.solid, built.fluid, built.walls, built.release_walls) if s is not None]
    if built.release_velocity is not None:
        travel = built.release_velocity / np.linalg.norm(built.release_velocity) * built.release_travel
        pos.append(built.release_walls.pos + travel)
    pos += _swept(values, built)
    given_lo, given_hi = np.array(values["geometry.domain_lo"]), np.array(values["geometry.domain_hi"])
    if (given_lo != given_hi).any():
        return given_lo, given_hi
    everything = np.concatenate(pos)
    lo, hi = everything.min(axis=0), everything.max(axis=0)
    margin = values["geometry.domain_margin"]
    if margin == 0.0:
        h = values["numerics.smoothing_ratio"] * values["numerics.spacing"]
        margin = max(0.1 * float((hi - lo).max()), 10.0 * h)
    lo, hi = lo - margin, hi + margin
    origin = values["geometry.lattice_origin"]
    for axis, period in enumerate(values["geometry.period"]):
        if period > 0.0:
            lo[axis], hi[axis] = origin[axis], origin[axis] + period
    return lo, hi


def _swept(values, built):
    """The corners of each moving wall's box at times through the run (every 1/64 of scene.end_time, and a table's
    rows): where its motion takes it. A commanded wall's is not known before the run: its built box only."""
    out = []
    end = values["scene.end_time"]
    for name, motion in built.motions.items():
        if isinstance(motion, Commanded):
            continue
        rows = built.parts[name][1]
        part = built.walls.pos[rows]
        times = np.linspace(0.0, end, 65)
        if isinstance(motion, Table):
            times = np.union1d(times, motion.rows[:, 0])
        for t in times:
            at = motion.positions(part, float(t))
            out.append(np.array([at.min(axis=0), at.max(axis=0)]))
    return out


def _probes(values, built, index):
    """The scene's probes (probes.ProbeSpec), each placed on what it measures."""
    out = []
    for name, keys in list_entries(values, "probes").items():
        kind = keys["kind"]
        if kind == "point":
            pos = built.solid.pos
            candidates = np.flatnonzero(built.solid.movable)
            at = candidates[np.argmin(((pos[candidates] - np.asarray(keys["position"])) ** 2).sum(axis=1))]
            out.append(ProbeSpec(name, kind, position=np.asarray(keys["position"], dtype=np.float64), index=int(at),
                                 reference_position=pos[at].copy()))
        elif kind == "displacement":
            half = 0.5 * np.asarray(keys["size"], dtype=np.float64)
            pos = built.solid.pos
            inside = built.solid.movable & np.all(np.abs(pos - np.asarray(keys["position"])) <= half, axis=1)
            idx = np.flatnonzero(inside)
            if not len(idx):
                raise SceneError(f"probes.{name}: no moving solid particle inside the box of size {plain(2 * half)} m "
                                 f"around position {plain(keys['position'])} m; allowed: a box around some of the "
                                 f"solid's moving particles")
            out.append(Probe(name, "solid", idx, pos[idx].mean(axis=0)))
        elif kind == "force":
            phase, idx = index[keys["part"]]
            out.append(ProbeSpec(name, kind, phase=phase, indices=idx, part=keys["part"]))
        elif kind == "water_height":
            out.append(ProbeSpec(name, kind, position=np.asarray(keys["position"], dtype=np.float64),
                                 span=(keys["span_x"], keys["span_y"]), **_own_kernel(keys, values)))
        else:
            position = np.asarray(keys["position"], dtype=np.float64)
            if keys["inset"] > 0.0:
                position = position + keys["inset"] * _into_water(name, keys, values, built)
            out.append(ProbeSpec(name, kind, position=position, part=keys["part"], **_own_kernel(keys, values)))
    return out


def _own_kernel(keys, values):
    """A water probe's own smoothing length and kernel id (ProbeSpec.h, .kernel; 0 and -1: the water's)."""
    return dict(h=keys["smoothing_ratio"] * values["numerics.spacing"],
                kernel=-1 if keys["kernel"] == "water" else KERNELS[keys["kernel"]])


def _into_water(name, keys, values, built):
    """A pressure probe's unit normal into the water: its `normal`, or away from the centroid of the wall
    particles within 2h of its position (a flat face's: its normal; at a corner, between the faces')."""
    given = np.asarray(keys["normal"], dtype=np.float64)
    if np.any(given != 0.0):
        return given / np.linalg.norm(given)
    position = np.asarray(keys["position"], dtype=np.float64)
    reach = SUPPORT_RADIUS_IN_H * values["numerics.smoothing_ratio"] * values["numerics.spacing"]
    walls = built.walls.pos if built.walls is not None else np.zeros((0, 3))
    near = walls[((walls - position) ** 2).sum(axis=1) < reach * reach]
    away = position - near.mean(axis=0) if len(near) else np.zeros(3)
    if np.linalg.norm(away) < 1e-6 * values["numerics.spacing"]:
        raise SceneError(f"probes.{name}.inset = {keys['inset']:g} m: no wall's face within 2h = {reach:.4g} m of "
                         f"position {list(keys['position'])} to set it in from; allowed: a position on a wall's face, "
                         f"or probes.{name}.normal given")
    return away / np.linalg.norm(away)


def evaluate(series, values):
    """The scene's judges (answers/judges.py): each one's measure, reference and error; `error` is the first's."""
    return evaluate_judges(series, values)


# the builder's interface (scenes/builder.py); conservative per scene: scenes.interface
BUILDER = Builder("geometry", PHASES, GEOMETRY, DEFAULTS, conservative=False, check=check, build=build,
                  particle_counts=particle_counts, evaluate=evaluate, phases_of=phases_of, list_params=list_params,
                  resolve_files=resolve_files, absent_sections=ABSENT_SECTIONS, expressions=True)
