"""Where planes start an episode (or start again alone, respawn.py): positions, headings and water, out of the fire's
sight. Functions of the simulator (``sim``: its params, agents, spawn_water and sighting), bound as its methods."""

from __future__ import annotations

import numpy as np

SPAWN_REDRAWS = 16  # a spawn that sees the fire is drawn again up to this many times (then kept)


def spawn(sim, rng: np.random.Generator, count: int, village: np.ndarray
          ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Positions (count, A, 2) uniform in the spawn disk clipped to the border, or, for planes without water
    (which would fill up on the first step over the ring), uniform over the island at least two steps from the
    ring; pushed two steps beyond the village radius (the village is found by flying to it); headings; water.
    ``village`` (count, 2)."""
    p, shape = sim.params, (count, sim.agents)
    if p.spawn_rule == "release":
        return release_spawn(sim, rng, shape)
    if sim.spawn_water:
        limit = p.border_half_extent_m
        radius = p.spawn_radius_m * np.sqrt(rng.random(shape))
        angle = rng.uniform(-np.pi, np.pi, shape)
        position = np.clip(np.stack([radius * np.cos(angle), radius * np.sin(angle)], axis=-1), -limit, limit)
    else:
        limit = p.island_half_extent_m - 2.0 * p.plane_speed_m
        position = rng.uniform(-limit, limit, shape + (2,))
    gap = position - village[:, None, :]
    distance = np.hypot(gap[..., 0], gap[..., 1])
    push = np.maximum(p.village_radius_m + 2.0 * p.plane_speed_m, distance) / np.maximum(distance, 1e-9)
    position = np.clip(village[:, None, :] + gap * push[..., None], -limit, limit)
    heading = rng.uniform(-np.pi, np.pi, shape)
    return position, heading, np.full(shape, sim.spawn_water)


def release_spawn(sim, rng: np.random.Generator, shape: tuple[int, int]
                  ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The release's RespawnAgent: a direction from a uniform point of the square [-1, 1]^2, normalised, a
    distance uniform up to spawn_radius_m, a uniform heading; nothing kept away from ring, village or fire."""
    square = rng.uniform(-1.0, 1.0, shape + (2,))
    direction = square / np.maximum(np.hypot(square[..., 0], square[..., 1]), 1e-12)[..., None]
    position = direction * rng.uniform(0.0, sim.params.spawn_radius_m, shape)[..., None]
    limit = sim.params.border_half_extent_m
    heading = rng.uniform(-np.pi, np.pi, shape)
    return np.clip(position, -limit, limit), heading, np.full(shape, sim.spawn_water)


def spawn_out_of_sight(sim, rng: np.random.Generator, fire, village: np.ndarray, mask: np.ndarray | None = None
                       ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """:func:`spawn`, drawn again (at most SPAWN_REDRAWS times) for the planes (where ``mask`` (B, A), all by
    default) whose view already holds a burning tree: as the village, the fire is found by flying to it
    (``spawn_rule: release`` draws once, as the release does)."""
    position, heading, water = spawn(sim, rng, len(village), village)
    if sim.params.spawn_rule == "release":
        return position, heading, water
    flying = np.ones(position.shape[:2], bool) if mask is None else mask
    for _ in range(SPAWN_REDRAWS):
        sees = sim._sight_of(fire, village, position, flying).plane_found
        if not sees.any():
            break
        again, turned, _ = spawn(sim, rng, len(village), village)
        position, heading = np.where(sees[..., None], again, position), np.where(sees, turned, heading)
    return position, heading, water
