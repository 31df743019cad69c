"""Each hot pass's speed-up from one Numba thread to two, in one process (issue 60, item 3).

Two real states, each built and stepped in this process before anything is timed (and `host`: loops that tell the
host's limits, compute alone, memory alone, and the viscous term's gathers alone on the dam break's lists):
- `fluid`: the dam break at 10^5 fluid particles (bench/fluid_throughput.py's case), stepped until its water moves
  (the lists then rebuilt every step, as after SPHERIC's impact);
- `solid`: the solid bench's 10^5 beam with the default scheme (bench/solid_throughput.py), after one outer step.
Each pass is called on the same state again and again: the arrays it writes are put back before every call
(`restore`), so every call does the same work with the same bits. Rounds alternate 1 and 2 threads
(numba.set_num_threads) call by call, and the medians are compared: the host's drift between processes and hours
(docs/performance/BENCH.md) then cancels. The per-chunk buffers of the half-list passes keep the two chunks they
were allocated with, so one thread runs both chunks in turn: the same work and the same sums.

A pass's speed-up below 1.7x is either fixed or explained in docs/performance/BENCH.md ("Two threads, pass by
pass"). `python -m bench.thread_scaling [--rounds 7] [--steps 40]`; do not run another benchmark at the same time.
"""
import argparse
import json
import os
import statistics
import time

import numba
import numpy as np
from numba import njit, prange

from sph_fsi_core.fluid.energy import mechanical_energy
from sph_fsi_core.fluid.okaji import (apply_displacement, compression_error, gravity_and_predictor,
                                      pressure_displacement, summation_density, velocity_from_displacement,
                                      viscous_velocity, wall_pressure)
from sph_fsi_core.fluid.stepper import FluidArrays
from sph_fsi_core.numerics.neighbours import max_displacement
from sph_fsi_core.scene import load_scene
from sph_fsi_core.simulation import Simulation
from sph_fsi_core.solid import stepper as solid_stepper
from sph_fsi_core.solid.fitted_gradient import (momentum_rate_mls, velocity_divergence_rate,
                                                xsph_velocity_and_mls_gradient)
from sph_fsi_core.solid.gradient_integration import gradient_force_rows, stress_gradient_rate, velocity_hessian
from sph_fsi_core.solid.gray2001 import jaumann_stress_rate, stress_terms
from sph_fsi_core.solid.implicit_pressure import deviatoric_over_rho2, implicit_pressure_step

from .fluid_throughput import CASES, SCENES
from .solid_throughput import beam_spec

TARGET = 1.7   # the bar for a pass's speed-up on 2 threads


def snapshot(*bundles):
    """Copies of every array in `bundles` (NamedTuples of arrays, or arrays), and the function that puts them back."""
    arrays = []
    for bundle in bundles:
        for value in (bundle if isinstance(bundle, tuple) else (bundle,)):
            if isinstance(value, np.ndarray) and value.size:
                arrays.append(value)
    saved = [a.copy() for a in arrays]

    def restore():
        for a, s in zip(arrays, saved):
            a[...] = s
    return restore


def time_pass(call, restore, rounds, threads=(1, 2)):
    """Median seconds of `call` at each thread count, the counts alternating call by call (after one warm call)."""
    times = {k: [] for k in threads}
    for k in threads:
        numba.set_num_threads(k)
        restore()
        call()
    for _ in range(rounds):
        for k in threads:
            numba.set_num_threads(k)
            restore()
            t0 = time.perf_counter()
            call()
            times[k].append(time.perf_counter() - t0)
    numba.set_num_threads(max(threads))
    return {k: statistics.median(v) for k, v in times.items()}


def moving_dam_break(steps, size):
    """(Simulation, its FluidSolver) of the dam break at `size` fluid particles after `steps` outer steps."""
    sim = Simulation(load_scene(SCENES["dam_break"], CASES[("dam_break", size)] + ["output.snapshot_interval=0"]))
    for _ in range(steps):
        sim.step()
    return sim, sim.fluid_phase.solver


