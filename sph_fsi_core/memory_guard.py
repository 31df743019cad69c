"""Refuse a scene too large for this machine before building it, with one line naming numerics.spacing.

The estimate: each builder's particle_counts(values) (the particles build() would make, computed from the layer
counts without making them) times the resident memory a running particle of each phase takes, plus the process's
base. The per-phase costs are the slopes of resident memory (psutil RSS after two steps) against particle count,
measured with one Numba thread, and rounded up:
    solid  5.5 kB: cantilever (quadratic fit, mirrored clamp) 8,544 -> 63,936 particles, 5.36 kB each;
    fluid  1.3 kB and walls 0.5 kB: dam break 26,868 -> 92,028 particles (fluid and walls), 1.18 kB each;
    the paper's gate 1 mm -> 0.5 mm (313,344 more of all three) takes 451 MB where these give 524 MB.
The limit is the memory the system reports available now (psutil), or the SPH_FSI_MAX_PARTICLES environment
variable (`sph-fsi run --max-particles N` sets it) when given.
"""
import os

from .schema import SceneError

BYTES_PER_PARTICLE = {"solid": 5500, "fluid": 1300, "walls": 500}
BASE_BYTES = 300 * 2 ** 20       # Python, NumPy, Numba and the compiled kernels: about 0.2-0.3 GiB resident
MAX_PARTICLES_ENV = "SPH_FSI_MAX_PARTICLES"
GIB = 2 ** 30


def estimate(counts):
    """(particles, bytes) a run of these {phase: count} takes."""
    particles = sum(counts.values())
    return particles, BASE_BYTES + sum(BYTES_PER_PARTICLE.get(phase, 1300) * n for phase, n in counts.items())


def available_bytes():
    import psutil
    return psutil.virtual_memory().available


def max_particles_from_env():
    raw = os.environ.get(MAX_PARTICLES_ENV, "").strip()
    if not raw:
        return None
    try:
        value = int(float(raw))
    except ValueError:
        value = 0
    if value < 1:
        raise SceneError(f"{MAX_PARTICLES_ENV} = {raw!r}: not a particle count; allowed: a positive integer")
    return value


def check(builder, values):
    """SceneError if the scene's particles would not fit: above SPH_FSI_MAX_PARTICLES when set, else above the
    memory available now."""
    counts = builder.particle_counts(values)
    particles, need = estimate(counts)
    dp = values["numerics.spacing"]
    phases = ", ".join(f"{phase} {n:,}" for phase, n in counts.items())
    limit = max_particles_from_env()
    if limit is not None:
        if particles > limit:
            raise SceneError(f"numerics.spacing = {dp:g} m: the scene would have {particles:,} particles ({phases}), "
                             f"above the limit {MAX_PARTICLES_ENV} (--max-particles) = {limit:,}; allowed: a "
                             f"coarser numerics.spacing or a higher limit")
        return
    have = available_bytes()
    if need > have:
        raise SceneError(f"numerics.spacing = {dp:g} m: the scene would have {particles:,} particles ({phases}), "
                         f"about {need / GIB:,.1f} GiB, and {have / GIB:,.1f} GiB of memory is available; allowed: "
                         f"a coarser numerics.spacing, or --max-particles N (the node: {MAX_PARTICLES_ENV}=N) to "
                         f"override the estimate")
