"""The nearest burning tree around query points.

Each query is paired with candidate burning cells of its world, and the nearest candidate inside its box
wins. Any candidate set holding every burning cell of the box gives the same answer, so the pairing is
picked by cost: every burning cell of the query's world when that is little work (no index to build; one
world with few pairs tests them all as one dense (queries, burning) box test), or only the cells of the
coarse blocks its box overlaps (:mod:`.blocks`) when fronts are large.
"""

from __future__ import annotations

from typing import Callable

import numpy as np

from .blocks import block_pairs, block_side
from .engine import FireState, in_range, split_flat, vector

SMALL_WORK = 8000  # up to about this many pairs (plus K / 8) the plain pairing beats building the block index
HUGE = 2.0**40  # beyond this, coordinates lose the precision that the one-cell margin of a span relies on
ONE_WORLD_PAIRS = 65_536  # a single world's queries x burning cells up to this go through one (M, K) box test
_BOTH = np.uint16(0x0101)  # two adjacent True bytes read as one uint16, on either byte order


def _world_pairs(flat: np.ndarray, burning_world: np.ndarray, count: np.ndarray, world: np.ndarray,
                 cells: int) -> tuple[np.ndarray, np.ndarray, np.ndarray, Callable]:
    """Every query (M,) paired with every burning cell of its world, as :func:`.blocks.block_pairs` returns."""
    radix = np.uint16 if len(count) <= np.iinfo(np.uint16).max + 1 else np.int64  # uint16 sorts by radix
    grouped = flat[np.argsort(burning_world.astype(radix), kind="stable")]
    per_query = count[world]
    first = np.cumsum(per_query) - per_query
    pair = np.repeat((np.cumsum(count) - count)[world] - first, per_query)
    pair += np.arange(len(pair), dtype=pair.dtype)
    _, row, col = split_flat(grouped[pair].astype(np.int64), cells)

    def cell_of(pairs: np.ndarray) -> np.ndarray:
        return row[pairs] * cells + col[pairs]

    return np.repeat(np.arange(len(world)), per_query), row.astype(np.float64), col.astype(np.float64), cell_of


def _spans(centre: np.ndarray, half: np.ndarray, cells: int) -> tuple[np.ndarray, np.ndarray]:
    """(first, last) (M,) int64 cells within [0, C) of a span that holds every cell within ``half`` of ``centre``.

    One cell wider on each side than the exact bounds, so the rounding of ``centre -/+ half`` can never
    leave out a cell that the exact float test of :func:`_nearest` accepts.
    """
    huge = (np.abs(centre) > HUGE) | (half > HUGE)
    with np.errstate(over="ignore"):  # huge spans may overflow to inf here; they take the whole grid
        first = np.where(huge, 0.0, np.clip(np.floor(centre - half) - 1.0, 0.0, cells - 1.0))
        last = np.where(huge, cells - 1.0, np.clip(np.floor(centre + half) + 1.0, 0.0, cells - 1.0))
    return first.astype(np.int64), last.astype(np.int64)


