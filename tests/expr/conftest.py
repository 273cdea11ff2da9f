"""A small vocabulary shared by the expression tests: two worlds' worth of every shape and kind."""

from __future__ import annotations

import numpy as np
import pytest

from hivex_dsl.lang.expr import Quantity

QUANTITIES = (
    Quantity("distance_m", "agent", "number", "m", 0.0, 1000.0, "distance to the fire"),
    Quantity("speed_ms", "agent", "number", "m/s", -5.0, 5.0, "signed speed"),
    Quantity("heading_deg", "agent", "number", "deg", 0.0, 360.0, "heading"),
    Quantity("water", "agent", "number", "1", 0.0, 1.0, "water held"),
    Quantity("wind_ms", "world", "number", "m/s", 0.0, 20.0, "wind speed"),
    Quantity("burning", "world", "number", "1", 0.0, 400.0, "burning trees"),
    Quantity("dropped", "agent", "bool", "", 0.0, 1.0, "dropped water this step"),
    Quantity("raining", "world", "bool", "", 0.0, 1.0, "rain falls"),
)
VOCABULARY = {q.name: q for q in QUANTITIES}
AGENTS = 3


def sample(rng: np.random.Generator, batch: int = 4, agents: int = AGENTS) -> dict[str, np.ndarray]:
    """In-range values of every quantity, at their shapes."""
    values = {}
    for q in QUANTITIES:
        shape = (batch, agents) if q.per == "agent" else (batch,)
        values[q.name] = rng.random(shape) < 0.5 if q.kind == "bool" else rng.uniform(q.low, q.high, shape)
    return values


@pytest.fixture
def states():
    rng = np.random.default_rng(7)
    return sample(rng), sample(rng)
