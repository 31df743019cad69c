"""Antoci's gate's summary metrics on synthetic free-end curves with exact answers (no simulation)."""
import numpy as np
import pytest

from sph_fsi_core.scene import load_scene
from sph_fsi_core.scenes.cases.antoci_gate import PEAK_SMOOTHING_S, evaluate, window_mean


def test_window_mean_keeps_a_line_and_removes_a_wobble_of_the_windows_period():
    """Samples every 2 ms, a 10 ms window: five samples a whole period apart, so a sine of that period sums to zero
    and a straight line is its own mean; at the ends the window is cut and the mean shifts along the line."""
    t = np.arange(0.0, 0.2 + 1e-12, 0.002)
    line = 0.01 + 0.3 * t
    wobble = 0.002 * np.sin(2.0 * np.pi * t / 0.010 + 0.3)
    mean = window_mean(t, line + wobble, 0.010)
    inside = (t >= 0.004 + 1e-12) & (t <= t[-1] - 0.004 - 1e-12)
    np.testing.assert_allclose(mean[inside], line[inside], rtol=0, atol=1e-14)
    assert mean[0] == pytest.approx(np.mean((line + wobble)[:3]), abs=1e-15)   # t = 0, 2, 4 ms


def test_the_smoothed_peak_is_the_motions_peak_without_its_ringing():
    """A broad bump (46 mm at 0.15 s) with a 1.5 mm, 10 ms ringing: the raw peak carries the ringing, the smoothed
    one is the bump's within its curvature over the window (a parabola's window mean lies below its top by
    c w^2 / 12 for the samples' variance 8e-6 s^2 here)."""
    t = np.arange(0.0, 0.4 + 1e-12, 0.002)
    curvature = 4.0                                           # m/s^2: 1.8 mm below the top 30 ms away
    bump = 0.046 - 0.5 * curvature * (t - 0.15) ** 2
    ring = 0.0015 * np.sin(2.0 * np.pi * t / PEAK_SMOOTHING_S)
    series = {"time": t, "tip_dx": bump + ring, "tip_dz": np.zeros_like(t)}
    out = evaluate(series, load_scene("antoci_gate").values)
    assert out["tip_x_peak_m"] == pytest.approx(0.046 + 0.0015, abs=1e-4)
    variance = np.mean((np.arange(-2, 3) * 0.002) ** 2)      # the five samples' spread about their centre
    assert out["tip_x_peak_smoothed_m"] == pytest.approx(0.046 - 0.5 * curvature * variance, abs=1e-12)
    assert out["tip_x_peak_smoothed_time_s"] == pytest.approx(0.15, abs=1e-9)


def test_the_load_against_the_level_behind_the_gate():
    """A column that loses 30 % of its water: the level is 0.7 H0 over the reservoir; the hydrostatic load of a level
    above the gate's free length is rho g W L (H - c - L / 2) (c: the clearance under it); a push of 0.8 of it
    reads 0.8."""
    from sph_fsi_core.scenes.cases import gate
    values = load_scene("antoci_gate").values
    geometry = gate.effective_geometry(values)
    length, width, clearance = geometry["gate_free_length_m"], geometry["span_m"], geometry["gate_clearance_m"]
    level = 0.7 * gate.water_surface_z(values)
    assert level > clearance + length                        # 98 mm above a gate reaching 81.5 mm
    exact = 1000.0 * 9.81 * width * length * (level - clearance - 0.5 * length)
    assert gate.hydrostatic_gate_load(level, values) == pytest.approx(exact, rel=1e-12)
    assert gate.hydrostatic_gate_load(0.5 * clearance, values) == 0.0   # below the gate: no load on it
    t = np.arange(0.0, 0.4 + 1e-12, 0.002)
    push = 1.0 if values["geometry.mirror"] else -1.0
    series = {"time": t, "tip_dx": 0.04 - (t - 0.12) ** 2, "tip_dz": np.zeros_like(t),
              "water_past_gate": np.full_like(t, 0.3), "coupling_force_x": np.full_like(t, 0.8 * push * exact)}
    out = evaluate(series, values)
    assert out["water_level_at_x_peak_m"] == pytest.approx(level, rel=1e-12)
    assert out["water_load_over_hydrostatic_at_x_peak"] == pytest.approx(0.8, rel=1e-12)


