"""Distances to trees, the hidden fertility field and the seed-drop equations of the paper.

Fields live on the square grids of :mod:`hivex_dsl.sim.grids` (row i follows y, column j follows x). Lengths in
metres.

The fertility of a point is the paper's seed quality without its new-tree condition:
``Remap(det, dot_min, dot_max, 1, 0)`` where ``dot_min <= det <= dot_max`` and 0 elsewhere,
``det`` being the distance to the nearest existing tree. It is highest just outside the forest
edge. Per step it is read from a raster of ``det`` computed at reset; seed drops (rare events)
use the exact distance to the jittered trees.
"""

from __future__ import annotations

import numpy as np

from ...sim.grids import Grid

FAR_M = 1.0e6  # position of an empty tree slot: farther than anything in the world


def forest_grid(forest) -> Grid:
    """The grid of a forest generator spec's cell centres, on which the tree-distance raster lives."""
    return Grid(-forest.half_extent_m + forest.spacing_m / 2.0, forest.spacing_m, forest.cells)


def _nearest_in_rows(occupied: np.ndarray, cap: int) -> np.ndarray:
    """(B, m, m) cells from each cell to the nearest occupied cell of its own row, at most ``cap``."""
    m = occupied.shape[-1]
    index = np.arange(m)
    left = np.maximum.accumulate(np.where(occupied, index, -cap - m), axis=-1)
    right = np.minimum.accumulate(np.where(occupied, index, m + cap)[..., ::-1], axis=-1)[..., ::-1]
    return np.minimum(np.minimum(index - left, right - index), cap)


def tree_distance_raster(occupied: np.ndarray, spacing_m: float, reach_m: float) -> np.ndarray:
    """Distance (B, m, m) float32 from each cell centre to the nearest occupied cell centre, in metres.

    ``occupied`` (B, m, m) bool marks cells holding a tree. Exact Euclidean distances between cell
    centres up to ``reach_m``; farther cells get the first multiple of the spacing beyond it.
    Separable: nearest occupied column per row, then the minimum over rows within reach.
    """
    reach = int(np.ceil(reach_m / spacing_m)) + 1
    along_row = _nearest_in_rows(occupied, reach).astype(np.float32) ** 2
    best = np.full(occupied.shape, np.float32(reach * reach), np.float32)
    m = occupied.shape[1]
    for offset in range(-reach + 1, reach):
        lo, hi = max(0, -offset), min(m, m - offset)
        if lo >= hi:
            continue
        candidate = along_row[:, lo + offset:hi + offset] + np.float32(offset * offset)
        np.minimum(best[:, lo:hi], candidate, out=best[:, lo:hi])
    return np.sqrt(best) * np.float32(spacing_m)


def fertility(distance: np.ndarray, min_m: float, max_m: float) -> np.ndarray:
    """The paper's Remap(det, dot_min, dot_max, 1, 0) where dot_min <= det <= dot_max, else 0."""
    inside = (distance >= min_m) & (distance <= max_m)
    return np.where(inside, (max_m - distance) / (max_m - min_m), 0.0)


def nearest_tree_distance(tree_xy: np.ndarray, forest: Grid, worlds: np.ndarray, points: np.ndarray,
                          reach_m: float) -> np.ndarray:
    """Exact distance (M,) from ``points`` (M, 2) of worlds ``worlds`` (M,) to the nearest existing tree.

    ``tree_xy`` (B, m, m, 2) holds each cell's tree (FAR_M where empty); ``forest`` is the grid of
    cell centres. Exact up to ``reach_m``; points with no tree that close get inf.
    """
    m = tree_xy.shape[1]
    half = int(np.ceil(reach_m / forest.cell)) + 1
    offsets = np.arange(-half, half + 1)
    col = np.rint((points[:, 0] - forest.origin) / forest.cell).astype(np.int64)
    row = np.rint((points[:, 1] - forest.origin) / forest.cell).astype(np.int64)
    rows = row[:, None, None] + offsets[None, :, None]
    cols = col[:, None, None] + offsets[None, None, :]
    inside = (rows >= 0) & (rows < m) & (cols >= 0) & (cols < m)
    found = tree_xy[worlds[:, None, None], np.clip(rows, 0, m - 1), np.clip(cols, 0, m - 1)]
    gap = found.astype(np.float64) - points[:, None, None, :]
    squared = np.where(inside, np.einsum("mijd,mijd->mij", gap, gap), np.inf)
    nearest = np.sqrt(squared.reshape(len(points), -1).min(axis=1, initial=np.inf))
    return np.where(nearest <= reach_m, nearest, np.inf)


