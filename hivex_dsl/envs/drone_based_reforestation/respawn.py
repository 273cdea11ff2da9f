"""Respawning single drones in running worlds (the vector env's ML-Agents agent reset).

A drone whose episode ended alone (its battery ran out, or a task ends on one of its own events)
starts again as at an episode start -- spawned as the scenario spawns drones, full battery, the
seed it would start with, its per-episode bests and running-back bookkeeping cleared -- while its
world's planted trees stay. Its vector observation is a first one (this frame, the older stack zeros).
"""

from __future__ import annotations

import numpy as np

from ...sim.batching import evolve
from .types import DroneState, Flight


def respawn_where(sim, state: DroneState, mask: np.ndarray, rng: np.random.Generator) -> DroneState:
    """``state`` with the drones where ``mask`` (B, A) is true respawned; the rest untouched."""
    if not np.count_nonzero(mask):
        return state
    p = sim.params
    spawn, spawn_heading, spawn_ground, holding_at_start = sim._spawn(rng, state.heights, state.station)
    position = np.where(mask[..., None], spawn, state.position)
    heading = np.where(mask, spawn_heading, state.heading)
    ground = np.where(mask, spawn_ground, state.ground)
    energy = np.where(mask, 1.0, state.energy)
    holding = np.where(mask, holding_at_start, state.holding)
    distance, _ = sim._station_distances(position, state.station)
    flight = Flight(position, position[..., :2], position[..., 2], heading,
                    np.stack([np.cos(heading), np.sin(heading)], axis=-1), ground, None)
    first = sim._frames(np.zeros_like(state.frames), flight, state.station, holding, energy)  # older stack zeros
    off = ~mask
    return evolve(state, position=position, heading=heading, ground=ground, energy=energy, holding=holding,
                  alive=state.alive | mask,
                  inside=np.where(mask, distance <= p.charge_radius_m, state.inside),
                  docked_steps=state.docked_steps * off,
                  away=np.where(mask, distance >= p.return_min_distance_m, state.away),
                  best_fertility=state.best_fertility * off, best_height=state.best_height * off,
                  best_distance=state.best_distance * off, back_active=state.back_active & off,
                  back_init=state.back_init * off, back_best=state.back_best * off,
                  back_multiplier=state.back_multiplier * off, flown=state.flown * off, dropped=state.dropped & off,
                  seed_reward=state.seed_reward * off, distance_reward=state.distance_reward * off,
                  drop_tree_distance=state.drop_tree_distance * off,
                  returned=state.returned & off, found_tree=state.found_tree & off,
                  running_back=state.running_back * off, frames=np.where(mask[..., None], first, state.frames))
