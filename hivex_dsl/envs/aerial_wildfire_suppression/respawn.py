"""Respawning single planes in running worlds (the vector env's ML-Agents agent reset), and every plane of a
world whose next episode continues it (``episodes_continue``).

A plane whose episode ended alone (it crossed the border, or a task ends on one of its own
events) starts again as at an episode start -- a random point of the spawn disk, a random
heading, water as the scenario spawns it, out of the fire's sight, its one-off latches cleared -- over the world's
burning island, which goes on. Its camera and sighting are those of its new place.
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from .types import AerialWildfireState, Sighting


def respawn_where(sim, state: AerialWildfireState, mask: np.ndarray, rng: np.random.Generator) -> AerialWildfireState:
    """``state`` with the planes where ``mask`` (B, A) is true respawned; the rest untouched."""
    if not np.count_nonzero(mask):
        return state
    spawn_position, spawn_heading, spawn_water = sim._spawn_out_of_sight(rng, state.fire, state.maps.village, mask)
    position = np.where(mask[..., None], spawn_position, state.position)
    heading = np.where(mask, spawn_heading, state.heading)
    flying = state.flying | mask
    seen = sim._sight_of(state.fire, state.maps.village, position, flying)
    sighting = Sighting(plane_found=np.where(mask, seen.plane_found, state.sighting.plane_found),
                        plane_xy=np.where(mask[..., None], seen.plane_xy, state.sighting.plane_xy),
                        village_threat=state.sighting.village_threat)
    cameras = sim._cameras(position, heading, state.look, state.fire.trees, state.maps.ground)
    off = ~mask
    # a respawned plane reads the ground at its spawn at once (the release's keeps its last hit until the next frame)
    cast_at = np.where(mask[..., None], spawn_position, state.cast_at)
    return replace(state, position=position, heading=heading, water=np.where(mask, spawn_water, state.water),
                   cast_at=cast_at, flying=flying, sighting=sighting, seen_fire=state.seen_fire & off,
                   seen_village=state.seen_village & off, crossed=state.crossed & off,
                   picked_up=state.picked_up & off, dropped=state.dropped & off, found_fire=state.found_fire & off,
                   found_village=state.found_village & off, extinguished=np.where(mask, 0, state.extinguished),
                   prepared=np.where(mask, 0, state.prepared),
                   visual=np.where(mask[..., None, None, None], cameras, state.visual))


def world_goes_on(state: AerialWildfireState, planes: int) -> np.ndarray:
    """(B,) bool: worlds whose next episode continues them under ``episodes_continue``: the fire still burns and
    fewer finishes than ``planes`` were counted, so the release's MaxStep, not its TriggerDone, ended the episode."""
    return state.burning & (state.finishes < planes)


def continue_worlds(sim, state: AerialWildfireState, worlds: np.ndarray, rng: np.random.Generator
                    ) -> AerialWildfireState:
    """A new episode in the running ``worlds`` (B,): every plane respawns, as the release's OnEpisodeBegin does;
    the island, the fire and its clock, wind, weather, the count of finishes and the village's flag go on, and a
    fire that reached the village is paid for again on the next step (the release's city flag stays set)."""
    if not np.count_nonzero(worlds):
        return state
    state = respawn_where(sim, state, np.repeat(worlds[:, None], state.position.shape[1], axis=1), rng)
    kept = ~worlds
    return replace(state, village_hit=state.village_hit & kept, village_threatened=state.village_threatened & kept,
                   fire_went_out=state.fire_went_out & kept)
