"""The closest burning tree of every tower, kept per cohort of trees that ignited at the same fire step.

Nothing douses a tree in Wildfire Resource Management, so every tree burns exactly ``burn_steps``
fire steps: the trees that ignited at one fire step (a cohort) burn out together, and until then
the cohort's closest tree to a tower stays its closest. A tower's closest burning tree is thus the
nearest of at most ``burn_steps`` cohort answers; each fire step only the new cohort, this step's
ignitions, has to be searched, and the cohort that burnt out is dropped. Slot ``j`` of the cohort
axis holds the trees of age ``j``.

Distances are squared cell distances between a tree's cell centre and the tower's fractional cell
coordinates, inside the tower's square search box, with ties to the lower flat index: exactly
:func:`hivex_dsl.sim.fire.closest_burning`'s answer (tests/envs/test_wrm_sight.py checks it).

An answer is one complex128 *key*: the squared distance (inf: no tree in the box) as the real part,
the cell row * C + col (exact in a float64) as the imaginary part, negative for a key outside the box.
NumPy orders complex numbers lexicographically, so one ``np.minimum`` picks the nearer cell and,
between equally near ones, the lower: the distance and the tie-break in a single pass.
"""

from __future__ import annotations

import numpy as np

NONE = complex(np.inf, -1.0)  # the key of "no tree in the box"
OUTSIDE = -(2.0**40)  # the imaginary part of a row or column outside the box: sums stay exact and negative


def square_table(centres: np.ndarray, half: float, cells: int) -> np.ndarray:
    """(C, A) float64: (r - centre)^2 for each grid row (or column) r and tower centre (A,), inf where
    |r - centre| > half (outside the tower's box); the same float operations as closest_burning's."""
    gap = np.arange(cells, dtype=np.float64)[:, None] - centres
    table = np.where(np.abs(gap) > half, np.inf, gap * gap)
    table.flags.writeable = False
    return table


def key_tables(row_table: np.ndarray, col_table: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(A, C) complex128 tables (tower-major) whose sum for row r and column c is the key of cell r * C + c:
    the :func:`square_table` (C, A) terms as real parts, r * C and c as imaginary parts (:data:`OUTSIDE`
    where the term is inf, so every key outside the box has a negative imaginary part). Tower-major, a
    gather of N cells gives (A, N) keys whose minimum runs along contiguous memory."""
    cells = len(row_table)
    band = np.arange(cells, dtype=np.float64)[:, None]
    rows = row_table + 1j * np.where(row_table < np.inf, band * cells, OUTSIDE)
    cols = col_table + 1j * np.where(col_table < np.inf, band, OUTSIDE)
    rows, cols = np.ascontiguousarray(rows.T), np.ascontiguousarray(cols.T)
    rows.flags.writeable = cols.flags.writeable = False
    return rows, cols


def _keys(cell: np.ndarray, cells: int, row_keys: np.ndarray, col_keys: np.ndarray) -> np.ndarray:
    """(A, N) complex128 keys of cells row * C + col (N,) for the A towers of :func:`key_tables`."""
    row, col = np.divmod(cell, cells)
    keys = row_keys.take(row, axis=1)
    keys += col_keys.take(col, axis=1)
    return keys


def nearest_keys(flat: np.ndarray, batch: int, cells: int, row_keys: np.ndarray, col_keys: np.ndarray
                 ) -> np.ndarray:
    """(B, A) complex128 key of each tower's nearest cell among burning cells ``flat`` (N,), given in
    ascending flat order; :data:`NONE` where no cell lies in the box. ``row_keys``/``col_keys`` (A, C)
    from :func:`key_tables` (the same towers in every world)."""
    towers = row_keys.shape[0]
    if len(flat) == 0:
        return np.full((batch, towers), NONE)
    if batch == 1:  # one world: flat indices are its cells
        return np.minimum.reduce(_keys(flat, cells, row_keys, col_keys), axis=1)[None]
    world, cell = np.divmod(flat, cells * cells)
    count = np.bincount(world, minlength=batch)
    worlds = np.flatnonzero(count)
    keys = np.full((batch, towers), NONE)
    keys[worlds] = np.minimum.reduceat(_keys(cell, cells, row_keys, col_keys), (np.cumsum(count) - count)[worlds],
                                       axis=1).T
    return keys


def key_cells(keys: np.ndarray) -> np.ndarray:
    """The cells (...) int64 of keys (...), -1 for a key without a tree in the box (a negative imaginary part)."""
    return np.maximum(keys.imag, -1.0).astype(np.int64)


def nearest_of_sorted(flat: np.ndarray, batch: int, cells: int, row_table: np.ndarray, col_table: np.ndarray
                      ) -> tuple[np.ndarray, np.ndarray]:
    """:func:`nearest_keys` from the :func:`square_table` tables, split: (squared distance (B, A) float64,
    inf when no cell lies in the box; cell (B, A) int64 row * C + col, -1 when none)."""
    keys = nearest_keys(flat, batch, cells, *key_tables(row_table, col_table))
    return keys.real.copy(), key_cells(keys)


def nearest_by_age(burning: np.ndarray, age: np.ndarray, slots: int, batch: int, cells: int, row_keys: np.ndarray,
                   col_keys: np.ndarray) -> np.ndarray:
    """Cohort keys (B, A, S) complex128 of a whole burning list (K,) with ages (K,) in [0, S): slot j
    holds the key of the nearest tree of age j (:func:`nearest_keys`)."""
    keys = np.full((batch, row_keys.shape[0], slots), NONE)
    for years in np.unique(age):  # one cohort at a reset
        keys[..., int(years)] = nearest_keys(np.sort(burning[age == years]), batch, cells, row_keys, col_keys)
    return keys


def age_cohorts(cohorts: np.ndarray, ignitions: np.ndarray) -> np.ndarray:
    """Cohort keys (B, A, S) one fire step later: the ignitions' (B, A) in slot 0, the others one slot
    older; the oldest cohort burnt out."""
    return np.concatenate([ignitions[..., None], cohorts[..., :-1]], axis=-1)
