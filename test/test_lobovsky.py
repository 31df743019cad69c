"""The Lobovsky et al. 2014 scene: its release options (the gate gone at t = 0, or lifted at the measured speed)
and its judgement against the experiment's front (reference_data/lobovsky2014_front_H600.csv)."""
from pathlib import Path

import numpy as np
import pytest

from sph_fsi_core.scene import load_scene
from sph_fsi_core.scenes.cases import lobovsky_dam_break as lob
from sph_fsi_core.simulation import Simulation
from sph_fsi_core.answers.references import lobovsky_front

COARSE = ["numerics.spacing=0.04", "fluid.settle_time=0"]     # H / 15, from zero pressure: a quick build


def test_the_lifted_gate_moves_at_its_speed_and_stops_clear_of_the_water():
    spec = load_scene("lobovsky_dam_break", COARSE + ["geometry.release=lifted", "output.timeseries_interval=0.01"])
    sim = Simulation(spec)
    walls = sim.walls.count
    gate0 = sim.fluid_phase.solver.wall_pos[walls:].copy()
    assert len(gate0) == 3 * 6 * 18                               # 3 layers, 6 across, 0.7 m high
    assert np.allclose(gate0[:, 0].min(), 15 * 0.04 + 0.02)                  # at the column's face
    sim.step()
    lifted = sim.fluid_phase.solver.wall_pos[walls:] - gate0
    assert np.allclose(lifted[:, :2], 0.0) and np.allclose(lifted[:, 2], 4.53 * 0.01)   # the last step's end
    travel = spec["geometry.travel"]                            # the file's derived quantity
    assert travel == pytest.approx(0.6 + 2 * 1.3 * 0.04)
    while sim.time < 0.2 - 1e-12:
        sim.step()
    assert np.allclose(sim.fluid_phase.solver.wall_pos[walls:, 2] - gate0[:, 2], travel)    # parked, clear of the water
    assert sim.fluid_phase.solver.wall_pos[walls:, 2].max() < sim.domain_hi[2]               # inside the lists' box
    assert sim.sample()["outside_walls"] == 0


def test_the_instant_release_has_no_gate_and_the_front_starts_at_the_gate():
    sim = Simulation(load_scene("lobovsky_dam_break", COARSE + ["geometry.release=instant"]))
    assert sim.fluid_phase.solver.walls.count == sim.walls.count
    s = sim.sample()
    assert s["front_x"] == 0.0 and s["front_Z"] == 1.0 and s["T"] == 0.0


def test_evaluate_against_the_experiment_itself():
    """Fed the experiment's own curve the judgement is exact: zero error, zero shift, its own speed (1.339, the
    paper's 1.34); a curve shifted by dT = 0.1 is found shifted by 0.1 and fits to rounding after it."""
    t, z = lobovsky_front()
    own = lob.evaluate({"T": t, "front_Z": z, "outside_walls": np.zeros(len(t))}, {"geometry.release": "lifted"})
    assert own["front_rms_relative_error"] == 0.0 and own["front_time_shift_T"] == 0.0
    assert own["front_speed_dZdT"] == pytest.approx(own["front_speed_dZdT_experiment"])
    assert own["front_speed_dZdT_experiment"] == pytest.approx(1.339, abs=0.001)
    judged = [p["T"] for p in own["front_points"]]
    assert min(judged) >= 1.0 and len(judged) == int(((t >= 1.0) & (np.arange(len(t)) < len(t) - 3)).sum())
    early = lob.evaluate({"T": t - 0.1, "front_Z": z, "outside_walls": np.zeros(len(t))},
                         {"geometry.release": "instant"})
    assert early["front_time_shift_T"] == pytest.approx(0.1, abs=0.002)
    assert early["front_rms_relative_error"] > 0.03 and early["front_rms_after_time_shift"] < 0.005


def test_the_other_experiment_of_the_square_column_judged_as_the_simulation_is():
    """Martin & Moyce 1952's square column (n^2 = 1, a tenth of Lobovsky's size; test/data/
    martin_moyce_1952_front_n1.csv, a third-party extraction, not in the project's reference set) through the scene's own judgement against Lobovsky's: RMS 7.1 %, late by dT =
    0.116 (0.54 % after it), and 6.0 % faster on T in [1, 1.6] (1.419 from its 3 points there). The two experiments
    of this column differ by more than the issue's goals (RMS 5 %, |dT| 0.06, speed 3 %): docs/validation/OPEN.md,
    3.1."""
    lines = (Path(__file__).parent / "data" / "martin_moyce_1952_front_n1.csv").read_text().splitlines()
    assert [ln for ln in lines if not ln.startswith("#")][0] == "T,Z"   # T = t sqrt(g / a), Z = x / a: Lobovsky's
    t, z = np.loadtxt([ln for ln in lines if ln[:1].isdigit()], delimiter=",", unpack=True)
    steps = np.diff(z)   # Z in steps of 2/9, 1/9 at the ends
    assert len(t) == 20 and np.all(np.diff(t) > 0)
    assert np.all(np.minimum(abs(steps - 1 / 9), abs(steps - 2 / 9)) < 0.011)
    other = lob.evaluate({"T": t, "front_Z": z, "outside_walls": np.zeros(len(t))}, {"geometry.release": "lifted"})
    assert other["front_rms_relative_error"] == pytest.approx(0.0714, abs=0.001)
    assert other["front_time_shift_T"] == pytest.approx(-0.116, abs=0.002)
    assert other["front_rms_after_time_shift"] == pytest.approx(0.0054, abs=0.0003)
    assert other["front_speed_dZdT"] == pytest.approx(1.419, abs=0.001)
    assert other["front_speed_error"] == pytest.approx(0.0596, abs=0.001)


def test_the_command_line_says_the_water_settles_and_what_the_settling_did(capsys, tmp_path):
    from sph_fsi.cli import main
    assert main(["run", "lobovsky_dam_break", "--set", "numerics.spacing=0.04", "--end-time", "0.02",
                 "--out", str(tmp_path)]) == 0
    out, err = capsys.readouterr()
    assert "the water first settles at rest for fluid.settle_time = 0.3 s before t = 0" in err
    settled = [line for line in out.splitlines() if line.startswith("settled: 0.3 s of water at rest")]
    assert len(settled) == 1 and "0 capped" in settled[0], out
