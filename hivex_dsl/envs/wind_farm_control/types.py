"""The batched state of Wind Farm Control."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Optional

import numpy as np

from ...sim.procgen.wind import WindProbe, WindState


@dataclass(frozen=True)
class WindFarmState:
    """B worlds of A turbines. Angles in radians; headings are where the rotor faces."""

    positions: np.ndarray  # (B, A, 2) metres, fixed for an episode
    heading: np.ndarray  # (B, A)
    performance: np.ndarray  # (B, A) P of the paper's equation, before clamping
    local_wind: np.ndarray  # (B, A) wind direction at each turbine (where it blows to)
    wind: WindState
    wind_probe: Optional[WindProbe] = None  # cached noise lookups at the turbines (see procgen.wind)
