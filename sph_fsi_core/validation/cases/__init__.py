"""What `sph-fsi validate` runs and reports, a module per case (or per family of cases that share a table): each has

    rungs()                                   its rungs (validation/rung.py), in the order they are reported
    table(out_dir, rungs, summaries)          optional: its section of REPORT.md, as lines ([] when nothing is run)
    plot(out_dir, rungs, summaries, plt)      optional: its PNGs written into out_dir, their file names

table and plot see every reported rung and pick their own (the gates' by scene, across cases). A run is judged by
its scene's evaluate (scenes/*.py), which run_scene calls; running the rungs is ladder.py's, the page report.py's.
"""
from . import (antoci_stiffness, cantilever, cantilever_shapes, clamp_effect, fluid, gate, gate_default, gate_span,
               gate_static, hydrostatic_plate, large_deflection, solid_pressure, solid_static, spheric2,
               volumetric_gradient)

# The order of the rungs, as the report's headline table lists them.
CASES = (cantilever, cantilever_shapes, large_deflection, solid_static, clamp_effect, hydrostatic_plate, fluid, gate,
         gate_default, gate_static, solid_pressure, volumetric_gradient, gate_span, spheric2)

# The order of the report's sections and plots: as CASES, but for gate_static's table, which has come before the
# fluid's (the pages under docs/validation/ keep their layout).
SECTIONS = (cantilever, cantilever_shapes, large_deflection, solid_static, clamp_effect, hydrostatic_plate, gate_static,
            fluid, gate, gate_default, solid_pressure, volumetric_gradient, gate_span, spheric2, antoci_stiffness)

# Studies of the default's sensitivity (not validation cases): run and reported only when named
# (`sph-fsi validate antoci_stiffness --out docs/validation/studies/antoci_stiffness`).
STUDIES = (antoci_stiffness,)

# Names that select several cases at once.
CASE_GROUPS = {"gate": ("antoci_gate", "elastic_gate")}


def all_rungs(studies=False):
    """Every case's rungs, and with `studies` the studies' too."""
    return [r for case in CASES + (STUDIES if studies else ()) for r in case.rungs()]