def fluid_passes(steps, size="1e5"):
    """(name, call, restore, serial) of the dam break's step at `size` (10^4 or 10^5 fluid particles) after `steps`
    outer steps; serial: a pass written as one loop (no prange)."""
    sim, sv = moving_dam_break(steps, size)
    fl = sv.fluid
    dt = sv.stable_dt(0.2)
    c = sv.correction_c(dt)
    prm = sv.correction_params(c, dt)
    arrays = FluidArrays.of(fl)
    walls = sv.wall_arrays()
    gx, gy, gz = sv.gravity
    sv.rebuild()
    nb, work = sv.neighbours(), sv.buffers()
    summation_density(arrays, walls, nb, prm, work)   # this iteration's pressures, for the passes after it
    keep = snapshot(arrays, walls, work, sv.vel_work, sv.pos_old, fl.vel)
    none = snapshot()
    passes = [
        ("lists: the water's half list", lambda: sv.fluid_neighbours.build(fl.pos, fl.pos), none, False),
        ("lists: all three (a rebuild)", sv.rebuild, none, False),
        ("density and eq. (7) (eq. (1))", lambda: summation_density(arrays, walls, nb, prm, work), keep, False),
        ("wall pressure (Shepard)", lambda: wall_pressure(walls, fl.pos, work.p, nb, prm.h, prm.rho0, prm.kernel), keep, False),
        ("position correction (eq. (2))", lambda: pressure_displacement(arrays, walls, nb, prm, work), keep, False),
        ("apply the correction", lambda: apply_displacement(fl.pos, work.disp, fl.correction_displacement,
                                                            nb.targets_at_build, work.moved2), keep, False),
        ("compression error", lambda: compression_error(fl.rho, prm.rho0), none, True),
        ("viscous term (eq. (9))", lambda: viscous_velocity(fl.pos, fl.vel, fl.mass, fl.rho, nb, work, sv.h, sv.nu,
                                                             dt, sv.vel_work), keep, False),
        ("gravity and predictor (eq. (6))", lambda: gravity_and_predictor(fl.pos, fl.vel, dt, gx, gy, gz, sv.pos_old),
         keep, False),
        ("velocity from displacement (eq. (8))", lambda: velocity_from_displacement(fl.pos, sv.pos_old, dt, fl.vel),
         keep, False),
        ("skin test", lambda: max_displacement(fl.pos, nb.targets_at_build), none, False),
        ("mechanical energy", lambda: mechanical_energy(fl.pos, fl.vel, fl.mass, gx, gy, gz), none, True),
    ]
    state = snapshot(fl.pos, fl.vel, fl.rho, fl.pressure, fl.correction_displacement)

    def whole_step():
        sv.step(dt)

    def restore_step():
        state()
        sv.rebuild()
    passes.append(("the whole fluid step", whole_step, restore_step, False))
    info = {"fluid_particles": int(fl.count), "wall_particles": int(sim.walls.count), "dt_s": dt,
            "pairs_per_particle": round(sv.fluid_neighbours.pairs / fl.count, 1)}
    return passes, info


