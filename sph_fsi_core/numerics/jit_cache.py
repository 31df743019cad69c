"""Whether Numba's on-disk cache already holds the simulator's compiled kernels, so that a driver can say a run is
about to compile (minutes after an install or a source update) instead of going quiet.

Numba compiles an @njit(cache=True) function at its first call and keeps the machine code in the module's
__pycache__ (or NUMBA_CACHE_DIR); an index per function lists the compiled signatures and is void once its source
file changes. This reads those indexes through Numba's own cache objects (numba is pinned in requirements.txt); if
they cannot be read, it says it cannot tell rather than guess.
"""


# What a driver says before a run whose kernels are not cached yet.
COMPILING_LINE = ("compiling the simulator's kernels (Numba; the first run after an install or a source update takes "
                  "a minute or two here, later runs start at once)")


def _entry_kernels(phases, fitted_solid=True):
    """The kernels every run of a scene with these phases calls, one per phase (the rest compile alongside); the
    solid's is its scheme's driver (fitted_solid: solid.velocity_gradient = quadratic)."""
    kernels = []
    if "solid" in phases:
        from ..solid.stepper import fitted_leapfrog, sph_leapfrog
        kernels.append(fitted_leapfrog if fitted_solid else sph_leapfrog)
    if "fluid" in phases:
        from ..fluid.stepper import correction_loop
        kernels.append(correction_loop)
    if "coupling" in phases:
        from ..coupling import pressure_force_on_solid
        kernels.append(pressure_force_on_solid)
    return kernels


def kernels_cached(phases, fitted_solid=True):
    """True if each entry kernel for `phases` (and the solid's scheme: fitted_solid, as _entry_kernels) has compiled
    code in the cache, False if one has none, None if the cache cannot be read (caching off, or Numba's internals
    changed)."""
    try:
        for kernel in _entry_kernels(phases, fitted_solid):
            cache = kernel._cache
            if not cache._cache_file._load_index():
                return False
        return True
    except (AttributeError, OSError, TypeError, ValueError):
        return None


def fitted_solid(spec):
    """Whether a scene (scene.SceneSpec) runs the quadratic fit's solid driver (kernels_cached's fitted_solid)."""
    return "solid" in spec.phases and spec["solid.velocity_gradient"] == "quadratic"


def scene_kernels_cached(spec):
    """kernels_cached for a scene (scene.SceneSpec): its phases and its solid's scheme."""
    return kernels_cached(spec.phases, fitted_solid(spec))


def start_parallel_runtime():
    """Start Numba's threading layer now, before any kernel runs.

    A cached kernel compiled without parallel=True that calls a parallel=True one (the solid's leapfrog drivers and
    their passes) is loaded from the cache with the threading layer's entry points still unset when it is the first
    compiled code a process calls: it then jumps to address 0 (numba/numba#8578, #4807, open). A fresh build calls a
    parallel kernel first and starts the layer on the way; a run restored from a checkpoint (checkpoint.py) calls the
    solid's leapfrog first, which crashed. Starting the layer is idempotent and takes microseconds once started."""
    from numba.np.ufunc import parallel
    parallel._launch_threads()
