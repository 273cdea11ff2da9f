"""The ground under the planes: which forest-grid cell, how high the terrain, whether a drop lands on land and
whether the drop's action mask opens. Functions of the simulator (``sim``: its params, forest grid, terrain grid,
sea level and drop rules), bound as its methods."""

from __future__ import annotations

import numpy as np

from ...base.numeric import clamp
from ...sim.grids import sample_bilinear
from ..island import SEA, IslandMaps

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