def solid_passes(size="1e5"):
    """(name, call, restore, serial) of the beam's default step (the quadratic fit, the strain-gradient integration,
    the implicit pressure) at `size` (10^4 or 10^5 particles) after one outer step."""
    sim = Simulation(beam_spec(size, []))
    sim.step()
    sv = sim.solid_phase.solver
    dt = sv.stable_dt()
    args = sv.leapfrog_arguments(1, True, dt)
    _, _, _, state, nb, prm, work, ext_acc, clamp_mirror, variant = args
    leapfrog = solid_stepper.solid_drivers(prm)[0]
    keep = snapshot(state, work)
    body = np.array([prm.gx, prm.gy, prm.gz])
    passes = [
        ("implicit pressure's solve", lambda: implicit_pressure_step(dt, state, nb, prm, work, clamp_mirror), False),
        ("velocity gradient and XSPH (the fit)", lambda: xsph_velocity_and_mls_gradient(state, nb, prm, work), False),
        ("velocity divergence rate", lambda: velocity_divergence_rate(state.rho, work.grad_v, work.drho), False),
        ("Jaumann stress rate", lambda: jaumann_stress_rate(work.grad_v, state.stress, prm.shear_modulus,
                                                            work.dstress), False),
        ("velocity Hessian", lambda: velocity_hessian(state, nb, prm, work), False),
        ("stress gradient rate", lambda: stress_gradient_rate(work.hessian, work.grad_v, state.stress,
                                                              state.stress_gradient, prm.shear_modulus,
                                                              prm.gradient_bulk_modulus, work.dstress_gradient), False),
        ("advance rho, S, r", lambda: solid_stepper._advance_state(dt, state, work, prm, clamp_mirror), True),
        ("stress terms (artificial stress)", lambda: stress_terms(state.stress, state.rho, prm.rho0, prm.c0 * prm.c0,
                                                                  prm.art_eps, state.pressure, work.sigma_over_rho2,
                                                                  work.art_stress, work.eig_work), False),
        ("deviatoric stress over rho^2", lambda: deviatoric_over_rho2(state.stress, state.rho, work.sigma_over_rho2),
         False),
        ("gradient force rows", lambda: gradient_force_rows(state.mass, state.rho, state.stress_gradient,
                                                            prm.cell_moment, work.mls_rows, work.force_rows), False),
        ("momentum (eq. (5))", lambda: momentum_rate_mls(state, nb, prm, work, body, variant), False),
        ("half kick", lambda: solid_stepper._half_kick(dt, state.vel, state.acc, state.movable, clamp_mirror), True),
        ("particle volumes", lambda: solid_stepper.particle_volumes(state.mass, state.rho, work.volume), True),
        ("fit refresh test", lambda: solid_stepper._fit_refresh_due(dt, prm, work), False),
        ("the whole solid step", lambda: leapfrog(*args), False),
    ]
    info = {"solid_particles": int(sv.solid.count), "dt_s": dt}
    return [(name, call, keep, serial) for name, call, serial in passes], info


@njit(cache=True, parallel=True)
def _divisions(x, repeats):
    """Compute alone: `repeats` dependent divisions per element of a small array, no memory traffic."""
    total = 0.0
    for i in prange(x.shape[0]):
        y = x[i]
        for _ in range(repeats):
            y = 1.0 / (y + 1.0)
        total += y
    return total


@njit(cache=True, parallel=True)
def _stream(x, y, z):
    """Memory alone: one pass over three long arrays, a multiply-add per element."""
    total = 0.0
    for i in prange(x.shape[0]):
        total += x[i] * y[i] + z[i]
    return total


@njit(cache=True, parallel=True)
def _gather(start, index, pos, vel, rho, f, out):
    """The viscous term's reads without its arithmetic: per pair of the half list, the neighbour's position,
    velocity and density and the pair's F (eight gathered values, one streamed), summed into the target's row."""
    for a in prange(start.shape[0] - 1):
        s = 0.0
        for k in range(start[a], start[a + 1]):
            b = index[k]
            s += pos[b, 0] + pos[b, 1] + pos[b, 2] + vel[b, 0] + vel[b, 1] + vel[b, 2] + rho[b] + f[k]
        out[a] = s


