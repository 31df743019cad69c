"""A rung of a validation case: one run of a scene with its overrides and end time (each module of cases/ lists
its case's)."""
from dataclasses import dataclass


@dataclass(frozen=True)
class Rung:
    case: str
    label: str
    scene: str
    overrides: dict
    periods: float = 0.0        # cantilever rungs: run this many periods of the reference frequency
    end_time: float = 0.0       # or a fixed end time
    quick: bool = False         # part of --quick (CI)
    bound: float = None         # --quick asserts error <= bound
    note: str = ""
    snapshot_interval: float = 0.0   # particle snapshots (0: none), for the frame plots
    counterpart: str = ""       # "case/label" of the same run made another way, reported side by side
    resolution: str = ""        # how fine, in the case's own terms ("4 through", "a/dp 20"): the report's column
    judge: str = ""             # the scene's judge whose measure and error are the row's (default: the summary's)

    @property
    def key(self):
        return f"{self.case}/{self.label}"


def rung_error(rung, summary):
    """The error a rung is reported and bounded by: its judge's (Rung.judge) or the summary's."""
    if rung.judge:
        return summary.get("judges", {}).get(rung.judge, {}).get("error")
    return summary.get("error")
