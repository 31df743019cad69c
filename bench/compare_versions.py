"""Step a scene with this checkout's simulator and with another commit's, in one process: are the results the same
to the bit, and which is faster?

    python -m bench.compare_versions REF SCENE [SCENE ...] [--steps N] [--rounds R] [--set KEY=VALUE ...]
    python -m bench.compare_versions REF --all --rounds 0      (every scene and scheme of SUITE, bits only)

REF is any git commit (e.g. HEAD~3). Its `sph_fsi_core` and `config/` are exported with `git archive` into a temporary
directory as the package `ref_core`, so both versions import side by side. Both simulations are built from the same
scene and overrides; `--steps` outer steps later their state (COMPARED) and every time-series row are compared
(bitwise, or the largest difference). Then `--rounds` more outer steps each, alternating, are timed: on this project's
2-core VM a process can run at half speed for its whole life (docs/performance/BENCH.md), so code versions are
compared only within one process. Numba's cache of the copy lives in the temporary directory and is discarded with it;
this checkout's is its own source-keyed one (sph_fsi_core/jit_cache.py). The solid's arrays are compared
on its moving particles and its clamp's apart (a version may leave out a clamp's unreached particles); the speed is
given per particle-step and per simulated second, which counts a particle left out as work saved.

The order's bias: the package loaded and built second runs slower in the same process whatever the code. HEAD
against itself reads 0.93x on `lobovsky_dam_break` (80 rounds), and pass by pass the second package's wall pressure
takes 2.7x the first's, its density pass 1.27x; with `--this-first` the bias turns round, and two simulations of
one package in one process show none (docs/performance/BENCH.md, "Two threads, two speeds"). So a speed-up is
measured twice, once in each order (each run a process of its own), and the geometric mean of the two is taken.
"""
import argparse
import importlib
import subprocess
import sys
import tarfile
import tempfile
import time
from pathlib import Path

import numpy as np

import sph_fsi_core  # noqa: F401  (first: this checkout's Numba cache is set up before the copy's kernels exist)

ROOT = Path(__file__).resolve().parents[1]
THIS = "this checkout"


def export(ref, into):
    """`git archive REF sph_fsi_core config` unpacked into `into`, the package renamed ref_core."""
    archive = into / "ref.tar"
    subprocess.run(["git", "-C", str(ROOT), "archive", "-o", str(archive), ref, "sph_fsi_core", "config"], check=True)
    with tarfile.open(archive) as tar:
        tar.extractall(into, filter="data")
    (into / "sph_fsi_core").rename(into / "ref_core")
    return into


def import_version(package, module, cache_dir):
    """Import `package.module`; with `cache_dir`, the kernels it defines cache there (Numba picks a kernel's cache
    directory when the kernel is defined), not in this checkout's cache."""
    if cache_dir is None:
        return importlib.import_module(f"{package}.{module}")
    from numba.core import config
    before = config.CACHE_DIR
    config.CACHE_DIR = str(cache_dir)
    try:
        return importlib.import_module(f"{package}.{module}")
    finally:
        config.CACHE_DIR = before


# the state compared to the bit: every array a later step reads or an output reports
COMPARED = {"solid": ("pos", "vel", "rho", "stress", "pressure", "acc", "stress_gradient"),
            "fluid": ("pos", "vel", "rho", "pressure", "correction_displacement")}


def state(sim):
    """COMPARED's arrays; the solid's on its moving particles, its clamp's apart (`solid.clamp.*`): a version that
    leaves out a clamp's unreached particles (scenes/built.without_unreached_clamp) has another count of them."""
    out = {}
    for phase, names in COMPARED.items():
        obj = getattr(sim, phase)
        if obj is not None:
            for name in names:
                values = getattr(obj, name)
                if phase == "solid" and len(values):
                    out[f"solid.{name}"] = values[obj.movable].copy()
                    out[f"solid.clamp.{name}"] = values[~obj.movable].copy()
                else:
                    out[f"{phase}.{name}"] = values.copy()
    return out


def sample_columns(rows):
    """The time series' rows as {column: array} (NaN where a row lacks the column)."""
    keys = list(dict.fromkeys(k for r in rows for k in r))
    return {f"timeseries.{k}": np.array([float(r.get(k, np.nan)) for r in rows]) for k in keys}


def particle_steps(sim):
    """Particle-steps so far, of either version's Simulation (the phases' counts; an older one's own)."""
    def steps(phase, older):
        return getattr(sim, older) if not hasattr(sim, "solid_phase") else getattr(sim, phase).steps
    n = sim.solid.count * steps("solid_phase", "solid_steps") if sim.solid is not None else 0
    return n + (sim.fluid.count * steps("fluid_phase", "fluid_steps") if sim.fluid is not None else 0)


