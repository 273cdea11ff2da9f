"""The closest burning tree of every tower, kept per cohort of trees that ignited at the same fire step.

Nothing douses a tree in Wildfire Resource Management, so every tree burns exactly ``burn_steps``
fire steps: the trees that ignited at one fire step (a cohort) burn out together, and until then
the cohort's closest tree to a tower stays its closest. A tower's closest burning tree is thus the
nearest of at most ``burn_steps`` cohort answers; each fire step only the new cohort, this step's
ignitions, has to be searched, and the cohort that burnt out is dropped. Slot ``j`` of the cohort
axis holds the trees of age ``j``.

Distances are squared cell distances between a tree's cell centre and the tower's fractional cell
coordinates, inside the tower's square search box, with ties to the lower flat index: exactly
:func:`hivex_dsl.fire.closest_burning`'s answer (tests/envs/test_wrm_sight.py checks it).
"""

from __future__ import annotations

import numpy as np

NONE = np.iinfo(np.int64).max  # cell index of an empty answer while comparing; -1 once stored


def square_table(centres: np.ndarray, half: float, cells: int) -> np.ndarray:
    """(C, A) float64: (r - centre)^2 for each grid row (or column) r and tower centre (A,), inf where
    |r - centre| > half (outside the tower's box); the same float operations as closest_burning's."""
    gap = np.arange(cells, dtype=np.float64)[:, None] - centres
    table = np.where(np.abs(gap) > half, np.inf, gap * gap)
    table.flags.writeable = False
    return table


def _candidate_distances(cell: np.ndarray, cells: int, row_table: np.ndarray, col_table: np.ndarray) -> np.ndarray:
    """(N, A) float64 squared distance of cells row * C + col (N,) to the A towers of the
    :func:`square_table` tables, inf outside the tower's box."""
    row, col = np.divmod(cell, cells)
    distance = row_table.take(row, axis=0)
    distance += col_table.take(col, axis=0)
    return distance


def nearest_of_sorted(flat: np.ndarray, batch: int, cells: int, row_table: np.ndarray, col_table: np.ndarray
                      ) -> tuple[np.ndarray, np.ndarray]:
    """Each tower's nearest cell among burning cells ``flat`` (N,) given in ascending flat order.

    row_table/col_table (C, A) from :func:`square_table` for the towers' fractional cell coordinates and
    the half side of their square boxes (the same towers in every world). Returns (squared distance (B, A)
    float64, inf when no cell lies in the box; cell (B, A) int64 row * C + col, -1 when none); ties go to
    the lower cell.
    """
    towers = row_table.shape[1]
    if len(flat) == 0:
        return np.full((batch, towers), np.inf), np.full((batch, towers), -1, np.int64)
    if batch == 1:  # one world: the first minimum along the ascending list is the lowest cell
        pair = _candidate_distances(flat, cells, row_table, col_table)
        nearest = np.minimum.reduce(pair, axis=0)
        return nearest[None], np.where(nearest < np.inf, flat.take(pair.argmin(axis=0)), -1)[None]
    world, cell = np.divmod(flat, cells * cells)
    pair = _candidate_distances(cell, cells, row_table, col_table)
    count = np.bincount(world, minlength=batch)
    worlds = np.flatnonzero(count)
    starts = (np.cumsum(count) - count)[worlds]
    nearest = np.minimum.reduceat(pair, starts, axis=0)  # (W, A) per world that has candidates
    group = np.repeat(np.arange(len(worlds)), count[worlds])
    tied = np.where(pair == nearest[group], cell[:, None], NONE)
    lowest = np.minimum.reduceat(tied, starts, axis=0)
    distance = np.full((batch, towers), np.inf)
    best = np.full((batch, towers), -1, np.int64)
    distance[worlds] = nearest
    best[worlds] = np.where(nearest < np.inf, lowest, -1)
    return distance, best


def nearest_by_age(burning: np.ndarray, age: np.ndarray, slots: int, batch: int, cells: int, row_table: np.ndarray,
                   col_table: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Cohort answers (distance (B, A, S) float64, cell (B, A, S) int64) of a whole burning list (K,)
    with ages (K,) in [0, S): slot j holds the nearest tree of age j (:func:`nearest_of_sorted`)."""
    towers = row_table.shape[1]
    distance = np.full((batch, towers, slots), np.inf)
    best = np.full((batch, towers, slots), -1, np.int64)
    for years in np.unique(age):  # one cohort at a reset
        slot = int(years)
        distance[..., slot], best[..., slot] = nearest_of_sorted(
            np.sort(burning[age == years]), batch, cells, row_table, col_table)
    return distance, best


def age_cohorts(distance: np.ndarray, best: np.ndarray, new_distance: np.ndarray, new_best: np.ndarray
                ) -> tuple[np.ndarray, np.ndarray]:
    """Cohort answers (B, A, S) one fire step later: the ignitions' (B, A) in slot 0, the others one slot
    older; the oldest cohort burnt out."""
    distance = np.concatenate([new_distance[..., None], distance[..., :-1]], axis=-1)
    best = np.concatenate([new_best[..., None], best[..., :-1]], axis=-1)
    return distance, best


def closest_of_cohorts(distance: np.ndarray, best: np.ndarray) -> np.ndarray:
    """(B, A) int64 cell row * C + col of each tower's closest burning tree over its cohorts (B, A, S),
    ties to the lower cell; -1 when no cohort has one."""
    nearest = np.minimum.reduce(distance, axis=-1)
    lowest = np.minimum.reduce(np.where(distance == nearest[..., None], best, NONE), axis=-1)
    return np.where(nearest < np.inf, lowest, -1)
