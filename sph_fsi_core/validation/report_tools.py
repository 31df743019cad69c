"""What every case's table and plot use (validation/cases/): a run's stored time series, a number's cell, a table
of one section, a figure's panels saved."""
import csv
import math
from pathlib import Path


def series_rows(out_dir, rung):
    """A rung's timeseries.csv as a list of rows (dicts of strings), None if it was not run."""
    path = Path(out_dir) / "runs" / rung.case / rung.label / "timeseries.csv"
    if not path.is_file():
        return None
    with path.open() as fh:
        return list(csv.DictReader(fh))


def fmt(x, spec=".3g"):
    """`x` formatted by `spec`, "-" when it is missing or not finite."""
    if x is None or (isinstance(x, float) and not math.isfinite(x)):
        return "-"
    return format(x, spec)


def save_panels(plt, fig, axes, path, legend_size=None):
    """A figure's panels gridded (and their legends drawn at `legend_size`), laid out, saved at 120 dpi and closed;
    returns the file's name."""
    for a in axes:
        a.grid(True, alpha=0.3)
        if legend_size:
            a.legend(fontsize=legend_size)
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)
    return Path(path).name


def grid_table(title, text, row_name, rows, col_names, cell):
    """A section with one table: a row per entry of `rows`, a column per (label, key) of `col_names`, each cell
    cell(row, key)."""
    lines = ["", title, "", text, "", f"| {row_name} | " + " | ".join(label for label, _ in col_names) + " |",
             "|---|" + "---|" * len(col_names)]
    for row, row_label in rows:
        lines.append(f"| {row_label} | " + " | ".join(cell(row, key) for _, key in col_names) + " |")
    return lines
