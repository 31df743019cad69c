"""sph_fsi_core: the 3D SPH simulator of Satake et al. (elastic solid, incompressible fluid, coupling).

Pure Python + Numba; never imports ROS. Entry points: scene.load_scene, simulation.Simulation, run.run_scene.
"""
import os

__version__ = "0.1.0"

# GNU OpenMP (Numba's threading layer here) lets a thread that waits between parallel regions spin 300,000 times
# before it sleeps. A solid sub-step runs about nine regions; with another busy process on one of the 2 cores the
# spinning thread holds the core the working one needs, and the paper's gate stepped 35x slower on 2 threads than
# with 1000 spins (30.3 against 0.88 s per outer step; the 10^5 dam break 3.7 against 1.2 s), while on a quiet host
# 1000 spins step within 2 % of the default (docs/method.md, "Performance design"). Set before Numba starts its
# threads (libgomp reads it when loaded); a value the user set stands.
os.environ.setdefault("GOMP_SPINCOUNT", "1000")