def host_passes(steps, size="1e5"):
    """(name, call, restore, serial) of loops that tell the host's limits: compute alone, memory streamed alone (as
    long as the dam break's pair arrays at 10^5, 3 x 3.2e7 doubles), and the viscous term's gathers alone on the dam
    break's own lists at `size` after `steps` outer steps."""
    _, sv = moving_dam_break(steps, size)
    fl = sv.fluid
    sv.rebuild()
    nb = sv.neighbours()
    small = np.linspace(0.5, 1.5, 4096)
    big = [np.random.default_rng(k).random(32_000_000) for k in range(3)]
    out = np.zeros(fl.count)
    none = snapshot()
    passes = [("compute alone: divisions", lambda: _divisions(small, 20_000), none, False),
              ("memory alone: a stream of 768 MB", lambda: _stream(*big), none, False),
              ("the viscous term's gathers alone", lambda: _gather(nb.fluid_start, nb.fluid_index, fl.pos, fl.vel,
                                                                   fl.rho, sv.f_fluid, out), none, False)]
    info = {"fluid_particles": int(fl.count), "pairs": int(sv.fluid_neighbours.pairs)}
    return passes, info


def measure(passes, rounds):
    rows = []
    for name, call, restore, serial in passes:
        t = time_pass(call, restore, rounds)
        rows.append({"pass": name, "ms_1_thread": 1e3 * t[1], "ms_2_threads": 1e3 * t[2], "speed_up": t[1] / t[2],
                     "serial": serial})
        print(f"  {name:40s} {1e3 * t[1]:9.3f} ms  {1e3 * t[2]:9.3f} ms  {t[1] / t[2]:5.2f}x"
              f"{'  (one loop)' if serial else ''}", flush=True)
    return rows


def markdown(result):
    """The tables of BENCH.md's "Two threads, pass by pass"."""
    lines = []
    for case in ("fluid", "solid", "host"):
        if case not in result:
            continue
        info = result[case]["info"]
        what = {"fluid": lambda: f"the dam break at {info['fluid_particles']:,} fluid particles "
                                 f"({info['wall_particles']:,} wall, {info['pairs_per_particle']} pairs each), its "
                                 f"water moving",
                "solid": lambda: f"the solid bench's beam, {info['solid_particles']:,} particles, the default scheme",
                "host": lambda: f"the host's limits (the gathers on the dam break's {info['pairs']:,} pairs)"}[case]()
        lines += [f"{case.capitalize()}: {what}; median of {result['rounds']} calls each.", "",
                  "| pass | 1 thread [ms] | 2 threads [ms] | speed-up |", "|---|---|---|---|"]
        for row in result[case]["passes"]:
            name = row["pass"] + (" (one loop)" if row["serial"] else "")
            lines.append(f"| {name} | {row['ms_1_thread']:.3f} | {row['ms_2_threads']:.3f} | "
                         f"{row['speed_up']:.2f}x |")
        lines.append("")
    lines.append(f"Load average {result['load_average_before']:.1f} before, {result['load_average_after']:.1f} after.")
    return "\n".join(lines)


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--rounds", type=int, default=7)
    parser.add_argument("--steps", type=int, default=40, help="the dam break's outer steps before timing")
    parser.add_argument("--cases", nargs="*", default=["fluid", "solid"], choices=["fluid", "solid", "host"])
    parser.add_argument("--size", default="1e5", choices=["1e4", "1e5"], help="particles of each state")
    args = parser.parse_args(argv)
    if numba.config.NUMBA_NUM_THREADS < 2:
        raise SystemExit("thread_scaling: needs 2 Numba threads (NUMBA_NUM_THREADS)")
    result = {"rounds": args.rounds, "load_average_before": os.getloadavg()[0]}
    for case in args.cases:
        make = {"fluid": lambda: fluid_passes(args.steps, args.size), "solid": lambda: solid_passes(args.size),
                "host": lambda: host_passes(args.steps, args.size)}[case]
        passes, info = make()
        print(f"{case}: {info}; median of {args.rounds} calls at 1 and 2 threads", flush=True)
        result[case] = {"info": info, "passes": measure(passes, args.rounds)}
    result["load_average_after"] = os.getloadavg()[0]
    return result


if __name__ == "__main__":
    print(json.dumps(main(), indent=1))
