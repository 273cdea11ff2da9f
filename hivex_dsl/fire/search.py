"""The nearest burning tree around query points, by pairing each query with its world's burning list."""

from __future__ import annotations

import numpy as np

from .engine import FireState, in_range, split_flat, vector


def _by_world(state: FireState) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The burning list grouped by world: (flat (K,) int64, start (B,), count (B,)) of each world's run."""
    world = state.burning // (state.cells * state.cells)
    small = np.uint16 if state.batch <= np.iinfo(np.uint16).max + 1 else np.int64  # uint16 sorts by radix
    flat = state.burning[np.argsort(world.astype(small), kind="stable")]
    count = np.bincount(world, minlength=state.batch)
    return flat, np.cumsum(count) - count, count


def _segment_min(values: np.ndarray, starts: np.ndarray) -> np.ndarray:
    """Minimum of each non-empty run ``values[starts[i]:starts[i + 1]]`` (last run to the end)."""
    return np.minimum.reduceat(values, starts) if len(starts) else values[:0]


def closest_burning(state: FireState, world: np.ndarray, rows: np.ndarray, cols: np.ndarray,
                    half_box_cells: float | np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The nearest burning cell to each of M query points within a square box around it.

    world (M,) int and rows/cols (M,) fractional cell coordinates give the queries, half_box_cells one
    number or one per query (M,). Among the burning
    cells of the query's world with |row - rows| <= half_box_cells and |col - cols| <= half_box_cells,
    returns the one closest in Euclidean cell distance, ties to the lowest flat index, as
    (found (M,) bool, row (M,) int64, col (M,) int64); row = col = -1 where nothing burns in the box.
    Work is the sum over queries of their world's burning count.
    """
    cells = state.cells
    world = vector("world", world, integer=True)
    queries = len(world)
    rows, cols = vector("rows", rows, queries), vector("cols", cols, queries)
    half = np.broadcast_to(np.asarray(half_box_cells, dtype=np.float64), (queries,))
    if not (np.isfinite(half).all() and (half >= 0.0).all()):
        raise ValueError(f"half_box_cells must be finite numbers >= 0, got {half_box_cells!r}")
    in_range("world", world, state.batch)
    flat, start, count = _by_world(state)
    per_query = count[world]
    total = int(per_query.sum())
    first = np.cumsum(per_query) - per_query  # each query's run in the pair list
    query = np.repeat(np.arange(queries), per_query)
    pair = np.arange(total) - first[query] + start[world][query]
    cell = flat[pair]
    _, row, col = split_flat(cell, cells)
    d_row, d_col = row - rows[query], col - cols[query]
    inside = (np.abs(d_row) <= half[query]) & (np.abs(d_col) <= half[query])
    distance = np.where(inside, d_row * d_row + d_col * d_col, np.inf)
    asked = np.flatnonzero(per_query > 0)
    nearest = np.full(queries, np.inf)
    nearest[asked] = _segment_min(distance, first[asked])
    found = np.isfinite(nearest)
    tied = np.where(distance == nearest[query], cell, np.iinfo(np.int64).max)
    best = np.full(queries, -1, np.int64)
    best[asked] = _segment_min(tied, first[asked])
    _, best_row, best_col = split_flat(best, cells)
    return found, np.where(found, best_row, -1), np.where(found, best_col, -1)
