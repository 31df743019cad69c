"""The study's experiment with a disordered start (docs/validation/studies/water_lattice/REPORT.md, "Reading it"):
the standing wave of config/standing_wave.yaml with each water particle moved at random by up to JITTER spacings
(uniform on each axis, seed 1) before a settling of 1 s, then the wave's velocity field laid on it at t = 0 as the
scene does. No scene key does this (the settling is monkeypatched here); it prints the two antinodes' frequency
error and loss per period (the scene's judges) and the level's drift over the run.

    python docs/validation/studies/water_lattice/jittered_start.py [JITTER [--shift A] [KEY=VALUE ...]]
    (e.g. 0.1 numerics.smoothing_ratio=1.5 geometry.span_layers=7; about 5 minutes on 2 threads)

With --shift A the water is shifted after every fluid step, its settling included (particle_shifting.py, with its
free-surface band; about 13 minutes).
"""
import sys
import tempfile

import numpy as np
from particle_shifting import install

from sph_fsi_core.fluid import phase
from sph_fsi_core.run import run_scene
from sph_fsi_core.scene import load_scene

JITTER = float(sys.argv[1]) if len(sys.argv) > 1 else 0.1
KEYS = sys.argv[2:]
SHIFT = 0.0
if KEYS[:1] == ["--shift"]:
    SHIFT, KEYS = float(KEYS[1]), KEYS[2:]
_settle = phase.FluidPhase.settle


def jittered_settle(self, duration, follow_solid):
    spacing = self.values["numerics.spacing"]
    self.fluid.pos[:] += JITTER * spacing * np.random.default_rng(1).uniform(-1.0, 1.0, self.fluid.pos.shape)
    self.solver.rebuild()
    return _settle(self, duration, follow_solid)


phase.FluidPhase.settle = jittered_settle
spec = load_scene("config/standing_wave.yaml", ["fluid.settle_time=1.0", "output.snapshot_interval=0"] + KEYS)
install(SHIFT, spec.values["numerics.spacing"], free_surface=True)
with tempfile.TemporaryDirectory() as out:
    summary = run_scene(spec, out_dir=out)
    series = np.genfromtxt(f"{out}/timeseries.csv", delimiter=",", names=True)
level = 0.5 * (series["antinode_0"] + series["antinode_half"])
drift = level[series["time"] >= series["time"][-1] - 0.5].mean() - level[0]
j = summary["judges"]
print(f"jitter {JITTER:g} dp, shift {SHIFT:g}, {' '.join(KEYS) or 'the defaults'}: frequency "
      f"{100 * j['period']['error_signed']:+.2f} / {100 * j['period_half']['error_signed']:+.2f} %, loss "
      f"{100 * j['loss']['measured']:.1f} / {100 * j['loss_half']['measured']:.1f} % a period, level "
      f"{1e3 * drift:+.2f} mm; settled with {summary['settling']['residual_max_speed_m_s']:.3f} m/s left")
