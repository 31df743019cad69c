"""Does the order the fluid's particles are numbered in matter? The bench's 10^5 dam break (bench.fluid_throughput)
built three ways in one process, its water numbered as the lattice makes it (z fastest, then y, then x), in cell
order (cells 3 dp wide, x-major) and at random, then stepped interleaved over the same outer steps: fluid
particle-iterations per second of each. Only the numbering differs (the water is built at rest: every particle has
the same mass and no velocity, so permuting the positions renumbers it); the iterations come out the same.

`python -m bench.particle_order [--steps N]`; docs/validation/OPEN.md, section 4, has what it measured.
"""
import argparse
import dataclasses
import os
import time

import numpy as np

from sph_fsi_core.scene import load_scene
from sph_fsi_core.scenes import BUILDERS
from sph_fsi_core.simulation import Simulation

from .fluid_throughput import CASES

ORDERS = ("lattice", "cell", "random")


def permutation(pos, order, spacing):
    """Indices that renumber particles at `pos` in `order` (ORDERS)."""
    if order == "lattice":
        return np.arange(len(pos))
    if order == "random":
        return np.random.default_rng(0).permutation(len(pos))
    cell = np.floor((pos - pos.min(0)) / (3.0 * spacing)).astype(np.int64)
    n = cell.max(0) + 1
    return np.argsort((cell[:, 0] * n[1] + cell[:, 1]) * n[2] + cell[:, 2], kind="stable")


def renumbered(builder, order):
    """A scene builder (scenes.Builder) whose build() renumbers the water it makes."""
    def build(values):
        built = builder.build(values)
        fluid = built.fluid
        assert np.all(fluid.mass == fluid.mass[0]) and not np.any(fluid.vel), "the water must be built uniform at rest"
        fluid.pos[:] = fluid.pos[permutation(fluid.pos, order, values["numerics.spacing"])]
        return built
    return dataclasses.replace(builder, build=build)


def simulation(order):
    spec = load_scene("dam_break", CASES[("dam_break", "1e5")] + ["output.snapshot_interval=0"])
    builder = BUILDERS[spec.builder]
    BUILDERS[spec.builder] = renumbered(builder, order)
    try:
        return Simulation(spec)
    finally:
        BUILDERS[spec.builder] = builder


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--steps", type=int, default=25, help="outer steps timed per order (after one untimed)")
    args = parser.parse_args()
    sims = {order: simulation(order) for order in ORDERS}
    for sim in sims.values():
        sim.step()   # compile, first build
    seconds = dict.fromkeys(ORDERS, 0.0)
    iterations = dict.fromkeys(ORDERS, 0)
    for _ in range(args.steps):
        for order, sim in sims.items():
            done = sim.fluid_phase.iterations
            t0 = time.perf_counter()
            sim.step()
            seconds[order] += time.perf_counter() - t0
            iterations[order] += sim.fluid_phase.iterations - done
    n = sims["lattice"].fluid.count
    rate = {order: n * iterations[order] / seconds[order] for order in ORDERS}
    print(f"dam break, {n} water particles, {args.steps} outer steps each, load {os.getloadavg()[0]:.1f}")
    for order in ORDERS:
        print(f"  {order:8s} {rate[order] / 1e6:.3f} M particle-iterations/s ({iterations[order]} iterations, "
              f"{seconds[order]:.1f} s): {rate[order] / rate['lattice']:.3f}x the lattice's order")


if __name__ == "__main__":
    main()
