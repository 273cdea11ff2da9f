"""The world facts of Wildfire Resource Management's global state (:mod:`hivex_dsl.runtime.global_state`)."""

from __future__ import annotations

import numpy as np

from ...runtime.global_state import StateComponent
from ...sim.fire.summary import FIRE_FACTS, fire_summary
from ..island import ISLAND_STATE_COMPONENTS, burning_cells_xy, island_fire_facts
from .types import WildfireResourceState


def state_components(self) -> tuple[StateComponent, ...]:
    """The main wind, the fire as a whole (the towers see only the nearest burning tree within their detection
    radius) and the weather over the whole island (the towers read it at their own feet)."""
    return (
        *ISLAND_STATE_COMPONENTS,
        StateComponent("island weather", 3, 0.0, 1.0, "Temperature, humidity and overcast averaged over the "
                       "weather grid (as the fire's spread factors read them)."),
    )


def world_state(self, state: WildfireResourceState) -> tuple[np.ndarray, np.ndarray]:
    """(vectors (B, 9, 16) float32 the towers' observations, world (B, 9) float64: main wind (2), fire summary
    (5, see :func:`hivex_dsl.sim.fire.summary.fire_summary`), island weather (3))."""
    batch = len(state.budget)
    world = np.empty((batch, 2 + FIRE_FACTS + 3))
    world[:, 0] = np.cos(state.wind.main)
    world[:, 1] = np.sin(state.wind.main)
    world[:, 2:2 + FIRE_FACTS] = fire_summary(state.fire, self.params.island_half_extent_m, self.cell_m)
    world[:, 2 + FIRE_FACTS:] = state.conditions.reshape(batch, -1, 3).mean(axis=1, dtype=np.float64)
    return state.frame, world


def state_facts(simulator, state: WildfireResourceState, params) -> dict[str, list[float]]:
    """World 0's fire and weather facts counted off the tree grid and the conditions, for the tests to compare with
    :func:`world_state` (:attr:`hivex_dsl.compiler.registry.EnvironmentEntry.state_facts`)."""
    return island_fire_facts(state, params.island_half_extent_m) | {
        "island weather": state.conditions[0].reshape(-1, 3).mean(axis=0).tolist()}
