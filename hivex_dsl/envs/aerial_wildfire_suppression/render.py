"""Top-down picture of one Aerial Wildfire Suppression world: island, trees by state, village, planes."""

from __future__ import annotations

import numpy as np

from ...sim.render.canvas import Canvas
from .camera import PALETTE, palette_index_at
from .params import AerialWildfireParams
from .types import AerialWildfireState

SIZE_PX = 500


def draw_island(state: AerialWildfireState, index: int, params: AerialWildfireParams) -> np.ndarray:
    """(SIZE_PX, SIZE_PX, 3) uint8 of world ``index``: ground shaded by height, trees (green existing,
    orange burning, dark burnt, blue wet), the water ring, the village ring, and each plane as a
    disk (white with water, grey without, red once out of the game: crossed the border or finished its task) with a heading pointer."""
    half = params.border_half_extent_m
    canvas = Canvas(SIZE_PX, half, background=(0, 0, 0))
    x, y = canvas.pixel_centres()
    points = np.stack([x, y], axis=-1)
    world = np.full(points.shape[:-1], index)
    picture = PALETTE[palette_index_at(points, world, state.fire.trees, state.maps.ground,
                                       params.island_half_extent_m, half)]
    canvas.fill(picture)
    village = state.maps.village[index][None]
    canvas.rings(village, params.village_radius_m, 2.0, (255, 255, 255))
    position, heading = state.position[index], state.heading[index]
    colours = np.where(state.water[index][:, None], [[255, 255, 255]], [[150, 150, 150]])
    colours = np.where(state.flying[index][:, None], colours, [[220, 30, 30]]).astype(np.uint8)
    size = 0.025 * half
    facing = np.stack([np.cos(heading), np.sin(heading)], axis=-1)
    canvas.disks(position, size, colours)
    canvas.arrows(position, facing * size * 2.5, 2.5, (10, 10, 10))
    return canvas.image()
