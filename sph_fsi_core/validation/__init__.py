"""What runs scenes and writes the reports: the validation ladders (cases/: a module per case with its rungs, table
and plot; ladder: running them; report: the page that gathers them), the stiff and extreme cases (stability), the
sweeps and the linear-modes analysis. What a run is judged against lives below the scenes, in sph_fsi_core.answers."""

# Where `sph-fsi validate` and `sph-fsi stability` write unless told otherwise: a user's run never overwrites the
# project's committed report; `--out docs/validation` publishes into it on purpose.
DEFAULT_OUT_DIR = "runs/validation"
