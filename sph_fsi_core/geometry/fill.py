"""A geometry scene's parts: their shapes from the scene's keys, and the lattice sites each holds by its role.

    water         every site inside the shape
    solid         every site inside the shape (its clamp: those inside the part's clamp box)
    wall, gate    `layers` of sites inside the shape's surface (side: inside, an obstacle; hollow beyond the
                  kernel's reach) or outside it (side: outside, a tank whose inside is the shape; open faces left
                  open)

`layers` 0 takes the fewest that reach the kernel's support, ceil(2h / dp), as every built-in scene's walls do. A
site on a shape's surface belongs to it by geometry/shapes.py's rule (the part beyond it towards +x, +y, +z); the
water gives up the sites walls, gates and solids overlap (scenes/geometry.py).
"""
import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..numerics.kernels import SUPPORT_RADIUS_IN_H
from ..errors import plain
from ..schema import SceneError
from .lattice import Lattice, estimated_shell_sites, filled, inner_shell, outer_shell
from .meshes import load_mesh
from .parts import AXES, list_entries, parse_faces, parse_order
from .shapes import Shape, rotation_matrix


@dataclass
class Part:
    name: str
    role: str
    shape: Shape
    keys: dict            # the part's keys without the 'parts.<name>.' prefix

    def key(self, sub):
        return f"parts.{self.name}.{sub}"


def shape_of(name, keys):
    """The placed Shape of a part's keys (SceneError naming a bad size or mesh)."""
    k = f"parts.{name}."
    kind = keys["shape"]
    if kind == "box":
        size = np.asarray(keys["size"], dtype=np.float64)
        if not (size > 0.0).all():
            raise SceneError(f"{k}size = {plain(keys['size'])}: an edge not positive; allowed: three lengths > 0 m")
        dims = size
    elif kind == "cylinder":
        dims = np.array([keys["radius"], keys["length"]], dtype=np.float64)
    elif kind == "sphere":
        dims = np.array([keys["radius"]], dtype=np.float64)
    else:
        dims = load_mesh(keys["file"], k + "file").triangles * keys["scale"]
    return Shape(kind, dims, rotation_matrix(keys["rotation"]), np.asarray(keys["position"], dtype=np.float64))


def parts_of(values):
    """The scene's parts in file order."""
    out = []
    for name, keys in list_entries(values, "parts").items():
        out.append(Part(name, keys["role"], shape_of(name, keys), keys))
    return out


def minimum_wall_layers(values):
    """ceil(2h / dp): the fewest layers a wall needs so that no water particle's kernel reaches past it."""
    return math.ceil(SUPPORT_RADIUS_IN_H * values["numerics.smoothing_ratio"] - 1e-9)


def wall_layers(part, values):
    """The part's wall layers (its `layers`, or the fewest that reach 2h); SceneError if set below that."""
    need = minimum_wall_layers(values)
    layers = part.keys["layers"]
    if layers == 0:
        return need
    if layers < need:
        raise SceneError(f"{part.key('layers')} = {layers}: thinner than the kernel's reach 2h = "
                         f"{SUPPORT_RADIUS_IN_H * values['numerics.smoothing_ratio']:.3g} spacings; allowed: at least "
                         f"{need} (or 0: that many)")
    return layers


def open_faces(part):
    return parse_faces(part.key("open"), part.keys["open"], part.keys["shape"], part.keys["side"])


def part_lattice(part, values):
    """(the Lattice the part's sites are counted on, their shift (3,) in whole sites on the scene's lattice): the
    scene's lattice moved by the part's `lattice_offset` (SceneError if that is not whole spacings)."""
    dp = values["numerics.spacing"]
    offset = np.asarray(part.keys["lattice_offset"], dtype=np.float64)
    steps = offset / dp
    shift = np.round(steps).astype(np.int64)
    if np.any(np.abs(steps - shift) > 1e-6 * np.maximum(1.0, np.abs(steps))):
        raise SceneError(f"{part.key('lattice_offset')} = {plain(offset)}: not a whole number of spacings "
                         f"(numerics.spacing = {dp:g} m); allowed: multiples of the spacing, so that the part "
                         f"stays on the scene's lattice")
    return Lattice(dp, np.asarray(values["geometry.lattice_origin"], dtype=np.float64) + offset), shift


