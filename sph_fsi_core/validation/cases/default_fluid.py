"""The water alone, against exact answers and experiments: the default suite's fluid cases (SPHERIC test 2, the 3D
one, has its own module, spheric2.py).

    tank          water at rest in a tank, H / dp 20 and 40: the floor pressure against rho g H
    rest_pressure the same tank stepped at 0.5 ms, the step a coupled run takes (one sample per fluid step): the
                  end-wall probe's swing from step to step over rho g H, its mean against rho g (H - z) beside
    martin_moyce  Martin & Moyce's collapsing column, a / dp 10, 20, 30: the surge front's RMS relative difference
                  from the measured one over T <= 3 (reference_data/martin_moyce_1952_a57mm.csv)
    lobovsky      Lobovsky et al. 2014's 600 mm column, H / dp 30, 60, 90, the scene's defaults (the gate lifted at
                  the measured speed, the water settled behind it): the front against the measured median, T >= 1
    box_push      a box pushed into water at rest (a wall that moves: parts.box.motion), 10 mm: the level's rise
                  against the volume it displaces (config/box_pushed_into_tank.yaml)
    impulse_balance  a box moved through still water and stopped, 10 mm (config/box_moved_through_water.yaml): the
                  water's change of x momentum against minus the x impulse of its force on the box and the floor
    standing_wave a small standing wave in a periodic slab, d / dp 20 and 40 (config/standing_wave.yaml): its period
                  at an antinode (as a frequency) against linear theory's omega^2 = g k tanh(k d) over five periods
    standing_wave_loss  the same runs: the fraction of its amplitude lost per period (none in linear theory)
    sliding_water water sliding as one at 0.04 m/s along a free-slip floor, d / dp 20 and 40
                  (config/sliding_water.yaml): its mean velocity over the last half of 0.5 s against the start's
    jet_on_wall   a plane jet on a wall without gravity, b / dp 10, 20 and 40 (config/jet_on_wall.yaml): the wall's
                  force over the steady window against the jet's momentum flux rho U^2 b per span
    jet_pressure  the same runs: the pressure on the jet's axis 1.5 h from the wall against free-streamline theory's
                  (answers/impinging_jet.py)
    jet_swing     the same runs: that pressure's swing from sample to sample (about one fluid step) over 1/2 rho U^2

Each rung runs the scene's defaults but for the spacing (and the tank's step at its finer rung, as the fluid's step
must shrink with dp there: docs/method.md).
"""
from ..rung import Rung

SECTION = "## The water alone"
TANK_DEPTH = 0.1                 # m (config/hydrostatic.yaml)
COLUMN_WIDTH = 0.05715           # m, a (config/dam_break.yaml)
LOBOVSKY_HEIGHT = 0.6            # m, H (config/lobovsky_dam_break.yaml)
BOX_RISE = 0.05                  # m, the level's rise (config/box_pushed_into_tank.yaml's geometry.rise)
WAVE_DEPTH = 0.1                 # m, d (config/standing_wave.yaml)
WAVE_END = 3.7                   # s: five periods of linear theory's 0.73 s
SLIDE_DEPTH = 0.1                # m, d (config/sliding_water.yaml)
JET_WIDTH = 0.05                 # m, b (config/jet_on_wall.yaml)
# s: the water at rest stepped as in a coupled run (the coupled rungs' fluid steps: Antoci's gate 0.11-0.2 ms, the
# paper's 0.25 ms, Antoci's gate at rest 1 ms), where gravity's g dt^2 per step is well inside the tolerance
REST_STEP = 0.0005

MEASURES = {
    "tank": ("floor pressure, settled", "rho g H (exact)"),
    "rest_pressure": ("end-wall pressure's swing from fluid step to fluid step, settled", "rho g H (its scale)"),
    "martin_moyce": ("surge front, RMS over T <= 3", "Martin & Moyce 1952 "
                                                     "(reference_data/martin_moyce_1952_a57mm.csv)"),
    "lobovsky": ("surge front, RMS over T >= 1", "Lobovsky et al. 2014, median of 100 repeats "
                                                 "(reference_data/lobovsky2014_front_H600.csv)"),
    "box_push": ("level's rise, a box pushed in", "the volume it displaces (exact)"),
    "impulse_balance": ("the water's x momentum, a box moved through it and stopped: the largest imbalance",
                        "minus the walls' x impulse (Newton's third law, exact)"),
    "standing_wave": ("a standing wave's frequency (1 / period) at an antinode, five periods",
                      "linear theory, omega^2 = g k tanh(k d), k d = 1 (exact for a small wave)"),
    "standing_wave_loss": ("the same wave's amplitude lost per period", "linear theory: none (the viscosity's "
                                                                          "1.5e-4 aside)"),
    "sliding_water": ("water sliding along a free-slip floor at 0.04 m/s: its mean velocity, 0.25-0.5 s",
                      "the start's (exact: nothing takes its momentum along the floor)"),
    "jet_on_wall": ("a plane jet's force on a wall, steady (0.15-0.4 s)",
                    "its momentum flux rho U^2 b (exact; answers/impinging_jet.py)"),
    "jet_pressure": ("the same jet's pressure on its axis 1.5 h from the wall, steady",
                     "free-streamline theory, 1/2 rho U^2 (1 - q^2) (exact; answers/impinging_jet.py)"),
    "jet_swing": ("that pressure's swing from sample to sample (0.5 ms, about a fluid step), steady",
                  "1/2 rho U^2 (its scale)"),
}


