"""The world facts of Wildfire Resource Management's global state (:mod:`hivex_dsl.global_state`)."""

from __future__ import annotations

import numpy as np

from ...fire.summary import FIRE_FACTS, fire_summary
from ...global_state import StateComponent
from .types import WildfireResourceState


def state_components(self) -> tuple[StateComponent, ...]:
    """The main wind, the fire as a whole (the towers see only the nearest burning tree within their detection
    radius) and the weather over the whole island (the towers read it at their own feet)."""
    return (
        StateComponent("main wind", 2, -1.0, 1.0, "Direction the main wind blows to (cos, sin); fire spreads "
                       "downwind."),
        StateComponent("fire burning", 1, 0.0, 1.0, "Burning trees n on the C x C forest grid, log(1 + n) / "
                       "log(1 + C^2)."),
        StateComponent("fire front centre", 2, -1.0, 1.0, "Mean (x, y) of the burning trees / island half extent "
                       "(0 without fire)."),
        StateComponent("fire front spread", 1, 0.0, 1.0, "Root-mean-square distance of the burning trees from "
                       "their centre / (sqrt(2) x island half extent)."),
        StateComponent("fire out", 1, 0.0, 1.0, "1 once the island's fire is out, else 0."),
        StateComponent("island weather", 3, 0.0, 1.0, "Temperature, humidity and overcast averaged over the "
                       "weather grid (as the fire's spread factors read them)."),
    )


def world_state(self, state: WildfireResourceState) -> tuple[np.ndarray, np.ndarray]:
    """(vectors (B, 9, 16) float32 the towers' observations, world (B, 9) float64: main wind (2), fire summary
    (5, see :func:`hivex_dsl.fire.summary.fire_summary`), island weather (3))."""
    batch = len(state.budget)
    world = np.empty((batch, 2 + FIRE_FACTS + 3))
    world[:, 0] = np.cos(state.wind.main)
    world[:, 1] = np.sin(state.wind.main)
    world[:, 2:2 + FIRE_FACTS] = fire_summary(state.fire, self.params.island_half_extent_m, self.cell_m)
    world[:, 2 + FIRE_FACTS:] = state.conditions.reshape(batch, -1, 3).mean(axis=1, dtype=np.float64)
    return state.frame, world
