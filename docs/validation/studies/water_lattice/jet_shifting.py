"""The plane jet on a wall (config/jet_on_wall.yaml, docs/method.md "A plane jet on a wall") with the water shifted
after every fluid step (particle_shifting.py: Lind et al. 2012's Fickian shifting, none in the free surface's band):
whether a more even arrangement of the flowing water takes the noise out of its pressure (docs/validation/OPEN.md
1.5). No scene key does this (FluidSolver.step is wrapped here); it prints the scene's judges (the wall's force, the
axis pressure and its swing over 1/2 rho U^2) and the swing left in 5 ms means.

    python docs/validation/studies/water_lattice/jet_shifting.py A [--global-speed] [KEY=VALUE ...]
    (e.g. 0.5; A = 0 runs the scene as it is; b/dp 20: about 4 minutes on 2 threads with A > 0; --global-speed
    shifts by the water's largest speed instead of each particle's, so the stagnation region is shifted too)

Under iisph_step.py (A = 0) it runs the jet with a pressure field solved each step instead of the correction
(docs/validation/OPEN.md 1.5), from the repository's root: PYTHONPATH=docs/validation/studies/water_lattice python
docs/validation/studies/water_lattice/iisph_step.py 0.15 0.5 1 jet_shifting.py 0 fluid.density_tolerance=0.001
"""
import sys
import tempfile

import numpy as np
from particle_shifting import install

from sph_fsi_core.run import run_scene
from sph_fsi_core.scene import load_scene

SHIFT = float(sys.argv[1]) if len(sys.argv) > 1 else 0.5
GLOBAL = "--global-speed" in sys.argv
KEYS = [a for a in sys.argv[2:] if a != "--global-speed"]
MEAN_WINDOW = 0.005   # s

spec = load_scene("config/jet_on_wall.yaml", ["output.snapshot_interval=0"] + KEYS)
install(SHIFT, spec.values["numerics.spacing"], free_surface=True, global_speed=GLOBAL)
with tempfile.TemporaryDirectory() as out:
    summary = run_scene(spec, out_dir=out)
    series = np.genfromtxt(f"{out}/timeseries.csv", delimiter=",", names=True)
j = summary["judges"]
t = series["time"]
steady = (t >= j["axis_swing"]["from_s"]) & (t <= j["axis_swing"]["to_s"])
samples = max(1, round(MEAN_WINDOW / float(np.median(np.diff(t)))))
means = np.convolve(series["axis_pressure"][steady], np.ones(samples) / samples, "valid")
print(f"shift {SHIFT:g}{' (global speed)' if GLOBAL else ''}, {' '.join(KEYS) or 'the defaults'}: force "
      f"{100 * j['force']['error_signed']:+.2f} %, axis "
      f"pressure {100 * j['axis_pressure']['error_signed']:+.2f} %, its swing {100 * j['axis_swing']['error']:.1f} % "
      f"of 1/2 rho U^2 ({100 * means.std() / j['axis_swing']['reference']:.1f} % in 5 ms means); "
      f"{summary['wall_time_s']:.0f} s")
