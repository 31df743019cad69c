"""ParaView snapshots (output.snapshot_format: vtk / both; sph_fsi_core/vtk_snapshots.py), read back by an
independent reader (meshio) and checked against the NumPy snapshots of the same run: every point and field, the
.pvd time series, the walls once."""
import re

import meshio
import numpy as np
import pytest

from sph_fsi_core.numerics.tensors import von_mises
from sph_fsi_core.run import run_scene
from sph_fsi_core.scene import load_scene


@pytest.fixture(scope="module")
def gate_run(tmp_path_factory):
    out = tmp_path_factory.mktemp("vtk")
    spec = load_scene("elastic_gate", ["numerics.spacing=0.002", "solid.scheme=gray2001",
                                       "output.snapshot_format=both", "output.snapshot_interval=0.001",
                                       "output.timeseries_interval=0.0005"])
    summary = run_scene(spec, out, end_time=0.002, progress=False)
    assert summary["stable"]
    return out / "snapshots"


def _pvd(path):
    return [(float(t), f) for t, f in re.findall(r'timestep="([^"]+)" group="" part="0" file="([^"]+)"',
                                                 path.read_text())]


def test_each_phase_has_a_time_series_of_vtu_files(gate_run):
    npz = sorted(gate_run.glob("snapshot_*.npz"))
    assert len(npz) == 3                      # t = 0, 0.001 and the final state at 0.002
    for phase in ("solid", "fluid"):
        entries = _pvd(gate_run / f"{phase}.pvd")
        assert [f for _, f in entries] == [f"{phase}_{i:05d}.vtu" for i in range(len(npz))]
        times = [float(np.load(p)["time"]) for p in npz]
        assert [t for t, _ in entries] == times
        assert all((gate_run / f).exists() for _, f in entries)
    assert (gate_run / "walls.vtu").exists() and not (gate_run / "walls.pvd").exists()


@pytest.mark.parametrize("index", [0, 2])
def test_fields_equal_the_numpy_snapshot(gate_run, index):
    ref = np.load(gate_run / f"snapshot_{index:05d}.npz")
    first = np.load(gate_run / "snapshot_00000.npz")
    solid = meshio.read(gate_run / f"solid_{index:05d}.vtu")
    assert solid.cells[0].type == "vertex" and len(solid.cells[0].data) == len(ref["solid_position"])
    np.testing.assert_array_equal(solid.points, ref["solid_position"])
    d = solid.point_data
    np.testing.assert_array_equal(d["velocity"], ref["solid_velocity"])
    np.testing.assert_array_equal(d["density"], ref["solid_density"])
    np.testing.assert_array_equal(d["pressure"], ref["solid_pressure"])
    np.testing.assert_array_equal(d["displacement"], ref["solid_position"] - first["solid_position"])
    np.testing.assert_array_equal(d["movable"].astype(bool), ref["solid_movable"])
    sigma = d["stress"].reshape(-1, 3, 3)
    dev, p = ref["solid_stress_deviatoric"], ref["solid_pressure"]
    np.testing.assert_array_equal(sigma, np.transpose(sigma, (0, 2, 1)))            # symmetric
    np.testing.assert_array_equal(sigma[:, 2, 2], ref["solid_sigma_zz"])             # the paper's sigma^22
    np.testing.assert_array_equal(sigma[:, 0, 1], dev[:, 3])                         # xy
    np.testing.assert_allclose(np.trace(sigma, axis1=1, axis2=2), dev[:, :3].sum(axis=1) - 3 * p, rtol=1e-12,
                               atol=1e-9 * (np.abs(p).max() + 1.0))
    np.testing.assert_array_equal(d["von_mises"], von_mises(dev))
    if index:
        assert np.abs(d["displacement"]).max() > 0.0 and np.abs(d["von_mises"]).max() > 0.0
    fluid = meshio.read(gate_run / f"fluid_{index:05d}.vtu")
    np.testing.assert_array_equal(fluid.points, ref["fluid_position"])
    for name, key in (("velocity", "fluid_velocity"), ("density", "fluid_density"), ("pressure", "fluid_pressure")):
        np.testing.assert_array_equal(fluid.point_data[name], ref[key])
    np.testing.assert_array_equal(fluid.point_data["displacement"], ref["fluid_position"] - first["fluid_position"])


def test_walls_once(gate_run):
    walls = meshio.read(gate_run / "walls.vtu")
    np.testing.assert_array_equal(walls.points, np.load(gate_run / "snapshot_00000.npz")["wall_position"])
