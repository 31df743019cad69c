"""Numba's on-disk cache of the simulator's kernels: where it lives, and whether it already holds them, so that a
driver can say a run is about to compile (minutes after an install or a source update) instead of going quiet.

Numba compiles an @njit(cache=True) function at its first call and keeps the machine code in the module's
__pycache__ (or NUMBA_CACHE_DIR); an index per function lists the compiled signatures and is void once its source
file changes. This reads those indexes through Numba's own cache objects (numba is pinned in requirements.txt); if
they cannot be read, it says it cannot tell rather than guess.

A cached kernel also holds the machine code of every kernel it calls, from other files too, and Numba voids it only
when its own file changes (numba/numba#6845): after an edit of solid/implicit_pressure.py alone the solid's
leapfrog in solid/stepper.py kept calling the old solve, and a run mixed the two versions without a word. So the
cache lives in a directory named by a digest of every file that defines kernels (use_source_keyed_cache, called
when sph_fsi_core is imported): a source update starts an empty cache, and going back to a version finds its own.
"""
import hashlib
import os
import re
import shutil
import sys
import time
from pathlib import Path

PACKAGE_DIR = Path(__file__).resolve().parent
_KERNEL = re.compile(r"^@njit\b", re.MULTILINE)
# how many caches of other source versions are kept beside the current one (the most recently used)
KEEP_OTHER_VERSIONS = 3
# a cache used within this many seconds is never removed (another process may be running that version)
IN_USE_SECONDS = 3600.0


def kernel_sources(package_dir=PACKAGE_DIR):
    """The package's files that define Numba kernels (a line starting "@njit"), sorted. The kernels read no constant
    from any other file (a global is frozen into the machine code at compile time)."""
    return sorted(path for path in Path(package_dir).rglob("*.py")
                  if "__pycache__" not in path.parts and _KERNEL.search(path.read_text(encoding="utf-8")))


def source_digest(package_dir=PACKAGE_DIR):
    """16 hex digits of SHA-256 over the kernel files' paths (relative to the package) and contents."""
    digest = hashlib.sha256()
    for path in kernel_sources(package_dir):
        digest.update(path.relative_to(package_dir).as_posix().encode() + b"\0" + path.read_bytes() + b"\0")
    return digest.hexdigest()[:16]


def cache_root(package_dir=PACKAGE_DIR):
    """The directory holding one cache per source version: the package's own __pycache__/numba where it can be
    written (as Numba's own default, next to the sources; `make clean` removes it), else the user's cache directory
    ($XDG_CACHE_HOME or ~/.cache, then sph_fsi/numba)."""
    local = Path(package_dir) / "__pycache__" / "numba"
    try:
        local.mkdir(parents=True, exist_ok=True)
        if os.access(local, os.W_OK):
            return local
    except OSError:
        pass
    return Path(os.environ.get("XDG_CACHE_HOME") or Path.home() / ".cache") / "sph_fsi" / "numba"


def prune_caches(root, current, keep=KEEP_OTHER_VERSIONS, in_use_seconds=IN_USE_SECONDS):
    """Remove the caches of other source versions under `root` beyond the `keep` most recently used, unless one was
    used within `in_use_seconds`. Returns the removed directories."""
    others = [p for p in Path(root).iterdir() if p.is_dir() and p != Path(current)]
    others.sort(key=lambda p: p.stat().st_mtime, reverse=True)
    removed = []
    for path in others[keep:]:
        if time.time() - path.stat().st_mtime > in_use_seconds:
            shutil.rmtree(path, ignore_errors=True)
            removed.append(path)
    return removed


def use_source_keyed_cache(package_dir=PACKAGE_DIR):
    """Point Numba's cache at cache_root()/source_digest() (NUMBA_CACHE_DIR, inherited by child processes such as
    precompile's), marked as used now, the old versions pruned; returns it. A NUMBA_CACHE_DIR the user set stands
    (returns None): that cache is theirs to empty after a source update. Call before the first kernel is defined
    (sph_fsi_core/__init__.py does); Numba reads the variable when imported, so if it already was, its setting is
    changed too."""
    if os.environ.get("NUMBA_CACHE_DIR"):
        return None
    root = cache_root(package_dir)
    path = root / source_digest(package_dir)
    try:
        path.mkdir(parents=True, exist_ok=True)
        os.utime(path)
    except OSError:
        return None     # Numba falls back to its own locations
    try:
        prune_caches(root, path)
    except OSError:     # another process pruning at the same time: the keyed cache stands
        pass
    os.environ["NUMBA_CACHE_DIR"] = str(path)
    config = sys.modules.get("numba.core.config")
    if config is not None:
        config.CACHE_DIR = str(path)
    return path


# What a driver says before a run whose kernels are not cached yet.
COMPILING_LINE = ("compiling the simulator's kernels (Numba; the first run after an install or a source update takes "
                  "a minute or two here, later runs start at once)")


def _entry_kernels(phases, fitted_solid=True):
    """The kernels every run of a scene with these phases calls, one per phase (the rest compile alongside); the
    solid's is its scheme's driver (fitted_solid: solid.velocity_gradient = quadratic)."""
    kernels = []
    if "solid" in phases:
        from .solid.stepper import fitted_leapfrog, sph_leapfrog
        kernels.append(fitted_leapfrog if fitted_solid else sph_leapfrog)
    if "fluid" in phases:
        from .fluid.stepper import correction_loop
        kernels.append(correction_loop)
    if "coupling" in phases:
        from .coupling.forces import pressure_pair_forces
        kernels.append(pressure_pair_forces)
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
