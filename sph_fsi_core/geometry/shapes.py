"""The shapes of a geometry scene's parts: a box, a cylinder, a sphere or a closed triangle mesh, placed in the world.

A shape lives in its own frame: the box centred on its origin with edges `size` along its axes, the cylinder's axis
along its z, centred on its origin, the sphere centred on its origin, a mesh as its file has it times `scale`. It is
placed by a rotation R (about the world's x, then y, then z axis, by `rotation` degrees) and a translation p:
x_world = R x_local + p. `inside(points)` says which world points it holds; `bounds()` its world bounding box.

A mesh's inside is found on the lattice by the parity of its crossings along +z above each site
(mesh_inside_lattice): exact for a closed mesh at sites off its surface, the cost linear in its triangles times the
lattice columns each one covers.

A site on a shape's surface (a face on a lattice plane: a box from 0.005 to 0.205 on sites at 0.005, 0.015, ...)
belongs to the shape when a step from it towards +x, +y, +z enters the shape: a box holds its sites on its low faces
and not those on its high faces, [lo, hi) along each world axis, so it holds its volume's worth (20 layers for
0.2 m at 0.01 m), and of two shapes that share a face the site on it belongs to exactly one, the one beyond it
towards +x, +y, +z, never to both or neither (a water box filling a tank's inside keeps its sites on the tank's
low faces, the tank's walls take none of them). The step is ON_FACE of a spacing, far below the lattice's
resolution and far above the rounding of a site's coordinates; a mesh's sites take the same step.
"""
import math
from dataclasses import dataclass, field

import numpy as np
from numba import njit

SHAPES = ("box", "cylinder", "sphere", "mesh")
# a site within this fraction of a spacing of a shape's surface is on it: it belongs to the shape if a step of this
# size towards +x, +y, +z (in these proportions, so that no face of a placed shape lies along the step) enters it
ON_FACE = 1.0e-6
ON_FACE_STEP = np.array([1.0, math.sqrt(2.0), math.sqrt(3.0)]) / math.sqrt(6.0)


def rotation_matrix(degrees):
    """R = Rz Ry Rx for rotations of degrees[0] about x, then degrees[1] about y, then degrees[2] about z (fixed
    world axes)."""
    ax, ay, az = (math.radians(d) for d in degrees)
    cx, sx, cy, sy, cz, sz = math.cos(ax), math.sin(ax), math.cos(ay), math.sin(ay), math.cos(az), math.sin(az)
    rx = np.array([[1.0, 0.0, 0.0], [0.0, cx, -sx], [0.0, sx, cx]])
    ry = np.array([[cy, 0.0, sy], [0.0, 1.0, 0.0], [-sy, 0.0, cy]])
    rz = np.array([[cz, -sz, 0.0], [sz, cz, 0.0], [0.0, 0.0, 1.0]])
    return rz @ ry @ rx


