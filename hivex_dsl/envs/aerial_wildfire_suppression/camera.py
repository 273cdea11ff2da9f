"""Colours of the island and the planes' 42x42 RGB downward cameras, by array gathers.

A pixel's colour is a palette entry: the ground index of its forest cell, or the tree state
drawn over it, or the water ring, or the dark outside of the border. One palette serves the
cameras (float32 in [0, 1]) and the top-down render (uint8).
"""

from __future__ import annotations

import numpy as np

from ...sim.fire import TreeState
from ..island import LAND_SHADES, SEA, VILLAGE

WATER_RING = VILLAGE + 1
OUTSIDE = VILLAGE + 2
TREE_BASE = VILLAGE + 3  # palette index of tree state s is TREE_BASE + s
TREE_COLOURS = {
    TreeState.EXISTING: (34, 110, 40),
    TreeState.BURNING: (235, 80, 20),
    TreeState.BURNT: (45, 40, 38),
    TreeState.WET: (60, 120, 230),
}


def palette() -> np.ndarray:
    """(TREE_BASE + 5, 3) uint8 colours of every palette index."""
    colours = np.zeros((TREE_BASE + len(TreeState), 3), np.uint8)
    t = np.linspace(0.0, 1.0, LAND_SHADES)[:, None]
    low, high = np.array([196, 186, 120]), np.array([150, 130, 110])  # sandy lowland -> brown-grey heights
    colours[:LAND_SHADES] = np.round(low + (high - low) * t).astype(np.uint8)
    colours[SEA] = (70, 130, 180)
    colours[VILLAGE] = (220, 60, 200)
    colours[WATER_RING] = (40, 90, 170)
    colours[OUTSIDE] = (15, 20, 40)
    for state, rgb in TREE_COLOURS.items():
        colours[TREE_BASE + state] = rgb
    return colours


PALETTE = palette()
PALETTE_FLOAT = PALETTE.astype(np.float32) / 255.0


def pixel_offsets(pixels: int, pixel_m: float) -> tuple[np.ndarray, np.ndarray]:
    """(P*P,) float32 forward and rightward metres of each camera pixel centre from the plane, row 0 ahead."""
    centre = (pixels - 1) / 2.0
    rows, cols = np.meshgrid(np.arange(pixels), np.arange(pixels), indexing="ij")
    return (((centre - rows) * pixel_m).ravel().astype(np.float32),
            ((cols - centre) * pixel_m).ravel().astype(np.float32))


def palette_index_at(points: np.ndarray, world: np.ndarray, trees: np.ndarray, ground: np.ndarray,
                     island_half_m: float, border_half_m: float) -> np.ndarray:
    """uint8 palette index at ``points`` (..., 2) metres of worlds ``world`` (...) given trees/ground (B, C, C)."""
    return _palette_index(points[..., 0], points[..., 1], world, trees, ground, island_half_m, border_half_m)


def _palette_index(x: np.ndarray, y: np.ndarray, world: np.ndarray, trees: np.ndarray, ground: np.ndarray,
                   island_half_m: float, border_half_m: float) -> np.ndarray:
    cells = trees.shape[-1]
    per_m = cells / (2.0 * island_half_m)
    col = np.floor((x + island_half_m) * per_m).astype(np.int32)
    row = np.floor((y + island_half_m) * per_m).astype(np.int32)
    # negative values wrap to huge unsigned ones, so one comparison per axis tests both bounds
    on_island = (col.view(np.uint32) < cells) & (row.view(np.uint32) < cells)
    np.clip(col, 0, cells - 1, out=col)
    np.clip(row, 0, cells - 1, out=row)
    flat = (world * cells + row).astype(np.int64) * cells + col
    state = trees.reshape(-1).take(flat)
    index = np.where(state > 0, state + np.uint8(TREE_BASE), ground.reshape(-1).take(flat))
    if not on_island.all():
        inside = (np.abs(x) <= border_half_m) & (np.abs(y) <= border_half_m)
        index = np.where(on_island, index, np.where(inside, np.uint8(WATER_RING), np.uint8(OUTSIDE)))
    return index


def cameras(position: np.ndarray, heading: np.ndarray, trees: np.ndarray, ground: np.ndarray,
            offsets: tuple[np.ndarray, np.ndarray], island_half_m: float, border_half_m: float) -> np.ndarray:
    """(B, A, P, P, 3) float32 in [0, 1]: each plane's downward view, forward up, centred under it."""
    batch, agents = heading.shape
    forward, right = offsets
    cos, sin = np.cos(heading).astype(np.float32)[..., None], np.sin(heading).astype(np.float32)[..., None]
    px, py = position[..., 0:1].astype(np.float32), position[..., 1:2].astype(np.float32)
    x = px + forward * cos + right * sin
    y = py + forward * sin - right * cos
    world = np.arange(batch, dtype=np.int32)[:, None, None]
    index = _palette_index(x, y, world, trees, ground, island_half_m, border_half_m)
    pixels = int(round(np.sqrt(forward.size)))
    return PALETTE_FLOAT.take(index, axis=0).reshape(batch, agents, pixels, pixels, 3)
