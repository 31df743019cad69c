"""numerics/jit_cache.py: telling a cold Numba cache from a warm one, so a first run says it is compiling."""
import os
import subprocess
import sys

from sph_fsi_core.numerics import jit_cache


def test_empty_cache_is_cold(tmp_path):
    """With an empty NUMBA_CACHE_DIR no entry kernel has compiled code: False for every phase set (nothing compiles
    here: the index is read, not built)."""
    code = ("from sph_fsi_core.numerics.jit_cache import kernels_cached; "
            "print(kernels_cached(('solid',)), kernels_cached(('fluid', 'walls')), "
            "kernels_cached(('solid', 'fluid', 'walls', 'coupling')))")
    env = dict(os.environ, NUMBA_CACHE_DIR=str(tmp_path))
    out = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True, text=True, timeout=120)
    assert out.returncode == 0, out.stderr
    assert out.stdout.split() == ["False", "False", "False"]


def test_unreadable_cache_says_unknown(monkeypatch):
    class NoCache:
        pass
    monkeypatch.setattr(jit_cache, "_entry_kernels", lambda phases, fitted_solid=True: [NoCache()])
    assert jit_cache.kernels_cached(("solid",)) is None
    monkeypatch.setattr(jit_cache, "_entry_kernels", lambda phases, fitted_solid=True: [])
    assert jit_cache.kernels_cached(()) is True


def test_a_scene_checks_its_own_solid_driver(monkeypatch):
    """Each solid scheme compiles only its own driver (solid.stepper.solid_drivers): the cold-start check asks for the
    scene's, the quadratic fit's for the default scheme and Gray's SPH driver for gray2001, none without a solid."""
    from sph_fsi_core.scene import load_scene
    from sph_fsi_core.solid.stepper import fitted_leapfrog, sph_leapfrog
    asked = []
    monkeypatch.setattr(jit_cache, "kernels_cached", lambda phases, fitted_solid=True: asked.append(
        jit_cache._entry_kernels(phases, fitted_solid)[0] if "solid" in phases else None))
    jit_cache.scene_kernels_cached(load_scene("elastic_gate"))
    jit_cache.scene_kernels_cached(load_scene("elastic_gate", ["solid.scheme=gray2001"]))
    jit_cache.scene_kernels_cached(load_scene("dam_break"))
    assert asked == [fitted_leapfrog, sph_leapfrog, None]
