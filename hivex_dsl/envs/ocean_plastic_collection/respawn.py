"""Respawning single vessels in running worlds (the vector env's ML-Agents agent reset).

A vessel whose episode ended alone (``crash_outcome: end``) starts again, at rest with a random
heading, at the best of a few random spawn points (the one farthest from every other vessel, as
``crash_outcome: respawn`` places it), with observations that are first ones: this frame
in the newest stack, zeros in the older one.
"""

from __future__ import annotations

import numpy as np

from ...sim.batching import evolve
from .camera import sense
from .neighbours import neighbour_distances
from .types import OceanState


def respawn_where(sim, state: OceanState, mask: np.ndarray, rng: np.random.Generator) -> OceanState:
    """``state`` with the vessels where ``mask`` (B, A) is true respawned; the rest untouched."""
    if not np.count_nonzero(mask):
        return state
    position, heading, speed = sim._respawn(state.position, state.heading, state.speed, mask, rng)
    active = state.active | mask
    facing = np.exp(1j * heading)
    sensing = sense(state.pebbles, position, facing, speed, active, sim.geometry, sweeping=None)
    distances = neighbour_distances(position, active)
    closest = distances.min(axis=-1)
    vector = sim._vector(position, facing, distances, closest, np.zeros_like(state.vector))
    visual = sim._visual(sensing, state.heat, position, facing, active, np.zeros_like(state.visual))
    picked = mask[..., None]
    return evolve(state, position=position, heading=heading, speed=speed, active=active,
                  crashed=state.crashed & ~mask, crossed_border=state.crossed_border & ~mask,
                  collided_vessel=state.collided_vessel & ~mask, closest=np.where(mask, closest, state.closest),
                  collected=np.where(mask, 0, state.collected), collected_total=np.where(mask, 0, state.collected_total),
                  decision_collected=np.where(mask, 0, state.decision_collected),
                  nearby=np.where(mask, sensing.nearby, state.nearby), nearby_best=np.where(mask, 0, state.nearby_best),
                  vector=np.where(picked, vector, state.vector),
                  visual=np.where(picked[..., None, None], visual, state.visual))
