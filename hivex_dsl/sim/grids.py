"""Fields on square grids of nodes, sampled bilinearly in batches: terrain heights, distance rasters.

``grids[b, i, j]`` is the value of world ``b`` at ``x = origin + j * cell``, ``y = origin + i * cell`` (row i
follows y, column j follows x), the convention of :class:`hivex_dsl.sim.procgen.terrain.Terrain`. Lengths in
metres. Shared by the environments that read a terrain or a raster under their agents (Drone-Based Reforestation's
drones, Aerial Wildfire Suppression's drop mask).
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import lru_cache
from typing import TYPE_CHECKING

import numpy as np

if TYPE_CHECKING:
    from .procgen.terrain import TerrainSpec


@dataclass(frozen=True)
class Grid:
    """n x n nodes spaced ``cell`` metres, the first at (origin, origin)."""

    origin: float
    cell: float
    n: int


def terrain_grid(spec: TerrainSpec) -> Grid:
    """The grid of a terrain generator spec's height map (``size`` nodes over ``extent_m``, centred on 0)."""
    return Grid(-spec.extent_m / 2.0, spec.extent_m / (spec.size - 1), spec.size)


def sample_bilinear(grids: np.ndarray, grid: Grid, xy: np.ndarray) -> np.ndarray:
    """Bilinear value (B, A) of fields ``grids`` (B, n, n) at points ``xy`` (B, A, 2), clamped at the border.

    The same surface as :meth:`Terrain.height_at` for a terrain's height grid.
    """
    return GridSet((grid,)).sample((grids,), xy)[0]


class GridSet:
    """Several grids on which the same points are sampled (:func:`sample_bilinear` on each); the points are
    placed on all of them with one set of array operations."""

    def __init__(self, grids: tuple[Grid, ...]):
        self.grids = grids

        def per_grid(values: list) -> np.ndarray:  # (grids, 1, 1, 1): broadcast over (B, A, 2) points
            return np.array(values).reshape(-1, 1, 1, 1)

        self._origin = per_grid([g.origin for g in grids])
        self._scale = per_grid([1.0 / g.cell for g in grids])
        self._top = per_grid([g.n - 1.0 for g in grids])  # the last node, as the float index is clamped
        self._cap = per_grid([g.n - 2 for g in grids])  # the last cell's lower node

    def sample(self, fields: tuple[np.ndarray, ...], xy: np.ndarray) -> list[np.ndarray]:
        """Bilinear values (B, A) of ``fields`` (one (B, n, n) array per grid) at points ``xy`` (B, A, 2)."""
        index = np.minimum(np.maximum((xy - self._origin) * self._scale, 0.0), self._top)  # (grids, B, A, 2)
        lower = np.minimum(index.astype(np.int64), self._cap)
        t = index - lower
        return [_interpolate(values, grid.n, lower[k], t[k])
                for k, (values, grid) in enumerate(zip(fields, self.grids))]


def _interpolate(grids: np.ndarray, n: int, lower: np.ndarray, t: np.ndarray) -> np.ndarray:
    """(B, A) bilinear value of ``grids`` (B, n, n) in the cells whose lower corners are ``lower`` (B, A, 2)
    (x, y node indices) at fractions ``t`` (B, A, 2) across them."""
    axis_steps, corners = _flat_offsets(len(grids), n)
    z = grids.reshape(-1)[np.dot(lower, axis_steps) + corners]  # (4, B, A) the cell's corners
    along_x = z[:2] + t[..., 0] * (z[2:] - z[:2])  # (2, B, A) at the cell's lower and upper y
    return along_x[0] + t[..., 1] * (along_x[1] - along_x[0])


def interpolation_matrix(coordinates: np.ndarray, grid: Grid) -> np.ndarray:
    """(R, n) weights of linear interpolation along one axis of ``grid`` at ``coordinates`` (R,), clamped
    like :func:`sample_bilinear`; bilinear sampling on a lattice of points is ``Wy @ grid @ Wx.T``."""
    index = np.minimum(np.maximum((coordinates - grid.origin) / grid.cell, 0.0), grid.n - 1)
    lower = np.minimum(index.astype(np.int64), grid.n - 2)
    weights = np.zeros((len(coordinates), grid.n))
    rows = np.arange(len(coordinates))
    weights[rows, lower] = 1.0 - (index - lower)
    weights[rows, lower + 1] = index - lower
    return weights


@lru_cache(maxsize=64)
def _flat_offsets(batch: int, n: int) -> tuple[np.ndarray, np.ndarray]:
    """Index steps (2,) along x and y of (B, n, n) grids, and the flat index (4, B, 1) of the four corners
    (x0 y0, x0 y1, x1 y0, x1 y1) of each world's first cell; read-only."""
    axis_steps = np.array([1, n])
    corners = np.array([0, n, 1, n + 1])[:, None, None] + (np.arange(batch) * (n * n))[:, None]
    for array in (axis_steps, corners):
        array.setflags(write=False)
    return axis_steps, corners
