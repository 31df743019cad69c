"""Everything that judges the simulator, kept apart from the simulator itself: the reference data and readers
(references, reference_data/), the 3D finite-element reference (fe_reference), the oscillation analysis
(oscillation), the validation ladders (cases/: a module per case with its rungs, table and plot; ladder: running
them; report: the page that gathers them) and the stiff and extreme cases (stability)."""

# Where `sph-fsi validate` and `sph-fsi stability` write unless told otherwise: a user's run never overwrites the
# project's committed report; `--out docs/validation` publishes into it on purpose.
DEFAULT_OUT_DIR = "runs/validation"
