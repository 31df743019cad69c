"""Mesh files of a geometry scene's parts (STL, OBJ, PLY), read with trimesh and refused by name unless closed.

A part's mesh must be a closed surface (watertight, every edge shared by two faces, consistently wound): its inside
is then well defined, and found on the lattice by the parity of crossings (shapes.mesh_inside_lattice). The triangles
are kept as read (times the part's scale); a file read once is cached by its path and modification time.
"""
from pathlib import Path

import numpy as np

from ..schema import SceneError

FORMATS = (".stl", ".obj", ".ply")
FORMAT_NAMES = {".stl": "an STL", ".obj": "an OBJ", ".ply": "a PLY"}
# a mesh thinner than this fraction of its size, or enclosing less than this fraction of its size cubed, encloses
# no volume
FLAT = 1.0e-6
_CACHE = {}


class Mesh:
    """A closed triangle mesh: its triangles (T, 3, 3) in the file's units, its area and volume."""

    def __init__(self, triangles, area, volume):
        self.triangles = triangles
        self.area = area
        self.volume = volume


def load_mesh(path, key):
    """The mesh in `path` (SceneError naming `key` if it is missing, a directory, unreadable, flat or not closed)."""
    path = Path(path)
    if path.suffix.lower() not in FORMATS:
        raise SceneError(f"{key} = {str(path)!r}: not a mesh file this reads; allowed: "
                         + ", ".join(FORMATS) + " (a closed surface)")
    if path.is_dir():
        raise SceneError(f"{key} = {str(path)!r}: a directory, not a file; allowed: a mesh file (STL, OBJ or PLY), "
                         f"its path relative to the scene file")
    if not path.is_file():
        raise SceneError(f"{key} = {str(path)!r}: not found; allowed: a mesh file, its path relative to the scene "
                         f"file")
    stamp = (str(path.resolve()), path.stat().st_mtime_ns)
    if stamp in _CACHE:
        return _CACHE[stamp]
    import trimesh
    unreadable = (f"{key} = {str(path)!r}: cannot be read as {FORMAT_NAMES[path.suffix.lower()]} mesh; allowed: an "
                  f"STL, OBJ or PLY file of a closed surface")
    try:
        mesh = trimesh.load(str(path), force="mesh", process=True)
    except Exception:   # noqa: BLE001 (whatever the reader, or a reader's optional module, raises: not a mesh)
        raise SceneError(unreadable) from None
    if not isinstance(mesh, trimesh.Trimesh) or len(mesh.faces) == 0:
        raise SceneError(f"{key} = {str(path)!r}: holds no triangles; allowed: an STL, OBJ or PLY file of a closed "
                         f"surface")
    if _flat(mesh.vertices):
        raise SceneError(f"{key} = {str(path)!r}: encloses no volume (its vertices lie in one plane); allowed: a "
                         f"closed surface around a volume")
    if not mesh.is_watertight:
        _, faces_per_edge = np.unique(mesh.edges_sorted, axis=0, return_counts=True)
        one, more = int((faces_per_edge == 1).sum()), int((faces_per_edge > 2).sum())
        raise SceneError(f"{key} = {str(path)!r}: the surface is not closed ({one} edge(s) with one face"
                         + (f", {more} with more than two" if more else "") + "); allowed: a closed (watertight) "
                         "surface, each edge shared by two faces")
    if not mesh.is_winding_consistent:
        raise SceneError(f"{key} = {str(path)!r}: its faces are not consistently wound; allowed: a closed surface "
                         f"with consistent normals")
    if abs(float(mesh.volume)) <= FLAT * float(np.ptp(mesh.vertices, axis=0).max()) ** 3:
        raise SceneError(f"{key} = {str(path)!r}: encloses no volume (its closed surface folds onto itself); "
                         f"allowed: a closed surface around a volume")
    result = Mesh(np.ascontiguousarray(mesh.triangles, dtype=np.float64), float(mesh.area), abs(float(mesh.volume)))
    _CACHE[stamp] = result
    return result


def _flat(vertices):
    """Whether the vertices lie in one plane (or on a line), to FLAT of the mesh's size."""
    singular = np.linalg.svd(vertices - vertices.mean(axis=0), compute_uv=False)
    return bool(singular[-1] <= FLAT * singular[0])
