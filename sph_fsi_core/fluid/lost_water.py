"""The record of the water that left the scene's domain box: how much, when, over which face, beside which wall.

Simulation holds such water still where it left (a splash over a tank's rim, water poured beside the tank), as
DualSPHysics excludes its "out" particles, and the run goes on: a splash is not a divergence. This record says which
particles left and when, over which face of the domain box (the axis along which each was farthest out) and, in a
scene of named wall parts, which wall or gate part each was nearest when it left; the log, summary.json's
`fluid_lost` and the node's /diagnostics report it. watchdog.max_fluid_lost may stop the run at a fraction
(diagnostics.WaterLost).
"""
import numpy as np
from numba import njit

from ..errors import plain

FACES = ("-x", "+x", "-y", "+y", "-z", "+z")


@njit(cache=True, fastmath=False, error_model="numpy", nogil=True)
def nearest(points, candidates):
    """The index of the candidate (N, 3) nearest to each point (P, 3), by brute force: a run calls it only for the
    few particles that left in an outer step."""
    out = np.empty(points.shape[0], dtype=np.int64)
    for i in range(points.shape[0]):
        best, at = np.inf, -1
        for j in range(candidates.shape[0]):
            d2 = ((points[i, 0] - candidates[j, 0]) ** 2 + (points[i, 1] - candidates[j, 1]) ** 2
                  + (points[i, 2] - candidates[j, 2]) ** 2)
            if d2 < best:
                best, at = d2, j
        out[i] = at
    return out


class LostWater:
    """Who left the domain box, when and where. `record` takes each outer step's newcomers; `summary` and `line`
    report them."""

    def __init__(self, count, built):
        """`count` water particles; `built` (scenes/built.Built): the domain box and the wall and gate parts."""
        self.count = count
        self.lo, self.hi = np.asarray(built.domain_lo), np.asarray(built.domain_hi)
        self.time = np.full(count, np.nan)                 # when each left (NaN: it has not)
        self.face = np.full(count, -1, dtype=np.int8)      # over which face (FACES)
        self.wall = np.full(count, -1, dtype=np.int32)     # nearest which wall part (wall_names)
        self.wall_names, positions, owners = [], [], []
        states = {"walls": built.walls, "gate": built.release_walls}
        for name, (phase, idx) in built.parts.items():
            if phase in states and states[phase] is not None and len(idx):
                owners.append(np.full(len(idx), len(self.wall_names)))
                positions.append(states[phase].pos[idx])
                self.wall_names.append(name)
        self._wall_pos = np.ascontiguousarray(np.concatenate(positions)) if positions else np.zeros((0, 3))
        self._wall_owner = np.concatenate(owners) if owners else np.zeros(0, dtype=np.int64)

    @property
    def lost(self):
        return int(np.isfinite(self.time).sum())

    def record(self, new, time, pos, warnings):
        """Water particles `new` (indices) found outside the box at `time`, at `pos` (len(new), 3) m, as they left.
        The first to leave adds a warning to `warnings`; the rest are counted for the summary."""
        first = self.lost == 0
        self.time[new] = time
        beyond = np.concatenate([self.lo - pos, pos - self.hi], axis=1)          # (n, 6): -x, -y, -z, +x, +y, +z
        self.face[new] = np.array([0, 2, 4, 1, 3, 5], dtype=np.int8)[np.argmax(beyond, axis=1)]
        if len(self._wall_pos):
            self.wall[new] = self._wall_owner[nearest(np.ascontiguousarray(pos, dtype=np.float64), self._wall_pos)]
        if first:
            i = new[0]
            near = f", nearest parts.{self.wall_names[self.wall[i]]}" if self.wall[i] >= 0 else ""
            warnings.append(f"t = {time:.6g} s: water began to leave the domain box {plain(self.lo)} .. "
                            f"{plain(self.hi)} m: {len(new)} particle(s) over its {FACES[self.face[i]]} face (e.g. "
                            f"fluid particle {i}{near}); held still where they left, the run goes on (summary.json's "
                            f"fluid_lost counts them all)")

    def summary(self):
        """{particles, fraction, first_time_s, faces: {face: particles}, nearest_walls: {part: particles}} (the last
        with named wall parts only)."""
        gone = np.isfinite(self.time)
        out = {"particles": int(gone.sum()), "fraction": float(gone.sum() / self.count) if self.count else 0.0,
               "first_time_s": float(np.nanmin(self.time)) if gone.any() else None,
               "faces": {FACES[f]: int(n) for f, n in enumerate(np.bincount(self.face[gone], minlength=6)) if n}}
        if self.wall_names:
            counts = np.bincount(self.wall[gone][self.wall[gone] >= 0], minlength=len(self.wall_names))
            out["nearest_walls"] = {name: int(n) for name, n in zip(self.wall_names, counts) if n}
        return out


def lost_line(lost):
    """One line for a log from a summary's `fluid_lost` (LostWater.summary); None if no water left."""
    if not lost or not lost["particles"]:
        return None
    faces = ", ".join(f"{face} {n}" for face, n in lost["faces"].items())
    walls = lost.get("nearest_walls") or {}
    near = ("; nearest " + ", ".join(f"parts.{name} {n}" for name, n in walls.items())) if walls else ""
    return (f"{lost['particles']} water particle(s) ({100 * lost['fraction']:.3g} % of the water) left the domain box "
            f"from t = {lost['first_time_s']:.6g} s, held still where they left: over its faces {faces}{near}")
