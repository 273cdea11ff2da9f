"""Top-down picture of one Wildfire Resource Management world: island and fire, towers coloured by support.

The island uses Aerial Wildfire Suppression's palette (ground shaded by height, sea blue, village
magenta, trees green/orange/dark for existing/burning/burnt).
"""

from __future__ import annotations

import numpy as np

from ...sim.render.canvas import Canvas, colormap
from ..aerial_wildfire_suppression.camera import PALETTE, palette_index_at
from .params import WildfireResourceParams
from .resources import TARGETS, TENTHS
from .types import WildfireResourceState

SIZE_PX = 500
TOWER_RADIUS_FRACTION = 0.045  # of the island's half extent
LINK_SIDE_M = 12.0  # a link a -> b runs this far to the side of b -> a, so both show
SUPPORT_SCALE = 3.0  # resource units at the top of the tower colour scale (the centre could reach 9)


def _links(state: WildfireResourceState, index: int, towers: np.ndarray):
    """Tails (L, 2), vectors (L, 2) and amounts (L,) in tenths of every resource a tower gives a neighbour."""
    given = state.allocation[index][:, 1:]  # (A, 3)
    giver, slot = np.nonzero(given > 0)
    start, end = towers[giver], towers[TARGETS[giver, slot + 1]]
    along = end - start
    length = np.linalg.norm(along, axis=-1, keepdims=True)
    unit = along / np.maximum(length, 1e-9)
    side = np.stack([unit[:, 1], -unit[:, 0]], axis=-1) * LINK_SIDE_M
    shrink = 0.2 * length  # leave the disks free at both ends
    return start + unit * shrink + side, along - 2.0 * unit * shrink, given[giver, slot]


def draw_towers(state: WildfireResourceState, index: int, params: WildfireResourceParams,
                towers: np.ndarray) -> np.ndarray:
    """(SIZE_PX, SIZE_PX, 3) uint8 of world ``index``: the island with its trees; an orange line from each
    tower to the closest fire it sees (red outline while that fire approaches); white arrows from a tower to
    each neighbour it gives resources (width by amount); each tower a disk coloured by its total support
    (viridis, dark = nothing, yellow = SUPPORT_SCALE or more) with the share it keeps as a white core."""
    half = params.island_half_extent_m
    canvas = Canvas(SIZE_PX, half, background=(0, 0, 0))
    x, y = canvas.pixel_centres()
    points = np.stack([x, y], axis=-1)
    index_map = palette_index_at(points, np.full(points.shape[:-1], index), state.fire.trees, state.maps.ground,
                                 half, half)
    canvas.fill(PALETTE[index_map])
    sighting = state.sighting
    seen = sighting.seen[index]
    radius = TOWER_RADIUS_FRACTION * half
    if seen.any():
        fire = towers[seen] + sighting.offset[index][seen][:, :2]
        canvas.segments(towers[seen], fire, 2.0, (255, 140, 0))
        canvas.disks(fire, 0.3 * radius, (255, 60, 0))
    tails, vectors, amounts = _links(state, index, towers)
    if len(tails):
        canvas.arrows(tails, vectors, 1.0 + 4.0 * amounts / TENTHS, (245, 245, 245))
    outline = np.where(sighting.approaching[index][:, None], [[230, 30, 30]], [[20, 20, 20]]).astype(np.uint8)
    canvas.disks(towers, radius * 1.25, outline)
    canvas.disks(towers, radius, colormap(state.support[index] / TENTHS, 0.0, SUPPORT_SCALE))
    own = state.allocation[index][:, 0] / TENTHS
    keeps = own > 0
    if keeps.any():
        canvas.disks(towers[keeps], 0.5 * radius * np.sqrt(own[keeps]), (255, 255, 255))
    return canvas.image()
