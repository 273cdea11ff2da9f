"""A summary of each world's fire for the global state (:mod:`hivex_dsl.runtime.global_state`): size, front, status.

Computed from the burning list alone (O(K) for K burning trees, never a scan of the (B, C, C) grid), at the cell
centres of the burning trees (their jitter ignored, as the engine's searches do).
"""

from __future__ import annotations

import numpy as np

from ...base import portable
from .engine import FireState, split_flat

FIRE_FACTS = 5  # values of fire_summary per world
SQRT2 = float(np.sqrt(2.0))


def burning_share(count: np.ndarray | int, cells: int) -> np.ndarray:
    """log(1 + n) / log(1 + C^2) for n burning trees (any shape) on the C x C grid, the same bits on every
    processor (:mod:`hivex_dsl.base.portable`)."""
    return portable.log(1.0 + np.asarray(count, dtype=np.float64)) / portable.log(1.0 + cells * cells)


def fire_summary(fire: FireState, half_extent_m: float, spacing_m: float) -> np.ndarray:
    """(B, 5) float64 per world, each in its stated range:

    0. burning: log(1 + n) / log(1 + C^2) in [0, 1] for n burning trees on the C x C grid (a log scale: a fire
       of 10 trees and one of 10,000 both read clearly);
    1-2. front centre: the burning trees' mean (x, y) / half extent in [-1, 1] (0 without fire);
    3. front spread: their root-mean-square distance from that centre / (sqrt(2) x half extent) in [0, 1];
    4. out: 1 once the world's fire is out (nothing burns and it stayed quiet long enough), else 0.
    """
    batch, cells = fire.batch, fire.cells
    world, row, col = split_flat(fire.burning, cells)
    x = (col + 0.5) * spacing_m - half_extent_m
    y = (row + 0.5) * spacing_m - half_extent_m
    count = np.bincount(world, minlength=batch).astype(np.float64)
    n = np.maximum(count, 1.0)
    mean_x = np.bincount(world, weights=x, minlength=batch) / n
    mean_y = np.bincount(world, weights=y, minlength=batch) / n
    square = np.bincount(world, weights=x * x + y * y, minlength=batch) / n
    spread = np.sqrt(np.maximum(square - mean_x * mean_x - mean_y * mean_y, 0.0))
    out = np.empty((batch, FIRE_FACTS))
    out[:, 0] = burning_share(count, cells)
    out[:, 1] = mean_x / half_extent_m
    out[:, 2] = mean_y / half_extent_m
    out[:, 3] = spread / (SQRT2 * half_extent_m)
    out[:, 4] = fire.out
    np.clip(out[:, 1:3], -1.0, 1.0, out=out[:, 1:3])  # rounding only: the cell centres lie inside the grid
    np.clip(out[:, 3], 0.0, 1.0, out=out[:, 3])
    return out


def nearest_burning_distance(fire: FireState, points: np.ndarray, half_extent_m: float, spacing_m: float
                             ) -> np.ndarray:
    """(B,) float64 metres from ``points`` (B, 2) (one point per world, e.g. its village) to the nearest burning
    tree's cell centre of the same world; inf where nothing burns."""
    world, row, col = split_flat(fire.burning, fire.cells)
    x = (col + 0.5) * spacing_m - half_extent_m
    y = (row + 0.5) * spacing_m - half_extent_m
    nearest = np.full(fire.batch, np.inf)
    np.minimum.at(nearest, world, np.hypot(x - points[world, 0], y - points[world, 1]))
    return nearest