def periodic_sites(values):
    """{axis: sites along it} of the scene's periodic axes (geometry.period: whole spacings)."""
    dp = values["numerics.spacing"]
    return {a: int(round(p / dp)) for a, p in enumerate(values["geometry.period"]) if p > 0.0}


def cut_to_period(sites, values):
    """The scene-lattice sites (N, 3) inside the periodic slab: 0 <= index < the period's sites along each periodic
    axis (a part across the slab runs on into its own image, so what lies beyond is its image's)."""
    keep = np.ones(len(sites), dtype=bool)
    for axis, n in periodic_sites(values).items():
        keep &= (sites[:, axis] >= 0) & (sites[:, axis] < n)
    return sites if keep.all() else sites[keep]


def ordered(part, sites):
    """The part's sites in its `order` (the lattice's own, x slowest then y then z, unless it says otherwise)."""
    axes, signs = parse_order(part.key("order"), part.keys["order"])
    if axes == (0, 1, 2) and signs == (1, 1, 1):
        return sites
    keys = [sign * sites[:, axis] for axis, sign in zip(axes[::-1], signs[::-1])]    # lexsort: the last key slowest
    return sites[np.lexsort(keys)]


@dataclass
class Placed:
    """A part's sites on the scene's lattice (N, 3), and how their positions are made: on the part's own Lattice
    (its lattice_offset), `shift` whole sites from the scene's (the offset's and the move's), then moved by `move`
    (m; None: not moved)."""
    sites: np.ndarray
    lattice: Lattice
    shift: np.ndarray
    move: np.ndarray | None = None

    def positions(self, sites=None):
        """(N, 3) m of `sites` (the part's own by default): lattice.positions(sites - shift) + move."""
        pos = self.lattice.positions((self.sites if sites is None else sites) - self.shift)
        return pos if self.move is None else pos + self.move

    def with_sites(self, sites):
        return Placed(sites, self.lattice, self.shift, self.move)

    def floor(self):
        """The bottom face of its lowest sites, m: lattice origin + whole layers (the water's floor, to the bit as a
        column built from its own corner)."""
        bottom = self.lattice.origin[2] + int((self.sites[:, 2] - self.shift[2]).min()) * self.lattice.dp
        return bottom if self.move is None else bottom + self.move[2]


def moved_sites(part, values):
    """(the part's `move` (3,) m or None, in whole sites (3,)); SceneError if it is not whole spacings."""
    dp = values["numerics.spacing"]
    move = np.asarray(part.keys["move"], dtype=np.float64)
    steps = move / dp
    whole = np.round(steps).astype(np.int64)
    if np.any(np.abs(steps - whole) > 1e-6 * np.maximum(1.0, np.abs(steps))):
        raise SceneError(f"{part.key('move')} = {plain(move)}: not a whole number of spacings (numerics.spacing = "
                         f"{dp:g} m); allowed: multiples of the spacing, so that the part stays on the lattice")
    return (move if move.any() else None), whole


def placed_sites(part, values):
    """The part's Placed sites on the scene's lattice: its shape's, moved, in its order and cut to the periodic slab
    (SceneError if it holds none)."""
    lattice, shift = part_lattice(part, values)
    move, steps = moved_sites(part, values)
    shift = shift + steps
    sites = cut_to_period(part_sites(part, lattice, values) + shift, values)
    if len(sites) == 0:
        raise SceneError(f"parts.{part.name}: holds no lattice site inside the periodic slab geometry.period = "
                         f"{plain(values['geometry.period'])} m; allowed: a part that reaches into it")
    return Placed(ordered(part, sites), lattice, shift, move)


