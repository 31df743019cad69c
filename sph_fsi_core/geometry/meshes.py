"""Mesh files of a geometry scene's parts (STL, OBJ, PLY), read with trimesh and refused by name unless closed.

A part's mesh must be a closed surface (watertight, every edge shared by two faces, consistently wound): its inside
is then well defined, and found on the lattice by the parity of crossings (shapes.mesh_inside_lattice). The triangles
are kept as read (times the part's scale); a file read once is cached by its path and modification time.
"""
from pathlib import Path

import numpy as np

from ..schema import SceneError

FORMATS = (".stl", ".obj", ".ply")
_CACHE = {}


class Mesh:
    """A closed triangle mesh: its triangles (T, 3, 3) in the file's units, its area and volume."""

    def __init__(self, triangles, area, volume):
        self.triangles = triangles
        self.area = area
        self.volume = volume


def load_mesh(path, key):
    """The mesh in `path` (SceneError naming `key` if it is missing, unreadable or not closed)."""
    path = Path(path)
    if path.suffix.lower() not in FORMATS:
        raise SceneError(f"{key} = {str(path)!r}: not a mesh file this reads; allowed: "
                         + ", ".join(FORMATS) + " (a closed surface)")
    if not path.is_file():
        raise SceneError(f"{key} = {str(path)!r}: not found; allowed: a mesh file, its path relative to the scene "
                         f"file")
    stamp = (str(path.resolve()), path.stat().st_mtime_ns)
    if stamp in _CACHE:
        return _CACHE[stamp]
    import trimesh
    try:
        mesh = trimesh.load(str(path), force="mesh", process=True)
    except Exception as exc:   # noqa: BLE001 (any reader error is bad input, reported in one line)
        raise SceneError(f"{key} = {str(path)!r}: cannot be read as a mesh ({type(exc).__name__}: "
                         f"{str(exc).splitlines()[0] if str(exc) else 'no detail'}); allowed: an STL, OBJ or PLY "
                         f"file of a closed surface") from None
    if not isinstance(mesh, trimesh.Trimesh) or len(mesh.faces) == 0:
        raise SceneError(f"{key} = {str(path)!r}: holds no triangles; allowed: an STL, OBJ or PLY file of a closed "
                         f"surface")
    if not mesh.is_watertight:
        edges = trimesh.grouping.group_rows(mesh.edges_sorted, require_count=1)
        raise SceneError(f"{key} = {str(path)!r}: the surface is not closed ({len(edges)} edge(s) with one face); "
                         f"allowed: a closed (watertight) surface")
    if not mesh.is_winding_consistent:
        raise SceneError(f"{key} = {str(path)!r}: its faces are not consistently wound; allowed: a closed surface "
                         f"with consistent normals")
    result = Mesh(np.ascontiguousarray(mesh.triangles, dtype=np.float64), float(mesh.area), abs(float(mesh.volume)))
    _CACHE[stamp] = result
    return result