def _nearest(query: np.ndarray, row: np.ndarray, col: np.ndarray, cell_of: Callable, rows: np.ndarray,
             cols: np.ndarray, half: float | np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(found (M,) bool, row * C + col (M,) int64 of the nearest cell) from candidate pairs query, row, col (P,).

    ``half`` is one number or one per query (M,). Pairs outside their box are ignored; ties go to the
    lowest row * C + col of ``cell_of(pairs)``, ordered as the flat index since a query's pairs share a
    world. Consumes ``row`` and ``col`` (float64, so offsets round exactly as ``row - rows`` does): the
    pair arrays are large and fresh pages are slow (the kernel zeroes each), so the work is in place.
    """
    d_row, d_col, scratch = row, col, np.take(rows, query)
    d_row -= scratch
    d_col -= np.take(cols, query, out=scratch)
    half = half[query] if np.ndim(half) else half
    outside = np.abs(d_row, out=scratch) > half
    outside |= np.abs(d_col, out=scratch) > half
    distance = np.multiply(d_row, d_row, out=d_row)
    distance += np.multiply(d_col, d_col, out=d_col)
    distance[outside] = np.inf
    nearest = np.full(len(rows), np.inf)
    np.minimum.at(nearest, query, distance)
    found = np.isfinite(nearest)
    tied = np.flatnonzero(distance == np.take(np.where(found, nearest, -1.0), query, out=scratch))
    best = np.full(len(rows), np.iinfo(np.int64).max)
    np.minimum.at(best, query[tied], cell_of(tied))
    return found, best


def _closest_in_one_world(flat: np.ndarray, cells: int, at: np.ndarray, half: float | np.ndarray
                          ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """:func:`closest_burning` of one world: every query against every burning cell in one (M, K) box
    test, then the nearest among the few pairs inside. ``at`` (M, 1) complex128 holds each query as
    cols + i rows; ``half`` is one number or (M,).

    Each entry of the box test is the complex gap (col - cols) + i (row - rows): one subtraction forms
    both float64 offsets exactly as :func:`_nearest` does (int cells convert exactly), and the distances
    and ties follow it, so the answers are identical. Most queries see no fire: four passes answer them.
    """
    queries, burning = len(at), len(flat)
    if burning == 0:
        return _nothing_found(queries)
    cell = np.empty(burning, np.complex128)
    np.divmod(flat, cells, out=(cell.imag, cell.real), casting="unsafe")
    gap = np.subtract(cell, at)  # (M, K)
    box = half[:, None] if np.ndim(half) else half
    near = np.abs(gap.view(np.float64)) <= box  # (M, 2K): |d_col|, |d_row| within the box, side by side
    hit = np.flatnonzero(near.view(np.uint16) == _BOTH)  # query-major pairs inside their box
    if hit.size == 0:
        return _nothing_found(queries)
    query, tree = np.divmod(hit, burning)
    offset = gap.reshape(-1).take(hit).view(np.float64)
    square = np.multiply(offset, offset, out=offset)
    distance = np.add(square[1::2], square[0::2])  # d_row^2 + d_col^2
    nearest = np.full(queries, np.inf)
    np.minimum.at(nearest, query, distance)
    tied = distance == nearest.take(query)
    best = np.full(queries, np.iinfo(np.int64).max)
    np.minimum.at(best, query[tied], flat.take(tree[tied]))
    found = nearest < np.inf
    best_row = best // cells
    return found, np.where(found, best_row, -1), np.where(found, best - best_row * cells, -1)


def _nothing_found(queries: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    none = np.full(queries, -1, np.int64)
    return np.zeros(queries, bool), none, none.copy()


def closest_burning(state: FireState, world: np.ndarray, rows: np.ndarray, cols: np.ndarray,
                    half_box_cells: float | np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The nearest burning cell to each of M query points within a square box around it.

    world (M,) int and rows/cols (M,) fractional cell coordinates give the queries, half_box_cells one
    number or one per query (M,). Among the burning
    cells of the query's world with |row - rows| <= half_box_cells and |col - cols| <= half_box_cells,
    returns the one closest in Euclidean cell distance, ties to the lowest flat index, as
    (found (M,) bool, row (M,) int64, col (M,) int64); row = col = -1 where nothing burns in the box.
    Work is a few passes over the burning list plus, per query, about the burning cells of the blocks
    its box overlaps (or of its whole world, when that is less work than indexing the blocks).
    """
    world = vector("world", world, integer=True)
    queries = len(world)
    rows, cols = vector("rows", rows, queries), vector("cols", cols, queries)
    half = np.asarray(half_box_cells, dtype=np.float64)
    half = np.full(queries, half) if half.ndim == 0 else np.broadcast_to(half, (queries,))
    if not np.logical_and.reduce((half >= 0.0) & (half < np.inf), axis=None):  # NaN fails both
        raise ValueError(f"half_box_cells must be finite numbers >= 0, got {half_box_cells!r}")
    in_range("world", world, state.batch)
    box = float(half[0]) if np.ndim(half_box_cells) == 0 and queries else half
    return closest_burning_unchecked(state, world, rows, cols, box)


def closest_burning_unchecked(state: FireState, world: np.ndarray, rows: np.ndarray, cols: np.ndarray,
                              half_box_cells: float | np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """:func:`closest_burning` without its argument checks, for callers whose queries are valid by
    construction: world (M,) int64 in [0, B), rows/cols (M,) finite float64, half_box_cells one finite
    float >= 0 or (M,) float64 of them."""
    cells, batch = state.cells, state.batch
    queries, half = len(world), half_box_cells
    if batch == 1 and queries * len(state.burning) <= ONE_WORLD_PAIRS:
        at = np.empty((queries, 1), np.complex128)
        at.real[:, 0], at.imag[:, 0] = cols, rows
        return _closest_in_one_world(state.burning, cells, at, half)
    index = np.int32 if batch * cells * cells <= np.iinfo(np.int32).max else np.int64
    flat = state.burning.astype(index, copy=False)
    burning_world = flat // index(cells * cells)
    small = len(flat) // 8 <= SMALL_WORK  # then sorting the burning list by world is cheap
    count = np.bincount(burning_world, minlength=batch) if small else None
    if small and int(count[world].sum()) + len(flat) // 8 <= SMALL_WORK:
        pairs = _world_pairs(flat, burning_world, count, world, cells)
    else:
        per_query = np.broadcast_to(half, (queries,))
        spans = (*_spans(rows, per_query, cells), *_spans(cols, per_query, cells))
        side = block_side(cells, batch, len(flat), spans)
        if small and side == cells:  # whole worlds: the plain pairing, without the index's overhead
            pairs = _world_pairs(flat, burning_world, count, world, cells)
        else:
            pairs = block_pairs(flat, burning_world, cells, batch, world, spans, side)
    found, best = _nearest(*pairs, rows, cols, half)
    best_row = best // cells
    return found, np.where(found, best_row, -1), np.where(found, best - best_row * cells, -1)


def closest_burning_at(state: FireState, world: np.ndarray, points: np.ndarray, half_box_cells: float | np.ndarray
                       ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """:func:`closest_burning_unchecked` of query ``points`` (M, 2) C-contiguous float64 (col, row) cell
    coordinates: a single world reads them in place, as the complex numbers cols + i rows."""
    if state.batch == 1 and len(points) * len(state.burning) <= ONE_WORLD_PAIRS:
        return _closest_in_one_world(state.burning, state.cells, points.view(np.complex128), half_box_cells)
    return closest_burning_unchecked(state, world, points[:, 1], points[:, 0], half_box_cells)
