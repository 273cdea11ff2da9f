"""A coarse block index over the burning list: pair each query only with the burning cells near its box.

The grid of every world is cut into ``side x side`` blocks of cells (the last block of a row or column
may be cut short by the grid edge). Each query lists the blocks its box overlaps; each burning cell then
pairs with the queries listing its block. Building this costs a few passes over the burning list and
over the (query, block) entries, with no sort of the burning list, so a query costs about the burning
cells of its box rather than of its whole world. Used by :func:`.search.closest_burning`.
"""

from __future__ import annotations

import functools
from typing import Callable

import numpy as np

MIN_SIDE = 4  # smaller blocks make more (query, block) entries than they save pairs
ENTRY_COST = 2.0  # a (query, block) entry costs about as much work as this many pairs
SAMPLE = 256  # queries whose spans choose the block side
GOLDEN = (5**0.5 - 1) / 2  # its multiples modulo 1 spread evenly: a sample without aliasing (unlike a stride)


@functools.lru_cache(maxsize=16)
def _block_of_cell(cells: int, side: int, dtype: type) -> np.ndarray:
    """(C * C,) ``dtype``: the block (row-major among ceil(C / side)^2) of each cell of one world."""
    per = -(-cells // side)
    band = np.arange(cells) // side
    table = (band[:, None] * per + band[None, :]).reshape(-1).astype(dtype)
    table.flags.writeable = False
    return table


def block_side(cells: int, batch: int, burning: int, spans: tuple[np.ndarray, ...]) -> int:
    """Block side in cells for ``burning`` burning cells over ``batch`` worlds and the queries' cell ``spans``.

    With density d burning cells per cell, a box of width W costs about (W / s + 1)^2 entries plus
    d (W + s)^2 pairs, least near s = (W / d)^(1/3); but boxes cut by the grid edge may cover all of
    it in a few blocks, so that side competes with a few coarser ones, whole worlds (s = C) included,
    on the entries and pairs they would make for up to SAMPLE of the queries (ENTRY_COST pairs per entry,
    uniform density).
    """
    queries = len(spans[0])
    if queries > SAMPLE:
        sample = (np.arange(SAMPLE) * GOLDEN % 1.0 * queries).astype(np.int64)
        spans = tuple(span[sample] for span in spans)
    first_row, last_row, first_col, last_col = spans
    density = max(burning, 1) / (batch * cells * cells)
    width = float(np.mean(last_row - first_row + last_col - first_col)) / 2.0 + 1.0 if len(first_row) else 1.0
    balanced = min(cells, max(MIN_SIDE, round((width / density) ** (1.0 / 3.0))))
    side = np.array(sorted({min(cells, balanced * 2**k) for k in range(4)} | {cells}))[:, None]  # (S, 1)
    rows = np.minimum(last_row // side * side + side, cells) - first_row // side * side  # (S, M) covered
    cols = np.minimum(last_col // side * side + side, cells) - first_col // side * side
    entries = (last_row // side - first_row // side + 1) * (last_col // side - first_col // side + 1)
    cost = ENTRY_COST * entries.sum(axis=1) + density * (rows * cols).sum(axis=1)
    return int(side[np.argmin(cost), 0])


def _entries(world: np.ndarray, blocks: tuple[np.ndarray, ...], per: int) -> tuple[np.ndarray, np.ndarray]:
    """Every (query, block) whose block lies in the query's block rectangle: (query (E,), block key (E,)).

    ``blocks`` = (first row, last row, first col, last col) (M,) block coordinates of each rectangle; the
    key of block (r, c) of world w is (w * per + r) * per + c.
    """
    row0, row1, col0, col1 = blocks
    wide = col1 - col0 + 1
    size = (row1 - row0 + 1) * wide
    query = np.repeat(np.arange(len(world)), size)
    step = np.arange(len(query)) - np.repeat(np.cumsum(size) - size, size)
    down = step // wide[query]
    key = (world[query] * per + row0[query] + down) * per + col0[query] + step - down * wide[query]
    return query, key


def block_pairs(flat: np.ndarray, burning_world: np.ndarray, cells: int, batch: int, world: np.ndarray,
                spans: tuple[np.ndarray, ...], side: int) -> tuple[np.ndarray, np.ndarray, np.ndarray, Callable]:
    """Pairs of each query with every burning cell of its world in the ``side``-cell blocks its span overlaps.

    flat (K,) int flat indices of the burning cells, burning_world (K,) their worlds; world (M,) the
    queries' worlds, spans = (first row, last row, first col, last col) (M,) int cell spans within
    [0, C) that contain every cell the query may accept; ``side`` from :func:`block_side`. Returns
    (query, row, col, cell_of): the query (P,) int64 and the cell's row and col (P,) float64 of each
    pair, in no particular order, and a function from pair positions (N,) to their cells' row * C + col
    (N,) int64.
    """
    per = -(-cells // side)
    entry_query, entry_key = _entries(world, tuple(span // side for span in spans), per)
    index = flat.dtype.type
    listed = entry_query[np.argsort(entry_key, kind="stable")]  # block by block; keys come in sorted runs
    listing = np.bincount(entry_key, minlength=batch * per * per).astype(index)
    first_listed = np.cumsum(listing) - listing
    # np.take, not fancy indexing: that would first convert every int32 index array to int64
    local = np.multiply(burning_world, index(cells * cells))
    np.subtract(flat, local, out=local)
    key = np.take(_block_of_cell(cells, side, index), local)
    key += burning_world * index(per * per)
    active = np.flatnonzero(np.take(listing > 0, key))
    key, local = key[active], local[active]
    count = np.take(listing, key)
    ends = np.cumsum(count)
    first = np.take(first_listed, key)
    owner = _runs(ends, 0, 0, 1)  # the active cell of each pair
    slot = _runs(ends, first[0] if len(first) else 0, 1, first[1:] - first[:-1] - count[:-1] + 1)
    row = local // index(cells)
    col = (local - row * index(cells)).astype(np.float64)

    def cell_of(pairs: np.ndarray) -> np.ndarray:
        return local[owner[pairs]].astype(np.int64)

    return np.take(listed, slot), np.take(row.astype(np.float64), owner), np.take(col, owner), cell_of


def _runs(ends: np.ndarray, start: int, step: int, jumps: np.ndarray | int) -> np.ndarray:
    """(ends[-1],) int64 values from ``start`` going up by ``step``, but by ``jumps`` where a run ends.

    Runs end at ``ends`` (R,) increasing; ``jumps`` is one number or (R - 1,). One cumulative sum: much
    faster than np.repeat when most runs are one long.
    """
    steps = np.full(int(ends[-1]) if len(ends) else 0, step, np.int64)
    if len(steps):
        steps[0] = start
        steps[ends[:-1]] = jumps
    return np.cumsum(steps, out=steps)
