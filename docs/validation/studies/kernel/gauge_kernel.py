"""The study's check on its water-height gauges: is what moves SPHERIC's H2 with Wendland's kernel the flow, or the
gauge? A water-height probe finds the surface where the water and the walls stop filling the kernel
(probes.surface_height), with the water's kernel and h, so at h / dp 2 a gauge reads the level smoothed over 4 dp
(0.11 m at SPHERIC's coarse rung) instead of 2.6 dp. This runs a scene with its gauges read by the cubic spline at
h = 1.3 dp whatever the water's kernel and h (the pressure probes and the water itself as the scene says), and prints
the judges' measures:

    python docs/validation/studies/kernel/gauge_kernel.py OUT_DIR SCENE [KEY=VALUE ...]
    (e.g. /tmp/g spheric2_dam_break numerics.spacing=0.0275 fluid.kernel=wendland_c2 numerics.smoothing_ratio=2.0;
    12-13 minutes on 2 threads)
"""
import json
import sys

import sph_fsi_core.probes as probes
from sph_fsi_core.numerics.kernels import CUBIC_SPLINE
from sph_fsi_core.run import run_scene
from sph_fsi_core.scene import load_scene

GAUGE_RATIO = 1.3   # h / dp of the gauges' kernel: the default's

out_dir, scene, overrides = sys.argv[1], sys.argv[2], sys.argv[3:]
spec = load_scene(scene, overrides + ["output.snapshot_interval=0"])
spacing = spec.values["numerics.spacing"]
water_height = probes.surface_height


def spline_gauge(x, y, z0, water_pos, water_volume, wall_pos, wall_volume, h, kernel, step):
    """probes.surface_height with the cubic spline at h = GAUGE_RATIO dp in place of the water's kernel and h."""
    return water_height(x, y, z0, water_pos, water_volume, wall_pos, wall_volume, GAUGE_RATIO * spacing,
                        CUBIC_SPLINE, step)


probes.surface_height = spline_gauge
summary = run_scene(spec, out_dir, progress=False)
for name, judge in summary.get("judges", {}).items():
    print(name, json.dumps({k: v for k, v in judge.items() if isinstance(v, (int, float)) and not isinstance(v, bool)}))
