"""The answers a run is judged against, and the judging: measured data and exact solutions (references, with the
data files in reference_data/), the finite-element reference (fe_reference, cantilever_fe_table), the oscillation
fit (oscillation) and a scene file's judges (judges). Below the scenes, which state their own answers with it; it
imports nothing above the schema and the geometry keys."""
