"""The half-list passes give one answer however the targets are cut into chunks (neighbours.chunk_first_target).

Each chunk sums into its own buffer; a target left out of every chunk or given to two would change the sums far
beyond round-off, so 1, 2 and 5 chunks must agree to round-off on a disordered cloud with a free surface.
"""
import numpy as np
import pytest

import fluid_bundles
import solid_bundles
from sph_fsi_core.fluid.okaji import viscous_velocity
from sph_fsi_core.numerics.neighbours import NeighbourList, pair_kernel_values
from sph_fsi_core.solid.gray2001 import continuity_rate, momentum_rate, xsph_velocity_and_gradient

DP, H = 1e-3, 1.3e-3
NO_PERIOD = np.zeros(3)


def _cloud(seed=4):
    rng = np.random.default_rng(seed)
    g = (np.arange(7) + 0.5) * DP
    pos = np.stack(np.meshgrid(g, g[:4], g, indexing="ij"), -1).reshape(-1, 3)
    pos = np.ascontiguousarray(pos + rng.uniform(-0.15, 0.15, pos.shape) * DP)
    n = len(pos)
    vel = np.ascontiguousarray(rng.normal(size=(n, 3)) * 0.1)
    rho = 1000.0 * (1.0 + rng.uniform(-0.01, 0.01, n))
    mass = np.full(n, 1000.0 * DP ** 3)
    stress = rng.normal(size=(n, 6)) * 1e3
    sigma_over_rho2 = stress / rho[:, None] ** 2
    nl = NeighbourList(2 * H, 0.1 * H, half=True)
    nl.build(pos, pos)
    w = np.zeros(nl.pairs)
    f = np.zeros(nl.pairs)
    pair_kernel_values(pos, pos, nl.start, nl.index, H, NO_PERIOD, w, f)
    return pos, vel, rho, mass, sigma_over_rho2, nl, w, f


def _solid_passes(chunks):
    pos, vel, rho, mass, sigma_over_rho2, nl, w, f = _cloud()
    n = len(pos)
    state = solid_bundles.state(pos, vel, rho, mass)
    lists = solid_bundles.neighbours(nl, NO_PERIOD)
    prm = solid_bundles.params(H, DP, sound_speed=30.0, alpha=1.0, beta=1.0, inv_w_dp=1.0)
    work = solid_bundles.buffers(n, nl.pairs, chunks, w=w, f=f, volume=mass / rho, sigma_over_rho2=sigma_over_rho2)
    xsph_velocity_and_gradient(state, lists, prm, work)
    continuity_rate(state, lists, work)
    momentum_rate(state, lists, prm, work._replace(w=w.copy(), f=f.copy()), np.zeros(3))
    return {"vhat": work.vhat, "grad_v": work.grad_v, "drho": work.drho, "acc": state.acc}


@pytest.mark.parametrize("chunks", [2, 5])
def test_solid_passes_do_not_depend_on_the_chunks(chunks):
    one, many = _solid_passes(1), _solid_passes(chunks)
    for name in one:
        scale = np.abs(one[name]).max()
        assert scale > 0.0
        assert np.abs(many[name] - one[name]).max() < 1e-12 * scale, name


@pytest.mark.parametrize("chunks", [2, 5])
def test_fluid_viscous_pass_does_not_depend_on_the_chunks(chunks):
    pos, vel, rho, mass, _, nl, _, f = _cloud()
    out = {}
    for c in (1, chunks):
        out[c] = np.zeros_like(vel)
        viscous_velocity(pos, vel, mass, rho, fluid_bundles.neighbours(nl, crossing=np.ones(len(pos), dtype=np.bool_)),
                         fluid_bundles.buffers(len(pos), nl.pairs, chunks=c, f_fluid=f), H, 1e-4, 1e-4, out[c])
    change = out[1] - vel
    assert np.abs(change).max() > 0.0
    assert np.abs(out[chunks] - out[1]).max() < 1e-12 * np.abs(change).max()