def rungs():
    out = [Rung("tank", f"H_over_dp_{round(TANK_DEPTH / dp)}", "hydrostatic", {"numerics.spacing": dp, **extra},
                end_time=0.6, resolution=f"H/dp {round(TANK_DEPTH / dp)}", quick=not extra, bound=0.02,
                note=f"dp = {dp * 1e3:g} mm; floor pressure against rho g H")
           for dp, extra in ((0.005, {}), (0.0025, {"fluid.time_step": 0.0025}))]
    out += [Rung("rest_pressure", f"H_over_dp_{round(TANK_DEPTH / dp)}", "hydrostatic",
                 {"numerics.spacing": dp, "fluid.time_step": REST_STEP, "output.timeseries_interval": REST_STEP,
                  "geometry.pressure_probes": True},
                 end_time=1.0, resolution=f"H/dp {round(TANK_DEPTH / dp)}", judge="wall_swing",
                 note=f"dp = {dp * 1e3:g} mm, a fluid step of {REST_STEP * 1e3:g} ms; the end-wall probe's swing")
            for dp in (0.005, 0.0025)]
    out += [Rung("martin_moyce", f"a_over_dp_{n}", "dam_break", {"numerics.spacing": COLUMN_WIDTH / n},
                 end_time=0.17, resolution=f"a/dp {n}", quick=n == 10, bound=0.15,
                 note=f"a / dp = {n}; front against Martin & Moyce")
            for n in (10, 20, 30)]
    out += [Rung("lobovsky", f"H_over_dp_{n}", "lobovsky_dam_break", {"numerics.spacing": LOBOVSKY_HEIGHT / n},
                 end_time=0.4, resolution=f"H/dp {n}", quick=n == 30, bound=0.05,
                 note=f"H / dp = {n}; front against Lobovsky et al.")
            for n in (30, 60, 90)]
    out += [Rung("box_push", "dp_10mm", "box_pushed_into_tank", {"numerics.spacing": 0.01}, end_time=5.0,
                 resolution=f"rise/dp {round(BOX_RISE / 0.01)}", bound=0.01,
                 note="dp = 10 mm; the level's mean rise over the last 1.5 s against b (d - z_b) / (L - b)")]
    out += [Rung("impulse_balance", "dp_10mm", "box_moved_through_water", {"numerics.spacing": 0.01}, end_time=0.6,
                 resolution="d/dp 10", bound=0.06,
                 note="dp = 10 mm; the water's x momentum against the box's and the floor's x impulse, every 5 ms")]
    out += [Rung(case, f"d_over_dp_{n}", "standing_wave", {"numerics.spacing": WAVE_DEPTH / n}, end_time=WAVE_END,
                 resolution=f"d/dp {n}", judge=judge, note=f"d / dp = {n}; {what} at the antinode x = 0")
            for case, judge, what in (("standing_wave", "period", "the period"),
                                      ("standing_wave_loss", "loss", "the amplitude lost per period"))
            for n in (20, 40)]
    out += [Rung("sliding_water", f"d_over_dp_{n}", "sliding_water", {"numerics.spacing": SLIDE_DEPTH / n},
                 end_time=0.5, resolution=f"d/dp {n}", judge="speed",
                 note=f"d / dp = {n}; the water's mean velocity along the floor against the start's")
            for n in (20, 40)]
    out += [Rung(case, f"b_over_dp_{n}", "jet_on_wall", {"numerics.spacing": JET_WIDTH / n}, end_time=0.45,
                 resolution=f"b/dp {n}", judge=judge, note=f"b / dp = {n}; {what}")
            for case, judge, what in (("jet_on_wall", "force", "the wall's force"),
                                      ("jet_pressure", "axis_pressure", "the pressure on the axis"),
                                      ("jet_swing", "axis_swing", "that pressure's swing"))
            for n in (10, 20, 40)]
    return out
