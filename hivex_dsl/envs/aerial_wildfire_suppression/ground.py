"""The ground under the planes: which forest-grid cell, how high the terrain, whether a drop lands on land and
whether the drop's action mask opens. Functions of the simulator (``sim``: its params, forest grid, terrain grid,
sea level and drop rules), bound as its methods."""

from __future__ import annotations

import numpy as np

from ...base.numeric import clamp
from ...sim.grids import sample_bilinear
from ..island import SEA, IslandMaps

# [orig] The release's AutoAdjustHeight, once a frame: a plane flies 100 m above the terrain its ray cast down hits
# (100 m over ground below 0), and past 500 m from the centre in x or y it descends to 10-110 m over the last 150 m
FLIGHT_HEIGHT_M = 100.0
DESCENT_FROM_M, DESCENT_OVER_M = 500.0, 150.0
# [orig] The release's WriteDiscreteActionMask opens the drop where the ray cast down hits the terrain (layer 8) at a
# height of at least 0.02, where its DropWater needs 10 (our SEA_LEVEL_M, 7 m, fitted to the untrained planes' first
# drops, stands for that): the mask is open over a low shore where a drop does nothing.
MASK_TERRAIN_M = 0.02


def over_land(sim, maps: IslandMaps, position: np.ndarray) -> np.ndarray:
    """(B, A) bool: the ground under each plane (``position`` (B, A, 2) metres) is land above the sea: its
    forest-grid cell is not sea, and past the grid, under params.drop_ground 'terrain', the generator's whole map
    stands above the sea level there (a headland under the water ring); else nothing past the grid."""
    inside, cell = cells_under(sim, position)
    land = inside & (maps.ground.reshape(-1).take(cell) != SEA)
    if sim.drops_past_island and not inside.all():
        land |= ~inside & (terrain_height(sim, maps, position) > sim.sea_level_m)
    return land


def over_terrain(sim, maps: IslandMaps, position: np.ndarray) -> np.ndarray:
    """(B, A) bool: the terrain under each plane (``position`` (B, A, 2) metres) stands at least MASK_TERRAIN_M
    high: its forest-grid cell's height, and past the grid, under params.drop_mask 'release', the whole
    terrain's (the water ring's seabed); else nothing past the grid."""
    inside, cell = cells_under(sim, position)
    high = inside & (maps.height.reshape(-1).take(cell) >= MASK_TERRAIN_M)
    if sim.release_mask and not inside.all():
        high |= ~inside & (terrain_height(sim, maps, position) >= MASK_TERRAIN_M)
    return high


def terrain_height(sim, maps: IslandMaps, position: np.ndarray) -> np.ndarray:
    """(B, A) metres: the generator's whole height map under each plane (``position`` (B, A, 2) metres), which
    runs on under the water ring past the forest grid."""
    return sample_bilinear(maps.terrain, sim.terrain_grid, position)


def cells_under(sim, position: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(B, A) bool whether each plane (``position`` (B, A, 2) metres) is over the island's grid, and (B, A) the
    flat index of the (B, C, C) grid cell under it (clamped onto the grid where it is not)."""
    half, cells = sim.params.island_half_extent_m, sim.forest_spec.cells
    cell = np.floor((position + half) / sim.cell_m)  # (B, A, 2): col, row
    inside = ((cell >= 0) & (cell < cells)).all(axis=-1)
    col, row = clamp(cell, 0, cells - 1).astype(np.int64).transpose(2, 0, 1)
    world = np.arange(position.shape[0])[:, None]
    return inside, (world * cells + row) * cells + col


def flight_height(sim, maps: IslandMaps, cast_at: np.ndarray) -> np.ndarray:
    """(B, A) metres: how high each plane flies, as the release's AutoAdjustHeight set it at its last frame's cast
    (``cast_at`` (B, A, 2) metres): FLIGHT_HEIGHT_M above the terrain there, ground below 0 read as 0; past
    DESCENT_FROM_M in x or y, ((cos(pi d) + 1) / 2 + 0.1) x FLIGHT_HEIGHT_M over the sea, d the distance past it
    (each axis at most DESCENT_OVER_M) over DESCENT_OVER_M."""
    height = np.maximum(terrain_height(sim, maps, cast_at), 0.0) + FLIGHT_HEIGHT_M
    past = clamp(np.abs(cast_at) - DESCENT_FROM_M, 0.0, DESCENT_OVER_M)
    d = np.hypot(past[..., 0], past[..., 1]) / DESCENT_OVER_M
    descending = ((np.cos(np.pi * d) + 1.0) / 2.0 + 0.1) * FLIGHT_HEIGHT_M
    return np.where(d > 0.0, descending, height)


def near_village(sim, maps: IslandMaps, position: np.ndarray, cast_at: np.ndarray, flying: np.ndarray
                 ) -> np.ndarray:
    """(B, A) bool: the flying planes (``position`` (B, A, 2) metres) within village_radius_m of the village:
    horizontally, or under params.village_distance 'release' in 3-D, as the release's FindVillageTask reads it,
    from the plane at its :func:`flight_height` to the village on its ground."""
    gap = position - maps.village[:, None, :]
    reach = sim.params.village_radius_m
    near = flying & (np.hypot(gap[..., 0], gap[..., 1]) <= reach)
    if sim.params.village_distance == "release" and np.count_nonzero(near):
        climb = flight_height(sim, maps, cast_at) - terrain_height(sim, maps, maps.village[:, None, :])
        near &= gap[..., 0] ** 2 + gap[..., 1] ** 2 + climb ** 2 < reach * reach
    return near
