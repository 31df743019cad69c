"""What `sph-fsi validate` runs and reports, a module per case (or per family of cases that share a table): each has

    rungs()                                   its rungs (validation/rung.py), in the order they are reported
    table(out_dir, rungs, summaries)          optional: its section of REPORT.md, as lines ([] when nothing is run)
    plot(out_dir, rungs, summaries, plt)      optional: its PNGs written into out_dir, their file names

table and plot see every reported rung and pick their own (the gates' by scene, across cases). A run is judged by
its scene's evaluate (scenes/*.py), which run_scene calls; running the rungs is ladder.py's, the page report.py's.

Two kinds: the default suite (CASES: today's default scheme on every case, `sph-fsi validate`, the page
docs/validation/REPORT.md) and the studies (STUDIES: other schemes and options, run only when named, each its own
page under docs/validation/studies/).
"""
from . import (antoci_stiffness, antoci_tank, cantilever, cantilever_shapes, clamp_effect, default_coupled,
               default_fluid, default_solid, fixed_iterations, fluid, gate, gate_default, gate_span, gate_static,
               hydrostatic_plate, kernel, large_deflection, partial_iteration, pressure_tolerance, push_ramp, shifting,
               solid_pressure, solid_static, spheric2, volumetric_gradient, water_lattice)

# The default suite, in the order of the report's headline table: the solid alone, the water alone, then both.
CASES = (default_solid, default_fluid, spheric2, default_coupled)

# Studies of other schemes and options, and of the default's sensitivity: run and reported only when named
# (`sph-fsi validate gate_span --out docs/validation/studies/gate_span`).
STUDIES = (cantilever, cantilever_shapes, large_deflection, solid_static, clamp_effect, hydrostatic_plate, fluid, gate,
           gate_default, gate_static, solid_pressure, volumetric_gradient, gate_span, antoci_stiffness,
           pressure_tolerance, partial_iteration, water_lattice, kernel, fixed_iterations, push_ramp, antoci_tank,
           shifting)

# The order of the pages' sections and plots (each module's table and plot pick their own rungs); among the studies,
# gate_static's table comes before the fluid's (the committed pages keep their layout).
SECTIONS = (default_solid, default_fluid, spheric2, default_coupled, cantilever, cantilever_shapes, large_deflection,
            solid_static, clamp_effect, hydrostatic_plate, gate_static, fluid, gate, gate_default, solid_pressure,
            volumetric_gradient, gate_span, antoci_stiffness, pressure_tolerance, partial_iteration, water_lattice,
            kernel, fixed_iterations, push_ramp, antoci_tank, shifting)

# Names that select several cases at once.
CASE_GROUPS = {"gate": ("antoci_gate", "elastic_gate"), "standing_wave": ("standing_wave", "standing_wave_loss")}


def all_rungs(studies=False):
    """The default suite's rungs, and with `studies` the studies' too."""
    return [r for case in CASES + (STUDIES if studies else ()) for r in case.rungs()]


def default_case_names():
    """The default suite's case names, in order."""
    return list(dict.fromkeys(r.case for r in all_rungs()))
