"""sph_fsi_core: the 3D SPH simulator of Satake et al. (elastic solid, incompressible fluid, coupling).

Pure Python + Numba; never imports ROS. Entry points: scene.load_scene, simulation.Simulation, run.run_scene.
"""
import os

__version__ = "0.1.0"

# GNU OpenMP (Numba's threading layer here) lets a thread that waits between parallel regions spin 300,000 times
# before it sleeps. A solid sub-step runs about nine regions, a fluid iteration four; with another busy process on
# one of the 2 cores the spinning thread holds a core the working one needs. Measured on the gate at 4/3 mm, one
# other busy process: 1.2-2x slower than with 1000 spins, and in one hour (perhaps the VM itself short of CPU) 24-35x;
# on a quiet host 1000 spins step as fast as the default within the host's spread (docs/method.md, "Performance
# design"). Set before Numba starts its threads (libgomp reads it when loaded); a value the user set stands.
os.environ.setdefault("GOMP_SPINCOUNT", "1000")

# Numba's cache in a directory named by the kernels' sources, so an edited file never runs beside stale machine code
# of the kernels calling it (jit_cache.py says why); before any kernel is defined.
from . import jit_cache as _jit_cache  # noqa: E402

_jit_cache.use_source_keyed_cache()
