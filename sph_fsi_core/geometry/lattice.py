"""The one cubic lattice every part of a geometry scene is built on, and the sites a shape holds on it.

Sites sit at origin + (i + 1/2) dp for integer i, j, k (a part may count its own from another corner of the same
lattice: its lattice_offset, geometry/fill.py): water, walls and solids continue each other's lattice, so a particle
next to a wall sums the same density as one in the bulk, and two parts overlap exactly where they claim the same
site. A part's sites are kept as integer indices (i, j, k); their positions follow from them.

Shells are measured in the chessboard distance on the lattice (the largest of the index differences), so a box's
walls have square corners, as a built-in tank's.
"""
import math

import numpy as np

from .shapes import ON_FACE, ON_FACE_STEP


class Lattice:
    """Sites at origin + (index + 1/2) dp."""

    def __init__(self, spacing, origin=(0.0, 0.0, 0.0)):
        self.dp = float(spacing)
        self.origin = np.asarray(origin, dtype=np.float64)

    def positions(self, index):
        """(N, 3) m of integer sites (N, 3)."""
        return self.origin + (np.asarray(index, dtype=np.float64) + 0.5) * self.dp

    def first_site(self, lo):
        """The lowest integer site at or above `lo` (3,) m along each axis."""
        return np.ceil((np.asarray(lo) - self.origin) / self.dp - 0.5 - 1e-9).astype(np.int64)

    def last_site(self, hi):
        """The highest integer site at or below `hi` (3,) m along each axis."""
        return np.floor((np.asarray(hi) - self.origin) / self.dp - 0.5 + 1e-9).astype(np.int64)

    def block(self, lo, hi, pad=0):
        """(first site (3,), counts (3,)) of the block of sites covering the box [lo, hi] and `pad` sites more on every
        side."""
        first = self.first_site(lo) - pad
        last = self.last_site(hi) + pad
        return first, np.maximum(last - first + 1, 0)

    def inside(self, shape, pad=0):
        """(first site (3,), bool grid (nx, ny, nz)): the sites of the shape's bounding block (plus `pad` on every side)
        that the shape holds."""
        lo, hi = shape.bounds()
        first, counts = self.block(lo, hi, pad)
        corner = self.origin + (first + 0.5) * self.dp
        return first, shape.inside_lattice(corner, self.dp, counts)


def dilate(mask, layers):
    """The sites within `layers` (chessboard distance) of a True site of `mask` (bool (nx, ny, nz)); the grid's edge
    is not crossed (pad it first)."""
    out = mask
    for axis in range(3):
        padded = np.pad(out, [(layers, layers) if a == axis else (0, 0) for a in range(3)])
        windows = np.lib.stride_tricks.sliding_window_view(padded, 2 * layers + 1, axis=axis)
        out = windows.any(axis=-1)
    return out


def sites_of(first, mask):
    """Integer sites (N, 3) of the True cells of a grid whose cell (0, 0, 0) is site `first`, x slowest."""
    return np.argwhere(mask) + first


def filled(lattice, shape):
    """Every site the shape holds."""
    first, mask = lattice.inside(shape)
    return sites_of(first, mask)


def inner_shell(lattice, shape, layers):
    """The sites the shape holds within `layers` of its outside: a body's walls, hollow beyond the kernel's reach."""
    first, mask = lattice.inside(shape, pad=1)
    return sites_of(first, mask & dilate(~mask, layers))


def outer_shell(lattice, shape, layers, open_faces=()):
    """The sites outside the shape within `layers` of it: a tank's walls, the shape being its inside. Past an open
    face ('+z': the top of a box or a cylinder) the shape runs on, and no wall is built there."""
    long = shape.stretched(open_faces, (layers + 1) * lattice.dp)
    first, mask = lattice.inside(long, pad=layers + 1)
    shell = dilate(mask, layers) & ~mask
    sites = sites_of(first, shell)
    if open_faces:     # a site on an open face's plane is past it, by the step that decides a site on a face
        stepped = lattice.positions(sites) + ON_FACE * lattice.dp * ON_FACE_STEP
        sites = sites[~shape.beyond_faces(stepped, open_faces)]
    return sites


def site_keys(sites, lo, counts):
    """One int64 per site of the block of `counts` sites from `lo` (for finding sites two parts share)."""
    rel = sites - lo
    return (rel[:, 0] * counts[1] + rel[:, 1]) * counts[2] + rel[:, 2]


def estimated_shell_sites(area, layers, dp):
    """About how many sites a shell of `layers` over a surface of `area` m^2 holds (the memory guard's count)."""
    return int(math.ceil(area * layers / (dp * dp)))