def logged_tree_distance(tree_xy: np.ndarray, worlds: np.ndarray, points: np.ndarray, near: np.ndarray
                         ) -> np.ndarray:
    """det (M,) of drops at ``points`` (M, 2) of worlds ``worlds`` (M,), exact at any distance, as Cumulative
    Distance to Existing Trees logs it: ``near`` (:func:`nearest_tree_distance`'s result) where it found a tree,
    else the nearest tree of the whole forest (a search of every cell, for the few drops that need it); 0 in a
    world without trees, where there is no distance to log."""
    far = np.isinf(near)
    if not np.count_nonzero(far):
        return near
    flat = tree_xy.reshape(len(tree_xy), -1, 2)[worlds[far]]  # (F, m * m, 2)
    gap = flat.astype(np.float64) - points[far][:, None, :]
    nearest = np.sqrt(np.einsum("fcd,fcd->fc", gap, gap).min(axis=1, initial=np.inf))
    logged = near.copy()
    logged[far] = np.where(nearest < FAR_M, nearest, 0.0)  # only empty slots (at FAR_M): no tree at all
    return logged


def nearest_new_tree_distance(new_trees: np.ndarray, worlds: np.ndarray, points: np.ndarray) -> np.ndarray:
    """Distance (M,) from ``points`` (M, 2) to the nearest planted tree of their worlds (inf if none).

    ``new_trees`` (B, C, 2) holds planted trees, FAR_M in empty slots.
    """
    gap = new_trees[worlds] - points[:, None, :].astype(np.float32)
    return np.sqrt(np.einsum("mcd,mcd->mc", gap, gap).min(axis=1, initial=np.inf).astype(np.float64))


def seed_reward(det: np.ndarray, dnt: np.ndarray, min_m: float, max_m: float, multiplier: float) -> np.ndarray:
    """r_s: sdrm * Remap(det, dot_min, dot_max, 1, 0) if dot_min <= det <= dot_max and dnt >= dot_min, else 0."""
    grows = (det >= min_m) & (det <= max_m) & (dnt >= min_m)
    return np.where(grows, multiplier * (max_m - np.minimum(det, max_m)) / (max_m - min_m), 0.0)


def distance_reward(seed: np.ndarray, station_distance: np.ndarray, half_extent_m: float,
                    multiplier: float) -> np.ndarray:
    """r_d: drm * sdd / ew when r_s > 0, else 0; sdd / ew is capped at 1 (the square's corners lie beyond ew)."""
    return np.where(seed > 0.0, multiplier * np.minimum(station_distance / half_extent_m, 1.0), 0.0)


def storage_slots(count: np.ndarray, world: np.ndarray) -> np.ndarray:
    """(M,) storage slot of each of M seeds planted this step: its world's ``count`` (B,) plus its rank
    among this step's seeds of the same world (``world`` (M,) sorted, as np.nonzero gives it)."""
    return count[world] + np.arange(len(world)) - np.searchsorted(world, world)


def same_step_distance(world: np.ndarray, points: np.ndarray) -> np.ndarray:
    """(M,) distance from each of M seeds planted this step to the nearest one planted by a drone earlier in
    agent order (lower index) in the same world, inf if none: same-step seeds are new trees too."""
    gap = points[:, None, :] - points[None, :, :]
    distance = np.sqrt(np.einsum("ijd,ijd->ij", gap, gap))
    order = np.arange(len(world))
    earlier = (world[:, None] == world[None, :]) & (order[None, :] < order[:, None])
    return np.where(earlier, distance, np.inf).min(axis=1, initial=np.inf)
