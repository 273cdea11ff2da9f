"""Water drops: every existing or burning tree near a drop point becomes wet (ENVIRONMENTS.md, AWS)."""

from __future__ import annotations

import numpy as np

from .engine import BURNING, EXISTING, WET, FireState, in_range, vector


def _window(centre: np.ndarray, half: int, cells: int) -> tuple[np.ndarray, int]:
    """First grid index (P,) int64 and length n of a window of cells, on the grid, holding every
    integer within ``half`` of ``rint(centre)`` that is on the grid."""
    size = min(2 * half + 1, cells)
    start = np.clip(np.rint(centre) - half, 0, cells - size)  # clip in float: centres may be far off-grid
    return start.astype(np.int64), size


def covered_cells(world: np.ndarray, rows: np.ndarray, cols: np.ndarray, radius: float, cells: int,
                  batch: int) -> tuple[np.ndarray, np.ndarray]:
    """Every (point, cell) pair with the cell centre within ``radius`` of the point (cell coordinates).

    ``world`` (P,) lies in [0, batch). Returns (point (N,) index into the P points, flat (N,) index
    of the cell), in point order. A cell within reach is at most floor(radius + 0.5) cells from
    rint(point) in row and in col, so each point scans one window of that half-width (clipped to the grid).
    """
    half = int(np.floor(radius + 0.5))
    row0, size = _window(rows, half, cells)
    col0, _ = _window(cols, half, cells)
    index = np.int32 if max(len(world) * size * size, batch * cells * cells) < 2**31 else np.int64
    span = np.arange(size)
    d_row = (row0[:, None] + span - rows[:, None]) ** 2
    d_col = (col0[:, None] + span - cols[:, None]) ** 2
    reach = (d_row[:, :, None] + d_col[:, None, :] <= radius * radius).reshape(len(world), size * size)
    pick = np.flatnonzero(reach).astype(index)
    point, inside = np.divmod(pick, index(size * size))
    corner = ((world * cells + row0) * cells + col0).astype(index)
    offset = (span[:, None] * cells + span[None, :]).astype(index).ravel()
    return point, corner[point] + offset[inside]


def _lowest_owner(flat: np.ndarray, owner: np.ndarray, owners: int) -> tuple[np.ndarray, np.ndarray]:
    """Distinct cells of ``flat`` (N,) and, for each, the lowest of the ``owner`` (N,) ids paired with it."""
    key = np.sort(flat.astype(np.int64) * owners + owner, kind="stable")  # runs of ascending cells: timsort is fast
    cell, who = np.divmod(key, owners)
    first = np.ones(len(key), bool)
    first[1:] = cell[1:] != cell[:-1]
    return cell[first], who[first]


def douse(state: FireState, world: np.ndarray, rows: np.ndarray, cols: np.ndarray, radius_cells: float,
          owner: np.ndarray, owners: int, spreading: bool = False) -> tuple[FireState, np.ndarray, np.ndarray]:
    """Wet every existing or burning tree whose cell centre lies within ``radius_cells`` of a drop point.

    The P points are given by world (P,) int, rows/cols (P,) fractional cell coordinates (anywhere,
    even off the grid) and owner (P,) int in [0, owners). Writes ``state.trees`` in place (``state``
    is consumed). Returns (state, extinguished (owners,), prepared (owners,)) int64: burning -> wet
    and existing -> wet trees credited per owner; a tree covered by several owners is credited once,
    to the lowest owner id. Wet trees leave the burning list; with ``spreading`` they join ``doused`` with their
    ages and go on trying their neighbours until their burn ends (the release's fire: water never touches its
    burning list); nothing else changes.
    """
    cells, batch = state.cells, state.batch
    world = vector("world", world, integer=True)
    points = len(world)
    rows, cols = vector("rows", rows, points), vector("cols", cols, points)
    owner = vector("owner", owner, points, integer=True)
    if not (np.isfinite(radius_cells) and radius_cells >= 0.0):
        raise ValueError(f"radius_cells must be a finite number >= 0, got {radius_cells!r}")
    if not (isinstance(owners, (int, np.integer)) and owners >= 1):
        raise ValueError(f"owners must be a positive integer, got {owners!r}")
    if state.trees.size * owners >= 2**62:
        raise ValueError(f"owners ({owners}) too large for {state.trees.size} cells: cell * owners must fit int64")
    in_range("world", world, batch)
    in_range("owner", owner, int(owners))
    point, flat = covered_cells(world, rows, cols, float(radius_cells), cells, batch)
    trees = state.trees.reshape(-1)
    before = trees[flat]
    wettable = np.flatnonzero((before == EXISTING) | (before == BURNING))
    cell, who = _lowest_owner(flat[wettable], owner[point[wettable]], int(owners))
    was_burning = trees[cell] == BURNING
    extinguished = np.bincount(who[was_burning], minlength=owners).astype(np.int64)
    prepared = np.bincount(who[~was_burning], minlength=owners).astype(np.int64)
    trees[cell] = WET
    if was_burning.any():
        still = trees[state.burning] == BURNING
        doused, doused_age = state.doused, state.doused_age
        if spreading:
            doused = np.concatenate([doused, state.burning[~still]])
            doused_age = np.concatenate([doused_age, state.age[~still]])
        state = FireState(trees=state.trees, burning=state.burning[still], age=state.age[still], quiet=state.quiet,
                          out=state.out, ignited=state.ignited, burnt_out=state.burnt_out, spent=state.spent[still],
                          doused=doused, doused_age=doused_age, carry=state.carry)
    return state, extinguished, prepared
