"""A wall part's prescribed motion from its keys (`parts.<name>.motion` and the motion_* keys, geometry/parts.py):
a motion.Motion, or None for a wall that stays. Errors are SceneErrors naming the key."""
from pathlib import Path

import numpy as np

from ..errors import SceneError, plain
from ..motion import Commanded, Linear, Sinusoid, Table


def part_motion(name, keys):
    """The motion of wall part `name` with keys `keys` (its keys without the 'parts.<name>.' prefix)."""
    kind = keys.get("motion", "none")
    k = f"parts.{name}."
    if kind == "none":
        return None
    if kind == "linear":
        velocity = np.asarray(keys["motion_velocity"], dtype=np.float64)
        if not velocity.any():
            raise SceneError(f"{k}motion_velocity = {plain(velocity)}: no velocity; allowed: a vector other than "
                             f"[0, 0, 0] m/s (or motion = none)")
        return Linear(velocity, keys["motion_start"], keys["motion_travel"])
    if kind == "sinusoid":
        axis = np.asarray(keys["motion_axis"], dtype=np.float64)
        if not axis.any():
            raise SceneError(f"{k}motion_axis = [0, 0, 0]: no direction; allowed: any vector but [0, 0, 0]")
        return Sinusoid(axis, keys["motion_amplitude"], keys["motion_frequency"], keys["motion_phase"],
                        keys["motion_ramp"], keys["motion_rotation"], keys["motion_point"])
    if kind == "table":
        return Table(read_table(k + "motion_file", keys["motion_file"]), keys["motion_point"])
    return Commanded(keys["motion_point"], keys["motion_max_speed"], keys["motion_period"])


def read_table(key, path):
    """The rows (t, x, y, z[, rx, ry, rz]) of a motion table: a CSV with '#' comments and an optional header row.
    SceneError naming `key` for a file that is missing or is not such a table."""
    file = Path(path)
    if not file.is_file():
        raise SceneError(f"{key} = {path!r}: not found; allowed: a CSV file of poses, relative to the scene file")
    try:
        lines = [ln for ln in file.read_text(encoding="utf-8").splitlines() if ln.strip() and
                 not ln.lstrip().startswith("#")]
    except (OSError, UnicodeDecodeError) as exc:
        raise SceneError(f"{key} = {path!r}: cannot be read ({exc}); allowed: a CSV text file of poses") from None
    rows = []
    for number, line in enumerate(lines):
        cells = [c.strip() for c in line.split(",")]
        try:
            rows.append([float(c) for c in cells])
        except ValueError:
            if number == 0:          # the header row
                continue
            raise SceneError(f"{key} = {path!r}: row {line!r} is not numbers; allowed: rows of t, x, y, z "
                             f"(and rx, ry, rz)") from None
    if not rows or len({len(r) for r in rows}) != 1 or len(rows[0]) not in (4, 7):
        raise SceneError(f"{key} = {path!r}: not a table of poses; allowed: rows of 4 (t, x, y, z) or 7 (and rx, ry, "
                         f"rz) numbers, at least one")
    table = np.array(rows, dtype=np.float64)
    if not np.isfinite(table).all():
        raise SceneError(f"{key} = {path!r}: a value is not finite; allowed: finite numbers")
    if len(table) > 1 and not (np.diff(table[:, 0]) > 0.0).all():
        raise SceneError(f"{key} = {path!r}: its times do not increase from row to row; allowed: increasing times")
    return table
