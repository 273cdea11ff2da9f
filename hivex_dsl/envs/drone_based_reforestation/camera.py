"""The downward grayscale camera: a per-world raster drawn at reset, sampled by gathering.

Each world has a (R, R) uint8 raster of square cells ``cell`` metres wide covering the world,
``raster[b, i, j]`` for the cell whose centre is ``x = -half + (j + 0.5) cell``,
``y = -half + (i + 0.5) cell``. It holds ground shaded by height, existing trees, planted trees
(stamped in when they grow) and the station pad, on the gray levels below. A camera image is
16 x 16 samples of it on a square footprint centred below the drone, north up ([ours]: a
gimbal-stabilised camera; the drone's heading is in the vector observation), whose half width
grows with the height above ground.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import lru_cache

import numpy as np

PIXELS = 16  # [paper] 16 x 16 x 1 (the process diagram's prose says 32 x 32; the spec table wins)
GROUND_LOW, GROUND_HIGH = 0.40, 0.90  # ground at height 0 and at the height bound
TREE_GRAY = 0.10
NEW_TREE_GRAY = 0.25
STATION_GRAY = 1.00
TREE_BELOW = 0.175  # a camera value below this is an existing tree
NEW_TREE_BELOW = 0.325  # ... and below this (and not an existing tree) a planted tree

_TO_UNIT = np.arange(256, dtype=np.float32) / np.float32(255.0)


def to_byte(gray: np.ndarray | float) -> np.ndarray:
    """Gray levels in [0, 1] -> uint8 raster values."""
    return np.rint(np.clip(gray, 0.0, 1.0) * 255.0).astype(np.uint8)


def pixel_offsets() -> np.ndarray:
    """(PIXELS,) pixel centres as fractions of the footprint half width, from -1 to 1 (exclusive).

    Column c looks at ``x + hw * offsets[c]``; row r looks at ``y - hw * offsets[r]`` (row 0 is north).
    """
    return (np.arange(PIXELS) + 0.5) / PIXELS * 2.0 - 1.0


_UNIT = pixel_offsets()
_SIGNED_UNIT = np.stack([_UNIT, -_UNIT])  # (2, PIXELS): x offsets of the columns, y offsets of the rows


@dataclass(frozen=True)
class Raster:
    """Geometry of the camera raster: ``n`` x ``n`` cells of ``cell`` metres over +/- ``half`` metres."""

    half: float
    cell: float
    n: int

    @classmethod
    def covering(cls, half_extent: float, cell: float) -> "Raster":
        return cls(half_extent, cell, int(np.ceil(2.0 * half_extent / cell - 1e-9)))

    def centres(self) -> np.ndarray:
        """(n,) cell centre coordinates (x of columns, y of rows)."""
        return -self.half + (np.arange(self.n) + 0.5) * self.cell

    def index(self, coordinate: np.ndarray) -> np.ndarray:
        """Cell index of coordinates, clamped to the raster."""
        # Truncation differs from floor only below 0, where the clamp gives 0 either way.
        index = ((coordinate + self.half) / self.cell).astype(np.int64)
        np.maximum(index, 0, out=index)
        return np.minimum(index, self.n - 1, out=index)


def ground_shade(heights: np.ndarray, height_bound: float) -> np.ndarray:
    """Gray level of bare ground at ``heights`` metres (any shape)."""
    return GROUND_LOW + (GROUND_HIGH - GROUND_LOW) * np.clip(heights / height_bound, 0.0, 1.0)


def stamp_disks(rasters: np.ndarray, raster: Raster, worlds: np.ndarray, centres: np.ndarray, radius: float,
                gray: float) -> None:
    """Paint disks of ``radius`` metres at ``centres`` (N, 2) into ``rasters[worlds]`` (N,), in place.

    A cell is painted when its centre lies within the radius, and the cell holding each centre always.
    """
    if len(centres) == 0:
        return
    reach = int(np.ceil(radius / raster.cell))
    offsets = np.arange(-reach, reach + 1)
    col = raster.index(centres[:, 0])[:, None, None] + offsets[None, None, :]
    row = raster.index(centres[:, 1])[:, None, None] + offsets[None, :, None]
    col, row = np.broadcast_arrays(col, row)
    cx = -raster.half + (col + 0.5) * raster.cell - centres[:, 0, None, None]
    cy = -raster.half + (row + 0.5) * raster.cell - centres[:, 1, None, None]
    hit = (cx * cx + cy * cy <= radius * radius) | ((col == col[:, reach:reach + 1, reach:reach + 1])
                                                    & (row == row[:, reach:reach + 1, reach:reach + 1]))
    hit &= (col >= 0) & (col < raster.n) & (row >= 0) & (row < raster.n)
    world = np.broadcast_to(worlds[:, None, None], hit.shape)
    rasters[world[hit], row[hit], col[hit]] = to_byte(gray)


def camera_images(rasters: np.ndarray, raster: Raster, xy: np.ndarray, half_width: np.ndarray) -> np.ndarray:
    """(B, A, 16, 16, 1) float32 in [0, 1]: the camera of each drone at ``xy`` (B, A, 2) with footprint
    half width ``half_width`` (B, A) metres, sampled (nearest cell) from ``rasters`` (B, n, n) uint8."""
    # Columns look at x + hw * offset, rows at y - hw * offset = y + hw * (-offset): both axes at once.
    cells = raster.index(xy[..., None] + half_width[..., None, None] * _SIGNED_UNIT)  # (B, A, 2, 16)
    rows = cells[..., 1, :] * raster.n + _world_starts(len(rasters), raster.n)  # (B, A, 16) flat row starts
    flat = rows[..., :, None] + cells[..., 0, None, :]
    return _TO_UNIT.take(rasters.reshape(-1)[flat])[..., None]


@lru_cache(maxsize=32)
def _world_starts(batch: int, n: int) -> np.ndarray:
    """(B, 1, 1) read-only flat index of each world's first cell in (B, n, n) rasters."""
    starts = (np.arange(batch) * (n * n))[:, None, None]
    starts.setflags(write=False)
    return starts
