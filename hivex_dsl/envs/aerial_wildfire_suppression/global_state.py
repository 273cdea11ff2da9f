"""The world facts of Aerial Wildfire Suppression's global state (:mod:`hivex_dsl.runtime.global_state`)."""

from __future__ import annotations

import numpy as np

from ...runtime.global_state import StateComponent
from ...sim.fire.summary import FIRE_FACTS, SQRT2, fire_summary, nearest_burning_distance
from ..island import ISLAND_STATE_COMPONENTS, burning_cells_xy, island_fire_facts
from .types import AerialWildfireState


def state_components(self) -> tuple[StateComponent, ...]:
    """The main wind, the fire as a whole (a plane sees only the nearest burning tree in its view square) and the
    village (where it lies, how close the fire is to it)."""
    return (
        *ISLAND_STATE_COMPONENTS,
        StateComponent("village", 2, -1.0, 1.0, "The village centre (x, y) / border half extent, as the planes' "
                       "positions are observed."),
        StateComponent("fire to village", 1, 0.0, 1.0, "Distance from the village centre to the nearest burning "
                       "tree / the island's diagonal (1 without fire)."),
        StateComponent("village threatened", 1, 0.0, 1.0, "1 while a burning tree lies in the village's zone "
                       "(params.village_zone), else 0."),
    )


def world_state(self, state: AerialWildfireState) -> tuple[np.ndarray, np.ndarray]:
    """(vectors (B, A, 8) float32 the planes' vector observations, world (B, 11) float64: main wind (2), fire
    summary (5, see :func:`hivex_dsl.sim.fire.summary.fire_summary`), village (2), fire to village, village
    threatened)."""
    p, fire, village = self.params, state.fire, state.maps.village
    half = p.island_half_extent_m
    world = np.empty((fire.batch, 2 + FIRE_FACTS + 4))
    world[:, 0] = np.cos(state.wind.main)
    world[:, 1] = np.sin(state.wind.main)
    world[:, 2:2 + FIRE_FACTS] = fire_summary(fire, half, self.cell_m)
    end = 2 + FIRE_FACTS
    world[:, end:end + 2] = np.clip(village / p.border_half_extent_m, -1.0, 1.0)
    distance = nearest_burning_distance(fire, village, half, self.cell_m)
    world[:, end + 2] = np.minimum(distance / (2.0 * SQRT2 * half), 1.0)
    world[:, end + 3] = state.sighting.village_threat
    return self.observe(state)["vector"], world


def state_facts(simulator, state: AerialWildfireState, params) -> dict[str, list[float]]:
    """World 0's fire and village facts counted off the tree grid, for the tests to compare with :func:`world_state`
    (:attr:`hivex_dsl.compiler.registry.EnvironmentEntry.state_facts`)."""
    half = params.island_half_extent_m
    x, y = burning_cells_xy(state, half)
    vx, vy = state.maps.village[0]
    gap = min((float(np.hypot(bx - vx, by - vy)) for bx, by in zip(x, y)), default=np.inf)
    return island_fire_facts(state, half) | {"fire to village": [min(gap / (2 * np.sqrt(2) * half), 1.0)],
                                             "village": (state.maps.village[0] / params.border_half_extent_m).tolist()}