@dataclass(frozen=True, eq=False)
class Shape:
    """A placed shape. `dims`: the box's size (3,), the cylinder's (radius, length), the sphere's (radius,); for a
    mesh its local triangles (T, 3, 3)."""
    kind: str
    dims: np.ndarray
    rotation: np.ndarray = field(default_factory=lambda: np.eye(3))   # R, (3, 3)
    position: np.ndarray = field(default_factory=lambda: np.zeros(3))  # p, (3,) m

    def to_local(self, points):
        """World points (N, 3) in the shape's frame: R^T (x - p)."""
        return (np.asarray(points, dtype=np.float64) - self.position) @ self.rotation

    def local_corners(self):
        """The corners of the shape's local bounding box, (8, 3)."""
        if self.kind == "box":
            half = 0.5 * self.dims
        elif self.kind == "cylinder":
            half = np.array([self.dims[0], self.dims[0], 0.5 * self.dims[1]])
        elif self.kind == "sphere":
            half = np.full(3, self.dims[0])
        else:
            lo, hi = self.dims.reshape(-1, 3).min(axis=0), self.dims.reshape(-1, 3).max(axis=0)
            return np.array([[(lo, hi)[i][0], (lo, hi)[j][1], (lo, hi)[k][2]] for i in (0, 1) for j in (0, 1)
                             for k in (0, 1)])
        return np.array([[sx * half[0], sy * half[1], sz * half[2]] for sx in (-1, 1) for sy in (-1, 1)
                         for sz in (-1, 1)])

    def bounds(self):
        """(lo, hi), the world's axis-aligned box around the shape, m."""
        if self.kind == "mesh":
            world = self.dims.reshape(-1, 3) @ self.rotation.T + self.position
        else:
            world = self.local_corners() @ self.rotation.T + self.position
        return world.min(axis=0), world.max(axis=0)

    def volume(self):
        """The shape's volume, m^3."""
        if self.kind == "box":
            return float(np.prod(self.dims))
        if self.kind == "cylinder":
            return math.pi * self.dims[0] ** 2 * self.dims[1]
        if self.kind == "sphere":
            return 4.0 / 3.0 * math.pi * self.dims[0] ** 3
        t = self.dims
        return float(np.einsum("ij,ij->i", t[:, 0], np.cross(t[:, 1], t[:, 2])).sum() / 6.0)

    def inside_lattice(self, origin, dp, counts):
        """Which lattice sites origin + (i, j, k) dp, (i, j, k) < counts, the shape holds: bool (nx, ny, nz)."""
        if self.kind == "mesh":
            return mesh_inside_lattice(self.dims @ self.rotation.T + self.position, origin, dp, counts)
        axes = [origin[a] + np.arange(counts[a]) * dp + ON_FACE * dp * ON_FACE_STEP[a] for a in range(3)]
        points = np.stack(np.meshgrid(*axes, indexing="ij"), axis=-1).reshape(-1, 3)
        return self.inside(points).reshape(tuple(int(n) for n in counts))

    def inside(self, points):
        """Which world points (N, 3) a box, cylinder or sphere holds, (N,) bool (points on its surface may go either
        way); a mesh's: inside_lattice."""
        if self.kind == "mesh":
            raise ValueError("a mesh's inside is found on the lattice (inside_lattice)")
        local = self.to_local(points)
        if self.kind == "box":
            return np.all(np.abs(local) < 0.5 * self.dims, axis=1)
        if self.kind == "cylinder":
            radius, length = self.dims
            return (local[:, 0] ** 2 + local[:, 1] ** 2 < radius * radius) & (np.abs(local[:, 2]) < 0.5 * length)
        return (local ** 2).sum(axis=1) < self.dims[0] ** 2

    def stretched(self, faces, by):
        """The shape lengthened by `by` (m) beyond each of its open `faces` ('-x' .. '+z' of a box, '-z' / '+z' of a
        cylinder), its other faces kept: a tank's walls are the layers outside the stretched shape that are not past
        an open face."""
        if not faces:
            return self
        if self.kind == "box":
            lo, hi = -0.5 * self.dims, 0.5 * self.dims
        else:
            lo = np.array([-self.dims[0], -self.dims[0], -0.5 * self.dims[1]])
            hi = -lo
        lo, hi = lo.copy(), hi.copy()
        for face in faces:
            axis = "xyz".index(face[1])
            if face[0] == "+":
                hi[axis] += by
            else:
                lo[axis] -= by
        centre = 0.5 * (lo + hi)
        dims = hi - lo if self.kind == "box" else np.array([self.dims[0], hi[2] - lo[2]])
        return Shape(self.kind, dims, self.rotation, self.position + self.rotation @ centre)

    def beyond_faces(self, points, faces):
        """Which world points lie past one of the open `faces` of the (unstretched) shape, along its axis."""
        local = self.to_local(points)
        half = 0.5 * self.dims if self.kind == "box" else np.array([self.dims[0], self.dims[0], 0.5 * self.dims[1]])
        out = np.zeros(len(local), dtype=bool)
        for face in faces:
            axis = "xyz".index(face[1])
            out |= local[:, axis] > half[axis] if face[0] == "+" else local[:, axis] < -half[axis]
        return out