def part_sites(part, lattice, values):
    """The integer lattice sites the part holds (N, 3) (SceneError if it holds none)."""
    if part.role in ("water", "solid"):
        sites = filled(lattice, part.shape)
    elif part.keys["side"] == "outside":
        sites = outer_shell(lattice, part.shape, wall_layers(part, values), open_faces(part))
    else:
        sites = inner_shell(lattice, part.shape, wall_layers(part, values))
    if len(sites) == 0:
        raise SceneError(f"parts.{part.name}: holds no lattice site at numerics.spacing = "
                         f"{values['numerics.spacing']:g} m (a {part.keys['shape']} of "
                         f"{part.shape.volume():.3g} m^3); allowed: a part larger than the spacing")
    return sites


def _area(part):
    s = part.shape
    if s.kind == "box":
        a, b, c = s.dims
        return 2.0 * (a * b + b * c + a * c)
    if s.kind == "cylinder":
        r, length = s.dims
        return 2.0 * math.pi * r * (r + length)
    if s.kind == "sphere":
        return 4.0 * math.pi * s.dims[0] ** 2
    t = s.dims
    return float(0.5 * np.linalg.norm(np.cross(t[:, 1] - t[:, 0], t[:, 2] - t[:, 0]), axis=1).sum())


def _box_in_slab(part, values):
    """(sites along each axis (3,) ints, periodic axes) of an axis-aligned box part, cut to the periodic slab; None
    for another shape. A site at origin + (i + 1/2) dp belongs to the box on [lo, hi) (a site on a face: the rule of
    geometry/shapes.py, to a hundredth of a spacing here)."""
    s = part.shape
    if s.kind != "box" or not np.allclose(np.abs(s.rotation), np.eye(3)):
        return None
    dp = values["numerics.spacing"]
    lo, hi = s.bounds()
    origin = np.asarray(values["geometry.lattice_origin"], dtype=np.float64)
    first = np.ceil((lo - origin) / dp - 0.5 - 0.01)
    end = np.ceil((hi - origin) / dp - 0.5 - 0.01)
    periodic = []
    for axis, p in enumerate(values["geometry.period"]):
        if p > 0.0:
            first[axis], end[axis] = max(first[axis], 0.0), min(end[axis], round(p / dp))
            periodic.append(axis)
    return np.maximum(end - first, 0).astype(np.int64), periodic


def estimated_sites(part, values):
    """About how many sites the part holds, from its volume or its surface (the memory guard's count, made before
    anything is built); an axis-aligned box's sites counted along each axis (its volume, or its shell's layers on
    each face, none across a periodic axis or an open face), within the periodic slab."""
    dp = values["numerics.spacing"]
    box = _box_in_slab(part, values)
    if part.role in ("water", "solid"):
        return int(np.prod(box[0])) if box is not None else int(math.ceil(part.shape.volume() / dp ** 3))
    layers = wall_layers(part, values)
    if box is not None:         # a box's shell counted site by site: its layers on each face that is not open
        sites, periodic = box
        opened = [AXES.index(f[1]) for f in open_faces(part)]
        if part.keys["side"] == "outside":
            layered = np.array([0 if axis in periodic else layers * (2 - opened.count(axis)) for axis in range(3)])
            return int(np.prod(sites + layered) - np.prod(sites))
        # an obstacle's shell is its shape's, faces across a periodic axis included (a slab under twice its layers
        # wide is filled through), then cut to the slab
        layered = np.array([layers * (2 - opened.count(axis)) for axis in range(3)])
        return int(np.prod(sites) - np.prod(np.maximum(sites - layered, 0)))
    area = _area(part)
    if part.keys["side"] == "outside":     # the shell's outer surface is larger than the shape's
        grow = layers * dp
        area = area + grow * math.sqrt(area) * 8.0 + 24.0 * grow * grow
    return min(estimated_shell_sites(area, layers, dp), 10 ** 12)


def resolve_files(values, scene_file):
    """Mesh, motion table and measurement file paths relative to the scene file made absolute (in place)."""
    base = Path(scene_file).resolve().parent if scene_file and Path(scene_file).is_file() else Path.cwd()
    for key, value in values.items():
        if key.split(".", 1)[0] in ("parts", "judge") and key.endswith((".file", ".motion_file")) \
                and isinstance(value, str) and value and not value.startswith("reference_data:") \
                and not Path(value).is_absolute():
            values[key] = str(base / value)
