"""Suite-wide order: the longest files first, so that `make test`'s two pytest-xdist workers (one file each at a
time, --dist loadfile) end together instead of one waiting on a long file handed out last. And the `slow` marker:
tests over ~10 s on one thread (coarse validation runs, long physics runs, node tests that run long simulations),
which `make test-fast` leaves out (`-m "not slow"`) and `make test` runs."""
import pytest

# the files that take about a minute or more on one thread (pytest --durations), longest first
LONG_FILES = ("test_artificial_stress.py", "test_implicit_pressure.py", "validation/test_stability_ci.py",
              "test_pair_blocks.py", "test_fluid.py", "validation/test_cantilever_quick.py",
              "validation/test_solid_static_quick.py", "validation/test_hydrostatic_plate_quick.py",
              "test_gradient_integration.py", "node/test_node.py", "test_runner.py")


def _rank(item):
    path = item.nodeid.split("::")[0]
    for rank, name in enumerate(LONG_FILES):
        if path.endswith(name):
            return rank
    return len(LONG_FILES)


def pytest_configure(config):
    config.addinivalue_line("markers", "slow: over ~10 s on one thread; left out of `make test-fast`")


def pytest_collection_modifyitems(items):
    items.sort(key=_rank)   # stable: the order within a file and among the rest is kept


def pytest_sessionstart(session):
    """On-demand FE references (references.fe3d_frequency) go to a cache of the test session's own, not the
    user's: a test sees the committed tables and what it computes itself."""
    import os
    import tempfile
    os.environ["SPH_FSI_CACHE"] = tempfile.mkdtemp(prefix="sph_fsi_test_cache_")


@pytest.fixture(scope="module")
def one_numba_thread():
    """A module's simulations on one Numba thread (the node's NUMBA_NUM_THREADS=1), then the count back for the tests
    after it: numba's thread count is the calling thread's, and a runner's thread would not share it
    (`pytestmark = pytest.mark.usefixtures("one_numba_thread")`)."""
    import numba
    saved = numba.get_num_threads()
    numba.set_num_threads(1)
    yield
    numba.set_num_threads(saved)