@njit(cache=True, fastmath=False, error_model="numpy", nogil=True)
def column_crossings(triangles, x0, y0, dp, nx, ny, shift_x, shift_y, heights, start, fill):
    """Where each lattice column (x0 + i dp, y0 + j dp), i < nx, j < ny, crosses a triangle mesh (T, 3, 3): with
    `fill` False counts the crossings into start[i * ny + j + 1]; with `fill` True writes their heights into
    heights[start[c]:start[c + 1]] (start the counts' running sum). The columns are shifted by (shift_x, shift_y), far
    below the lattice's resolution, so that none runs through an edge or a vertex the mesh and the lattice share."""
    slot = start[:-1].copy() if fill else start[:1].copy()
    for t in range(triangles.shape[0]):
        ax, ay, az = triangles[t, 0, 0], triangles[t, 0, 1], triangles[t, 0, 2]
        bx, by, bz = triangles[t, 1, 0], triangles[t, 1, 1], triangles[t, 1, 2]
        cx, cy, cz = triangles[t, 2, 0], triangles[t, 2, 1], triangles[t, 2, 2]
        area = (bx - ax) * (cy - ay) - (cx - ax) * (by - ay)
        if area == 0.0:
            continue      # seen edge-on along z: the column crosses its neighbours instead
        i0 = max(0, int(math.floor((min(ax, bx, cx) - shift_x - x0) / dp)))
        i1 = min(nx - 1, int(math.ceil((max(ax, bx, cx) - shift_x - x0) / dp)))
        j0 = max(0, int(math.floor((min(ay, by, cy) - shift_y - y0) / dp)))
        j1 = min(ny - 1, int(math.ceil((max(ay, by, cy) - shift_y - y0) / dp)))
        for i in range(i0, i1 + 1):
            px = x0 + i * dp + shift_x
            for j in range(j0, j1 + 1):
                py = y0 + j * dp + shift_y
                # barycentric coordinates of (px, py) in the triangle's projection on the xy plane
                u = ((bx - px) * (cy - py) - (cx - px) * (by - py)) / area
                v = ((cx - px) * (ay - py) - (ax - px) * (cy - py)) / area
                w = 1.0 - u - v
                if u < 0.0 or v < 0.0 or w < 0.0:
                    continue
                c = i * ny + j
                if fill:
                    heights[slot[c]] = u * az + v * bz + w * cz
                    slot[c] += 1
                else:
                    start[c + 1] += 1


@njit(cache=True, fastmath=False, error_model="numpy", nogil=True)
def _odd_crossings_above(z0, dp, nz, heights, start, inside):
    """inside[c, k] for lattice column c and the site at height z0 + k dp: whether an odd number of the column's
    crossings (heights[start[c]:start[c + 1]]) lie above it."""
    for c in range(start.shape[0] - 1):
        row = np.sort(heights[start[c]:start[c + 1]])
        n = row.shape[0]
        below = 0
        for k in range(nz):
            z = z0 + k * dp
            while below < n and row[below] <= z:
                below += 1
            inside[c, k] = (n - below) % 2 == 1


def mesh_inside_lattice(triangles, origin, dp, counts):
    """Which sites origin + (i, j, k) dp, i < counts[0], j < counts[1], k < counts[2], lie inside a closed triangle
    mesh (T, 3, 3) in world coordinates: an odd number of its crossings above them (bool (nx, ny, nz))."""
    nx, ny, nz = (int(n) for n in counts)
    # the sites stepped towards +x, +y, +z as a primitive's (Shape.inside_lattice): a site on a face belongs to the
    # mesh if the step enters it, and no column runs through an edge or a vertex the mesh and the lattice share
    shift_x, shift_y, shift_z = ON_FACE * dp * ON_FACE_STEP
    start = np.zeros(nx * ny + 1, dtype=np.int64)
    tri = np.ascontiguousarray(triangles, dtype=np.float64)
    column_crossings(tri, origin[0], origin[1], dp, nx, ny, shift_x, shift_y, np.zeros(0), start, False)
    np.cumsum(start, out=start)
    heights = np.zeros(start[-1])
    column_crossings(tri, origin[0], origin[1], dp, nx, ny, shift_x, shift_y, heights, start, True)
    inside = np.zeros((nx * ny, nz), dtype=np.bool_)
    _odd_crossings_above(origin[2] + shift_z, dp, nz, heights, start, inside)
    return inside.reshape(nx, ny, nz)
