"""jit_cache.py: telling a cold Numba cache from a warm one, so a first run says it is compiling."""
import os
import subprocess
import sys
import time
from pathlib import Path

from sph_fsi_core import jit_cache


def test_empty_cache_is_cold(tmp_path):
    """With an empty NUMBA_CACHE_DIR no entry kernel has compiled code: False for every phase set (nothing compiles
    here: the index is read, not built)."""
    code = ("from sph_fsi_core.jit_cache import kernels_cached; "
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


def _write_package(root, value):
    """A two-file kernel package whose `caller.f` returns `callee.g()`, cached by Numba, its cache keyed by
    jit_cache.use_source_keyed_cache; `value` is what g returns."""
    pkg = root / "kpkg"
    pkg.mkdir(exist_ok=True)
    (pkg / "__init__.py").write_text(     # importing sph_fsi_core keyed the cache to its own sources: undone here
        "import os\n"
        "from pathlib import Path\n"
        "from sph_fsi_core.jit_cache import use_source_keyed_cache\n"
        "if os.environ.pop('KPKG_KEYED', None):\n"
        "    os.environ.pop('NUMBA_CACHE_DIR')\n"
        "    use_source_keyed_cache(Path(__file__).parent)\n")
    (pkg / "callee.py").write_text(f"from numba import njit\n\n\n@njit(cache=True)\ndef g():\n    return {value}\n")
    (pkg / "caller.py").write_text("from numba import njit\n\nfrom .callee import g\n\n\n"
                                   "@njit(cache=True)\ndef f():\n    return g()\n")
    return pkg


def _call_f(root, keyed):
    """f() in a fresh process: with the package's source-keyed cache, or with Numba's own (a fixed NUMBA_CACHE_DIR)."""
    env = dict(os.environ, NUMBA_CACHE_DIR=str(root / "numba_own"))
    if keyed:
        env["KPKG_KEYED"] = "1"
    env["PYTHONPATH"] = os.pathsep.join([str(root), os.environ.get("PYTHONPATH", "")])
    code = "import kpkg.caller as c; print(c.f())"
    out = subprocess.run([sys.executable, "-c", code], env=env, cwd=root, capture_output=True, text=True, timeout=300)
    assert out.returncode == 0, out.stderr
    return int(out.stdout.split()[-1])


def test_an_edited_kernel_never_runs_with_stale_callers(tmp_path):
    """Numba voids a cached kernel only when its own file changes, and a kernel's machine code holds its callees' from
    other files too (numba/numba#6845): after an edit of callee.py alone, Numba's own cache still runs the old g
    inside f (the control; numba is pinned). The source-keyed cache starts afresh after any kernel file's edit."""
    for keyed in (True, False):
        root = tmp_path / ("keyed" if keyed else "own")
        root.mkdir()
        _write_package(root, 1)
        assert _call_f(root, keyed) == 1
        _write_package(root, 2)
        assert _call_f(root, keyed) == (2 if keyed else 1)


def test_the_digest_follows_the_kernel_files_only(tmp_path):
    pkg = _write_package(tmp_path, 1)
    (pkg / "scene.py").write_text("SIZE = 1\n")
    first = jit_cache.source_digest(pkg)
    assert [p.name for p in jit_cache.kernel_sources(pkg)] == ["callee.py", "caller.py"]
    (pkg / "scene.py").write_text("SIZE = 2\n")
    assert jit_cache.source_digest(pkg) == first
    _write_package(tmp_path, 2)
    assert jit_cache.source_digest(pkg) != first
    _write_package(tmp_path, 1)
    assert jit_cache.source_digest(pkg) == first     # back to a version: its own cache again


def test_old_caches_are_pruned_but_not_recent_or_in_use_ones(tmp_path):
    now = time.time()
    ages = {"current": 0, "a": 10, "b": 20, "c": 30, "d": 7200, "e": 9000, "f": 100}   # seconds since last use
    for name, age in ages.items():
        (tmp_path / name).mkdir()
        os.utime(tmp_path / name, (now - age, now - age))
    removed = jit_cache.prune_caches(tmp_path, tmp_path / "current", keep=3, in_use_seconds=3600)
    # the three most recently used others stay, and so does "f" (used 100 s ago: maybe running); d and e go
    assert sorted(p.name for p in removed) == ["d", "e"]
    assert sorted(p.name for p in tmp_path.iterdir()) == ["a", "b", "c", "current", "f"]


def test_importing_the_package_keys_numbas_cache_unless_the_user_set_one(tmp_path):
    code = "import sph_fsi_core, numba.core.config as c; print(c.CACHE_DIR)"
    env = {k: v for k, v in os.environ.items() if k != "NUMBA_CACHE_DIR"}
    out = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True, text=True, timeout=120)
    assert out.returncode == 0, out.stderr
    path = Path(out.stdout.split()[-1])
    assert path.name == jit_cache.source_digest() and path.parent == jit_cache.cache_root()
    env["NUMBA_CACHE_DIR"] = str(tmp_path)
    out = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True, text=True, timeout=120)
    assert out.stdout.split()[-1] == str(tmp_path)
