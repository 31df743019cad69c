"""Whether Numba's on-disk cache already holds the simulator's compiled kernels, so that a driver can say a run is
about to compile (minutes after an install or a source update) instead of going quiet.

Numba compiles an @njit(cache=True) function at its first call and keeps the machine code in the module's
__pycache__ (or NUMBA_CACHE_DIR); an index per function lists the compiled signatures and is void once its source
file changes. This reads those indexes through Numba's own cache objects (numba is pinned in requirements.txt); if
they cannot be read, it says it cannot tell rather than guess.
"""


# What a driver says before a run whose kernels are not cached yet.
COMPILING_LINE = ("compiling the simulator's kernels (Numba; the first run after an install or a source update takes "
                  "a few minutes here, later runs start at once)")


def _entry_kernels(phases):
    """The kernels every run of a scene with these phases calls, one per phase (the rest compile alongside)."""
    kernels = []
    if "solid" in phases:
        from ..solid.stepper import solid_leapfrog
        kernels.append(solid_leapfrog)
    if "fluid" in phases:
        from ..fluid.stepper import correction_loop
        kernels.append(correction_loop)
    if "coupling" in phases:
        from ..coupling import pressure_force_on_solid
        kernels.append(pressure_force_on_solid)
    return kernels


def kernels_cached(phases):
    """True if each entry kernel for `phases` has compiled code in the cache, False if one has none, None if the
    cache cannot be read (caching off, or Numba's internals changed)."""
    try:
        for kernel in _entry_kernels(phases):
            cache = kernel._cache
            if not cache._cache_file._load_index():
                return False
        return True
    except (AttributeError, OSError, TypeError, ValueError):
        return None


def start_parallel_runtime():
    """Start Numba's threading layer now, before any kernel runs.

    A cached kernel compiled without parallel=True that calls a parallel=True one (solid_leapfrog and its passes)
    is loaded from the cache with the threading layer's entry points still unset when it is the first compiled code
    a process calls: it then jumps to address 0 (numba/numba#8578, #4807, open). A fresh build calls a parallel kernel
    first and starts the layer on the way; a run restored from a checkpoint (checkpoint.py) calls solid_leapfrog
    first, which crashed. Starting the layer is idempotent and takes microseconds once started."""
    from numba.np.ufunc import parallel
    parallel._launch_threads()
