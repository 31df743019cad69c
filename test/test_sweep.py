"""Sweeps and ladders as tasks (sph_fsi_core/validation/tasks.py, sweep.py): a sweep on a local Dask cluster of two
workers gives the same runs, to the bit, as the same sweep run here one after the other, and one table of their
summaries; a bad value is refused before anything runs."""
import csv
import os
import subprocess
import sys

import pytest

from sph_fsi_core.schema import SceneError
from sph_fsi_core.validation.sweep import parse_vary, run_sweep
from sph_fsi_core.validation.tasks import map_runs

VARY = [("solid.young_modulus", [1.5e6, 2.0e6]), ("solid.poisson_ratio", [0.3, 0.45])]
SET = [("geometry.length", 0.02)]
END = 0.002


def _square(x):
    return x * x, os.getpid(), os.environ.get("NUMBA_NUM_THREADS")


def test_map_runs_on_a_local_cluster_keeps_the_order_and_gives_each_worker_its_threads():
    here = map_runs(_square, range(6))
    assert [r[0] for r in here] == [x * x for x in range(6)] and {r[1] for r in here} == {os.getpid()}
    there = map_runs(_square, range(6), workers=2)
    assert [r[0] for r in there] == [x * x for x in range(6)]
    assert os.getpid() not in {r[1] for r in there}                       # ran in the worker processes
    assert {r[2] for r in there} == {str(max(1, (os.cpu_count() or 1) // 2))}


def test_a_sweep_on_dask_equals_the_serial_sweep(tmp_path):
    """The same Numba thread count as each of the two workers (cores / 2): the passes chunk their sums by it."""
    import numba
    saved = numba.get_num_threads()
    numba.set_num_threads(min(saved, max(1, (os.cpu_count() or 1) // 2)))
    try:
        serial = run_sweep("cantilever", VARY, SET, END, tmp_path / "serial", workers=1)
    finally:
        numba.set_num_threads(saved)
    dask = run_sweep("cantilever", VARY, SET, END, tmp_path / "dask", workers=2)
    assert [c for c, _ in serial] == [c for c, _ in dask] and len(serial) == 4
    for (combo, _), label in zip(serial, ("solid.young_modulus=1500000.0,solid.poisson_ratio=0.3",
                                          "solid.young_modulus=1500000.0,solid.poisson_ratio=0.45",
                                          "solid.young_modulus=2000000.0,solid.poisson_ratio=0.3",
                                          "solid.young_modulus=2000000.0,solid.poisson_ratio=0.45")):
        a = (tmp_path / "serial" / "runs" / label / "timeseries.csv").read_bytes()
        b = (tmp_path / "dask" / "runs" / label / "timeseries.csv").read_bytes()
        assert a == b, label
    with open(tmp_path / "dask" / "sweep.csv") as f:
        rows = list(csv.DictReader(f))
    assert [(float(r["solid.young_modulus"]), float(r["solid.poisson_ratio"])) for r in rows] == \
        [(1.5e6, 0.3), (1.5e6, 0.45), (2.0e6, 0.3), (2.0e6, 0.45)]
    assert all(r["status"] == "finished" and r["stable"] == "True" for r in rows)
    assert [float(r["simulated_time_s"]) for r in rows] == pytest.approx([END] * 4)
    # a stiffer beam takes more solid steps (its sound speed sets the step)
    steps = [int(r["solid_steps"]) for r in rows]
    assert steps[2] > steps[0] and steps[3] > steps[1]


def test_bad_values_are_refused_before_anything_runs(tmp_path):
    with pytest.raises(SceneError, match="expected KEY=V1,V2"):
        parse_vary("solid.young_modulus")
    with pytest.raises(SceneError, match="solid.poisson_ratio"):
        run_sweep("cantilever", [("solid.poisson_ratio", [0.3, 0.7])], SET, END, tmp_path / "bad")
    assert not (tmp_path / "bad").exists()
    r = subprocess.run([sys.executable, "-m", "sph_fsi.cli", "sweep", "cantilever", "--vary",
                        "solid.young_modulus=1e6,-1", "--out", str(tmp_path / "cli")], capture_output=True,
                       text=True, timeout=120)
    assert r.returncode == 2 and "solid.young_modulus = -1" in r.stderr, r.stderr
    assert not (tmp_path / "cli").exists()
