"""The world facts of Ocean Plastic Collection's global state (:mod:`hivex_dsl.runtime.global_state`)."""

from __future__ import annotations

import numpy as np

from ...runtime.global_state import StateComponent
from .types import OceanState


def state_components(self) -> tuple[StateComponent, ...]:
    """The plastic still floating and where it lies (each vessel's camera sees 50 m around it), and per vessel
    its speed (no vessel observes one) and its catch so far (the Global Lowest Trash Collected reward compares
    them)."""
    return (
        StateComponent("plastic left", 1, 0.0, 1.0, "Pebbles still floating / pebbles at the start."),
        StateComponent("plastic centre", 2, -1.0, 1.0, "Mean (x, y) of the floating pebbles / half extent "
                       "(0 without any)."),
        StateComponent("speed", 1, 0.0, 1.0, "The vessel's speed / top speed (acceleration / drag, at most "
                       "max_speed_m).", per_agent=True),
        StateComponent("collected", 1, 0.0, 1.0, "Pebbles the vessel collected this episode / pebbles at the "
                       "start.", per_agent=True),
    )


def world_state(self, state: OceanState) -> tuple[np.ndarray, np.ndarray]:
    """(vectors (B, A, 12) float32 the vessels' vector observations, world (B, 3 + 2A) float64: plastic left,
    plastic centre (2), speed (A), collected (A))."""
    pebbles = state.pebbles
    total = pebbles.alive.shape[1]
    left = np.count_nonzero(pebbles.alive, axis=1)
    centre = np.where(pebbles.alive, pebbles.z, 0.0).sum(axis=1) / (np.maximum(left, 1) * self.half_extent)
    world = np.concatenate([
        (left / total)[:, None],
        np.clip(np.stack([centre.real, centre.imag], axis=1), -1.0, 1.0),
        np.clip(state.speed / self.geometry.top_speed, 0.0, 1.0),
        state.collected_total / total,
    ], axis=1)
    return state.vector, world


def state_facts(simulator, state: OceanState, params) -> dict[str, list[float]]:
    """World 0's plastic facts counted pebble by pebble, for the tests to compare with :func:`world_state`
    (:attr:`hivex_dsl.compiler.registry.EnvironmentEntry.state_facts`)."""
    alive = state.pebbles.alive[0]
    xy = state.pebbles.positions[0][alive]
    return {"plastic left": [float(alive.mean())], "plastic centre": (xy.mean(axis=0) / simulator.half_extent).tolist(),
            "collected": (state.collected_total[0] / alive.size).tolist()}