def test_the_water_levels_of_antocis_gate_read_its_column_at_rest():
    """config/antoci_gate.yaml's level probes at t = 0: the column's height (whole layers of its 0.14 m) at the back
    wall and behind the gate, within a quarter spacing (the surface where the water stops filling half a kernel)."""
    from sph_fsi_core.scenes.cases import gate
    from sph_fsi_core.simulation import Simulation
    spec = load_scene("antoci_gate", ["numerics.spacing=0.0025", "solid.scheme=gray2001"])
    readings = Simulation(spec).probe_readings()
    surface = gate.water_surface_z(spec.values)
    for name in ("level_back", "level_gate"):
        kind, values = readings[name]
        assert kind == "water_height"
        assert values["height"] == pytest.approx(surface, abs=0.25 * 0.0025), name
    assert readings["level_back"][1]["surface"][0] == pytest.approx(-(0.005 + 0.1 - 0.01))    # the water on -x
    assert readings["level_gate"][1]["surface"][0] == pytest.approx(-(0.005 + 0.01))


def test_antocis_gate_in_the_experiments_tank_is_closed_by_side_walls_and_is_the_slab_across_y():
    """config/antoci_gate.yaml with geometry.periodic_y: false and span: 0.1 (the antoci_tank study): no period, side
    walls of wall_layers layers just outside the water's and the gate's 0.1 m across, and in every y layer the slab's
    own arrangement in x and z (the same gate, water and floor, only repeated across)."""
    from sph_fsi_core.simulation import Simulation
    dp = 0.0025
    common = ["numerics.spacing=0.0025", "solid.scheme=gray2001"]
    slab = Simulation(load_scene("antoci_gate", common))
    tank = Simulation(load_scene("antoci_gate", common + ["geometry.periodic_y=false", "geometry.span=0.1"]))
    layers = round(0.1 / dp)
    assert slab.period[1] > 0.0 and not np.any(tank.period)
    for phase in ("fluid", "solid"):
        y = getattr(tank, phase).pos[:, 1]
        assert y.min() == pytest.approx(dp / 2) and y.max() == pytest.approx(0.1 - dp / 2)
        assert getattr(tank, phase).count == getattr(slab, phase).count * layers // slab.spec["geometry.ny"]
    wy = tank.walls.pos[:, 1]
    assert wy.min() == pytest.approx(-2.5 * dp) and wy.max() == pytest.approx(0.1 + 2.5 * dp)
    inside = tank.walls.pos[(wy > 0) & (wy < dp)]          # the first layer across: the slab's floor and end walls
    first = slab.walls.pos[slab.walls.pos[:, 1] < dp]
    assert {tuple(np.round(p[[0, 2]], 9)) for p in first} <= {tuple(np.round(p[[0, 2]], 9)) for p in inside}


def test_the_stiffness_study_scales_the_peaks_time_as_a_gate_alone_would(tmp_path):
    """The study's table (validation/cases/antoci_stiffness.py) on stored runs of known curves: each peak and its
    time read back, and the published material's time moved by sqrt(12 MPa / E) for the softer gates."""
    import csv
    import json
    from sph_fsi_core.validation.cases import antoci_stiffness
    rungs = antoci_stiffness.rungs()
    summaries = {}
    t = np.arange(0.0, 0.3 + 1e-12, 0.002)
    for k, r in enumerate(rungs):
        e = r.overrides.get("solid.young_modulus", 12.0e6)
        when, peak = 0.110 + 0.01 * k, 0.035 + 0.002 * k
        folder = tmp_path / "runs" / r.case / r.label
        folder.mkdir(parents=True)
        with (folder / "timeseries.csv").open("w", newline="") as fh:
            w = csv.writer(fh)
            w.writerow(["time", "tip_dx", "level_back", "level_gate"])
            for ti in t:
                w.writerow([ti, peak - 2.0 * (ti - when) ** 2, 0.14 - 0.1 * ti, 0.13 - 0.2 * ti])
        summaries[r.key] = {"settings": {"solid.young_modulus": e}, "wall_time_s": 1.0,
                            "geometry_effective": {"gate_free_length_m": 0.07875}}
        (folder / "summary.json").write_text(json.dumps(summaries[r.key]))
    lines = antoci_stiffness.table(tmp_path, rungs, summaries)
    rows = [ln.split(" | ") for ln in lines if ln.startswith("| E")]
    assert [row[0].lstrip("| ") for row in rows] == [r.label for r in rungs]
    assert [float(row[3]) for row in rows] == pytest.approx([35.0, 37.0, 39.0, 41.0])
    assert [float(row[4]) for row in rows] == pytest.approx([0.110, 0.120, 0.130, 0.140])
    scaled = [float(row[5]) for row in rows]
    assert scaled == pytest.approx([0.110, 0.110 * (12 / 8.4) ** 0.5, 0.110 * 2 ** 0.5, 0.110], abs=1e-3)
    level_gate = [float(row[7]) for row in rows]
    assert level_gate == pytest.approx([1e3 * (0.13 - 0.2 * w) for w in (0.110, 0.120, 0.130, 0.140)], abs=0.05)
