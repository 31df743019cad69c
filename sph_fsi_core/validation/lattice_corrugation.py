"""How much eq. (1)'s density sum changes as one lattice slides over another: the bumps the density correction
feels when water slides along a wall, or one layer of water over the next, while the particles keep their lattice.

The water and the walls are built on one simple cubic lattice of spacing dp. Take the particles of a half-space
below a plane (layers at z = -dp, -2 dp, ...) and a particle one spacing above them (z = 0). The sum
S(s) = dp^3 sum_b W(|x + s - x_b|, h) over the half-space, with the particle shifted by s along the plane, is the
half-space's share of the particle's density over rho0. If the particle's own layer slides with it (a layer of
water or the whole water sliding as one), its layer's share stays the same and S(s) is all that changes. Its range
over a half-spacing's slide, max S - min S, is a compression that appears and goes as the layer slides: the density
correction pushes the layer back into the wells of S where that range reaches the tolerance's slack, which a slow
layer cannot climb out of. It depends on h / dp through the kernel's spectrum at the lattice's wavenumbers, and
is nearly zero near h / dp = 1.25 and 1.5 for the M4 spline along a lattice axis (docs/validation/OPEN.md 7).
"""
import numpy as np

from ..numerics.kernels import SUPPORT_RADIUS_IN_H, cubic_spline_w


def half_space_share(ratio, shift):
    """S(s) of the module docstring for h / dp = `ratio` and the shift `shift` (3,) in spacings (along the plane:
    its z is 0): the half-space's share of the particle's density, over rho0 (dp = 1 here, as
    numerics.kernels.lattice_kernel_sum's full lattice)."""
    reach = int(np.ceil(SUPPORT_RADIUS_IN_H * ratio)) + 1
    g = np.arange(-reach, reach + 1, dtype=np.float64)
    x, y, z = np.meshgrid(g, g, -np.arange(1, reach + 1, dtype=np.float64), indexing="ij")
    r = np.sqrt((x - shift[0]) ** 2 + (y - shift[1]) ** 2 + (z - shift[2]) ** 2)
    return float(sum(cubic_spline_w(d, ratio) for d in r.ravel()))


def corrugation(ratio, direction=(1.0, 0.0, 0.0), samples=21):
    """max S - min S over a slide of half a spacing's period along `direction` (in the plane, a lattice axis or a
    diagonal: (1, 0, 0) or (1, 1, 0)), over rho0: the bumps of the module docstring."""
    d = np.asarray(direction, dtype=np.float64)
    values = [half_space_share(ratio, t * d) for t in np.linspace(0.0, 0.5, samples)]
    return max(values) - min(values)
