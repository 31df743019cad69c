"""Snapshots for ParaView: one VTK XML UnstructuredGrid (.vtu) per phase per snapshot, a .pvd time series per
phase, and the fixed particles (walls, and the solid's clamp is in the solid's file) once.

Written by run.py when output.snapshot_format is 'vtk' or 'both', into the snapshots directory:
    solid_00000.vtu, solid_00001.vtu, ...   solid.pvd      (a scene with a solid)
    fluid_00000.vtu, ...                    fluid.pvd      (a scene with water)
    walls.vtu                                              (a scene with walls; written with the first snapshot)
Open a .pvd in ParaView (File > Open, then Apply); the time slider steps through the snapshots. Each particle is
a VTK_VERTEX cell (use the Point Gaussian representation to see them as spheres of the spacing's size).

Point fields, SI units: velocity (m/s), displacement (m, from the particle's initial position), density
(kg/m^3), pressure (Pa); solid only: stress (the full Cauchy stress sigma = S - p I, 9 components, Pa),
von_mises (Pa), movable (1; 0 for the clamp). Binary data, base64 inline, little-endian, UInt32 block headers
(the VTK XML format's `binary` encoding), readable by ParaView/VTK and meshio without VTK installed here.
"""
import base64
from pathlib import Path

import numpy as np

from .numerics.tensors import SYM_INDEX, von_mises

_VTK_TYPES = {np.dtype(np.float64): "Float64", np.dtype(np.float32): "Float32", np.dtype(np.uint8): "UInt8",
              np.dtype(np.int64): "Int64"}
_VTK_VERTEX = 1


def _data_array(name, values):
    values = np.ascontiguousarray(values)
    if values.dtype == np.bool_:
        values = values.astype(np.uint8)
    if values.dtype.byteorder == ">":
        values = values.astype(values.dtype.newbyteorder("<"))
    components = "" if values.ndim == 1 else f' NumberOfComponents="{values.shape[1]}"'   # scalars: VTK's 1
    raw = values.tobytes()
    encoded = base64.b64encode(np.uint32(len(raw)).tobytes() + raw).decode()
    return (f'<DataArray type="{_VTK_TYPES[values.dtype]}" Name="{name}"{components} format="binary">'
            f'{encoded}</DataArray>')


def write_vtu(path, positions, fields):
    """A point cloud as a .vtu: `positions` (N, 3) m, `fields` {name: (N,) or (N, k) array}."""
    n = len(positions)
    point_data = "".join(_data_array(name, values) for name, values in fields.items())
    cells = (_data_array("connectivity", np.arange(n, dtype=np.int64))
             + _data_array("offsets", np.arange(1, n + 1, dtype=np.int64))
             + _data_array("types", np.full(n, _VTK_VERTEX, dtype=np.uint8)))
    text = ('<?xml version="1.0"?>\n'
            '<VTKFile type="UnstructuredGrid" version="1.0" byte_order="LittleEndian" header_type="UInt32">\n'
            f'<UnstructuredGrid><Piece NumberOfPoints="{n}" NumberOfCells="{n}">\n'
            f'<PointData>{point_data}</PointData>\n'
            f'<Points>{_data_array("Points", np.asarray(positions, dtype=np.float64))}</Points>\n'
            f'<Cells>{cells}</Cells>\n'
            '</Piece></UnstructuredGrid>\n</VTKFile>\n')
    Path(path).write_text(text)


def write_pvd(path, entries):
    """The time-series index: entries [(time s, file name relative to the .pvd)]."""
    rows = "".join(f'<DataSet timestep="{t!r}" group="" part="0" file="{name}"/>\n' for t, name in entries)
    Path(path).write_text('<?xml version="1.0"?>\n<VTKFile type="Collection" version="0.1" '
                          f'byte_order="LittleEndian">\n<Collection>\n{rows}</Collection>\n</VTKFile>\n')


def full_stress(deviatoric, pressure):
    """(N, 9) row-major Cauchy stress sigma = S - p I from the (N, 6) deviatoric stress and the pressure."""
    sigma = deviatoric[:, SYM_INDEX.ravel()].copy()
    for d in (0, 4, 8):
        sigma[:, d] -= pressure
    return sigma


def write_vtk_snapshot(sim, directory, index):
    """Snapshot `index` of every phase the scene has, and the .pvd indexes brought up to date."""
    directory = Path(directory)
    phases = []
    if sim.solid is not None:
        s = sim.solid
        write_vtu(directory / f"solid_{index:05d}.vtu", s.pos, {
            "velocity": sim.solid_velocity(), "displacement": s.pos - sim.initial_positions("solid"), "density": s.rho,
            "pressure": s.pressure, "stress": full_stress(s.stress, s.pressure), "von_mises": von_mises(s.stress),
            "movable": s.movable})
        phases.append("solid")
    if sim.fluid is not None:
        f = sim.fluid
        write_vtu(directory / f"fluid_{index:05d}.vtu", f.pos, {
            "velocity": f.vel, "displacement": f.pos - sim.initial_positions("fluid"), "density": f.rho,
            "pressure": f.pressure})
        phases.append("fluid")
    if sim.walls is not None and not (directory / "walls.vtu").exists():
        write_vtu(directory / "walls.vtu", sim.walls.pos, {})
    for phase in phases:
        index_path = directory / f"{phase}.pvd"
        entries = _read_pvd(index_path) if index > 0 and index_path.exists() else []
        entries = [e for e in entries if e[1] != f"{phase}_{index:05d}.vtu"] + [(sim.time, f"{phase}_{index:05d}.vtu")]
        write_pvd(index_path, entries)


def _read_pvd(path):
    import re
    return [(float(t), name) for t, name in re.findall(r'timestep="([^"]+)" group="" part="0" file="([^"]+)"',
                                                       Path(path).read_text())]