# Every built-in scene and example, and the schemes and models a scene can switch to, each at settings small enough
# for a few outer steps (`--all`): (scene, overrides). A refactor keeps every one the same to the bit.
SUITE = (
    ("cantilever", []), ("cantilever", ["solid.scheme=gray2001"]), ("cantilever", ["solid.scheme=quadratic_plain"]),
    ("cantilever", ["solid.scheme=quadratic_plain_artificial_stress"]),
    ("cantilever", ["solid.velocity_gradient=linear", "solid.scheme=gray2001"]),
    ("cantilever_loaded", []), ("clamped_plate", []), ("hydrostatic", []), ("hydrostatic", ["fluid.settle_time=0.01"]),
    ("dam_break", []), ("lobovsky_dam_break", ["numerics.spacing=0.03", "fluid.settle_time=0.02"]),
    ("spheric2_dam_break", ["numerics.spacing=0.055", "fluid.settle_time=0.02", "output.timeseries_interval=0.005"]),
    ("elastic_gate", []), ("elastic_gate", ["coupling.model=seed"]),
    ("elastic_gate", ["solid.scheme=gray2001", "numerics.spacing=0.002"]),
    ("elastic_gate", ["fluid.settle_time=0.005", "coupling.relaxation=0.5"]),
    ("antoci_gate", ["numerics.spacing=0.0016666666666667"]), ("antoci_gate_static", []), ("antoci_gate_loaded", []),
    ("hydrostatic_plate", []), ("config/examples/cantilever_geometry.yaml", []),
    ("config/examples/cantilever_stl.yaml", []), ("config/examples/hydrostatic_geometry.yaml", []),
    ("config/examples/spheric2_elastic_fin.yaml", ["output.timeseries_interval=0.002"]),
)


def compare(versions_to_load, scene_name, overrides, steps, rounds):
    """Both versions of one scene: the same to the bit after `steps` outer steps? Then `rounds` timed ones each,
    alternating. Returns whether they are the same."""
    versions = {}
    for name, package, cache in versions_to_load:
        scene = import_version(package, "scene", cache)
        simulation = import_version(package, "simulation", cache)
        spec = scene.load_scene(scene_name, overrides + ["output.snapshot_interval=0"])
        versions[name] = simulation.Simulation(spec)
    rows = {name: [] for name in versions}
    for name, sim in versions.items():
        for _ in range(steps):
            sim.step()
            rows[name].append(sim.sample())
    new_name = THIS
    ref_name = next(name for name in versions if name != THIS)
    ref_sim, new_sim = versions[ref_name], versions[new_name]
    a = {**state(ref_sim), **sample_columns(rows[ref_name])}
    b = {**state(new_sim), **sample_columns(rows[new_name])}
    same = set(a) == set(b)
    if not same:
        print(f"compared arrays differ: only in {ref_name}: {sorted(set(a) - set(b))}; only in {new_name}: "
              f"{sorted(set(b) - set(a))}")
    for key in sorted(set(a) & set(b)):
        if a[key].shape != b[key].shape:
            print(f"{key}: not compared, shapes {a[key].shape} and {b[key].shape}")
            continue
        if np.array_equal(a[key], b[key], equal_nan=True):
            if rounds:
                print(f"{key}: the same to the bit")
        else:
            same = False
            print(f"{key}: differs by up to {np.abs(a[key] - b[key]).max():.3e} (values up to "
                  f"{np.abs(a[key]).max():.3e})")
    label = " ".join([scene_name] + overrides)
    print(f"{label}: {'the same to the bit' if same else 'NOT the same'} after {steps} outer steps "
          f"({len(a)} arrays and time-series columns)", flush=True)
    if rounds == 0:
        return same
    rates = {name: [] for name in versions}
    simulated = {name: [] for name in versions}
    for _ in range(rounds):
        for name, sim in versions.items():
            work, t0, time0 = particle_steps(sim), time.perf_counter(), sim.time
            sim.step()
            wall = time.perf_counter() - t0
            rates[name].append((particle_steps(sim) - work) / wall)
            simulated[name].append((sim.time - time0) / wall)
    medians = {name: float(np.median(r)) for name, r in rates.items()}
    speeds = {name: float(np.median(r)) for name, r in simulated.items()}
    for name, r in medians.items():
        print(f"{name}: {r / 1e6:.3f} M particle-steps/s, {speeds[name]:.4g} simulated s per wall s (medians "
              f"of {rounds} outer steps)")
    print(f"speed-up of this checkout over {ref_name}: {medians[new_name] / medians[ref_name]:.2f}x in "
          f"particle-steps, {speeds[new_name] / speeds[ref_name]:.2f}x in simulated time")
    return same


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("ref")
    parser.add_argument("scenes", nargs="*", help="scene names or files (each with the --set overrides)")
    parser.add_argument("--all", action="store_true", help="every scene and scheme of SUITE, with its overrides")
    parser.add_argument("--steps", type=int, default=5, help="outer steps before the comparison")
    parser.add_argument("--rounds", type=int, default=6, help="timed outer steps per version after it")
    parser.add_argument("--set", dest="overrides", action="append", default=[], metavar="KEY=VALUE")
    parser.add_argument("--this-first", action="store_true",
                        help="load and build this checkout before REF (the order's bias: module docstring)")
    args = parser.parse_args(argv)
    cases = list(SUITE) if args.all else [(scene, args.overrides) for scene in args.scenes]
    if not cases:
        parser.error("name a scene, or --all")
    with tempfile.TemporaryDirectory() as tmp:
        sys.path.insert(0, str(export(args.ref, Path(tmp))))
        versions_to_load = ((args.ref, "ref_core", Path(tmp) / "numba"), (THIS, "sph_fsi_core", None))
        if args.this_first:
            versions_to_load = versions_to_load[::-1]
        different = [" ".join([scene] + overrides) for scene, overrides in cases
                     if not compare(versions_to_load, scene, list(overrides), args.steps, args.rounds)]
    if len(cases) > 1:
        print(f"{len(cases) - len(different)} of {len(cases)} the same to the bit"
              + (f"; not: {'; '.join(different)}" if different else ""))
    return 1 if different else 0


if __name__ == "__main__":
    sys.exit(main())
