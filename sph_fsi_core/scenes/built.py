"""What a builder returns: the particles of each phase the scene has (None for the others), probes, domain."""
from dataclasses import dataclass, field

import numpy as np

from ..state import FluidState, SolidState, WallState


@dataclass
class Built:
    solid: SolidState | None = None
    fluid: FluidState | None = None
    walls: WallState | None = None
    probes: list = field(default_factory=list)
    domain_lo: np.ndarray = None   # particles leaving this box stop the run as diverged
    domain_hi: np.ndarray = None
    period: np.ndarray = field(default_factory=lambda: np.zeros(3))
