"""The world facts of Drone-Based Reforestation's global state (:mod:`hivex_dsl.runtime.global_state`)."""

from __future__ import annotations

import numpy as np

from ...runtime.global_state import StateComponent
from .types import DroneState


def state_components(self) -> tuple[StateComponent, ...]:
    """The team's planting (how many trees and how good their spots), where the station lies (the drones observe
    only its height) and the drones' energy as one team figure."""
    return (
        StateComponent("trees planted", 1, 0.0, 1.0, "Trees planted this episode / new_tree_capacity (the most a "
                       "world holds)."),
        StateComponent("planting quality", 1, 0.0, 1.0, "Mean seed quality r_s / 20 of the planted trees (0 "
                       "before the first)."),
        StateComponent("station", 2, -1.0, 1.0, "The station's (x, y) / half extent: the centre, (0, 0), unless "
                       "a scenario lets the village move (generators.terrain.village_half_range_m)."),
        StateComponent("team energy", 1, 0.0, 1.0, "Mean battery level of the world's drones."),
    )


def world_state(self, state: DroneState) -> tuple[np.ndarray, np.ndarray]:
    """(vectors (B, A, 20) float32 the drones' vector observations, world (B, 5) float64: trees planted,
    planting quality, station (2), team energy)."""
    count = state.new_count
    quality = state.new_quality.sum(axis=1, dtype=np.float64) / np.maximum(count, 1)
    station = state.station[:, :2] / self.half
    world = np.concatenate([
        np.clip(count / state.new_quality.shape[1], 0.0, 1.0)[:, None],
        np.clip(quality, 0.0, 1.0)[:, None],
        np.clip(station, -1.0, 1.0),
        np.clip(state.energy.mean(axis=1), 0.0, 1.0)[:, None],
    ], axis=1)
    return self.vector_observation(state), world


def state_facts(simulator, state: DroneState, params) -> dict[str, list[float]]:
    """World 0's station, planting and energy facts read off the state, for the tests to compare with
    :func:`world_state` (:attr:`hivex_dsl.compiler.registry.EnvironmentEntry.state_facts`); the planting quality
    once a tree is planted."""
    count = int(state.new_count[0])
    facts = {"station": (state.station[0, :2] / simulator.half).tolist(),
             "trees planted": [count / params.new_tree_capacity], "team energy": [float(state.energy[0].mean())]}
    if count:
        facts["planting quality"] = [float(state.new_quality[0, :count].mean())]
    return facts
