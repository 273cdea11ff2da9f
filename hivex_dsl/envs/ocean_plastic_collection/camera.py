"""What a vessel's sensors and collector see of the floating plastic, for every vessel at once.

The pebbles are sorted into a square grid whose cells are at least ``1 / BLOCK_SPAN`` as wide as
the farthest any sensor reaches, so the pebbles a vessel can sense lie in the block of
``2 BLOCK_SPAN + 1`` grid cells on a side around its cell: one contiguous slice of the sorted
array per block row. All (vessel, pebble) candidate pairs of the batch are gathered into flat
arrays, moved into each vessel's frame, and reduced with ``np.bincount`` over (vessel slot,
camera cell) indices. No Python loop runs over worlds, vessels or pebbles.

Vessel frame: ``forward`` along the heading, ``left`` 90 degrees counter-clockwise from it. The
camera is ``CAMERA_CELLS`` x ``CAMERA_CELLS`` cells of ``CAMERA_CELL_M`` metres centred on the
vessel; row 0 is the farthest ahead and column 0 the farthest left, so the picture looks the way
the vessel travels (up). A pebble at (forward f, left l) lies in row ``floor((W - f) / c)`` and
column ``floor((W - l) / c)`` with ``W`` half the camera width and ``c`` the cell size.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property

import numpy as np

from .types import PebbleField

CAMERA_CELLS = 25  # [paper] 25 x 25 visual observation
CAMERA_CELL_M = 2.0  # [paper] each cell represents 2 metres
CAMERA_HALF_M = CAMERA_CELLS * CAMERA_CELL_M / 2.0
CAMERA_BINS = CAMERA_CELLS * CAMERA_CELLS + 1  # per vessel: the cells, then one bin for unseen pebbles
BLOCK_SPAN = 2  # grid cells searched on each side of a vessel's cell
BLOCK_ROWS = np.arange(-BLOCK_SPAN, BLOCK_SPAN + 1)
MAX_GRID_CELLS = 48  # the default 200 m world uses 22


@dataclass(frozen=True)
class Geometry:
    """The sensing constants of a scenario (metres) and what follows from them."""

    half_extent: float
    collector_reach: float
    collector_half_width: float
    nearby_radius: float
    top_speed: float  # metres per step; the collector sweeps up to this far behind its new position

    @property
    def reach(self) -> float:
        """The farthest (Euclidean) distance from a vessel's centre at which anything it senses can lie."""
        camera_corner = CAMERA_HALF_M * np.sqrt(2.0)
        collector = np.hypot(max(self.collector_reach, self.top_speed), self.collector_half_width)
        return float(max(camera_corner, self.nearby_radius, collector))

    @property
    def cells(self) -> int:
        """Grid cells per side: as many as keep a cell at least ``reach / BLOCK_SPAN`` wide, at most
        ``MAX_GRID_CELLS`` (the block-row tables grow with the square of it)."""
        fitting = int(2.0 * self.half_extent * BLOCK_SPAN // (self.reach + 1e-6))  # margin for rounding
        return min(max(1, fitting), MAX_GRID_CELLS)

    @cached_property
    def lookup(self) -> tuple[int, int, np.ndarray]:
        """(shift, width, table) turning a candidate's shifted camera row and column into its camera cell.

        A candidate lies within ``BLOCK_SPAN + 1`` grid cells of its vessel's clipped position on both
        world axes, and a vessel is at most one step (``top_speed``) outside the world when it is
        sensed, so a candidate lies within ``extent`` metres in the vessel's frame. Shifted by
        ``shift`` cells, its row and column are positive (so truncation is floor) and below
        ``width``; ``table[row * width + column]`` is ``row * 25 + column`` inside the camera and
        625 (unseen) outside it."""
        extent = ((BLOCK_SPAN + 1) * (2.0 * self.half_extent / self.cells) + self.top_speed) * np.sqrt(2.0)
        shift = int(np.ceil(extent / CAMERA_CELL_M)) + 1
        width = 2 * shift + CAMERA_CELLS
        index = np.arange(width) - shift
        inside = (index >= 0) & (index < CAMERA_CELLS)
        table = np.where(inside[:, None] & inside[None, :], index[:, None] * CAMERA_CELLS + index[None, :],
                         CAMERA_BINS - 1)
        return shift, width, table.ravel().astype(np.int16)


def build_field(positions: np.ndarray, geometry: Geometry) -> PebbleField:
    """Sort (B, N, 2) pebble positions into the geometry's grid and tabulate every cell's block rows;
    all pebbles alive."""
    batch, count = positions.shape[:2]
    half, cells = geometry.half_extent, geometry.cells
    cell_m = 2.0 * half / cells
    grid = np.clip(np.floor((positions + half) / cell_m), 0, cells - 1).astype(np.int64)
    key = grid[..., 1] * cells + grid[..., 0]
    order = np.argsort(key, axis=1, kind="stable")
    key = np.take_along_axis(key, order, axis=1)
    worlds = np.arange(batch)[:, None] * cells * cells
    counts = np.bincount((worlds + key).ravel(), minlength=batch * cells * cells).reshape(batch, cells * cells)
    start = np.zeros((batch, cells * cells + 1), np.int64)
    np.cumsum(counts, axis=1, out=start[:, 1:])
    first, length = _block_rows(start, cells)
    ordered = np.take_along_axis(positions, order[..., None], axis=1)
    return PebbleField(z=ordered[..., 0] + 1j * ordered[..., 1], alive=np.ones((batch, count), bool),
                       first=first, length=length, cells=cells, cell_m=cell_m)


def _block_rows(start: np.ndarray, cells: int) -> tuple[np.ndarray, np.ndarray]:
    """(B, cells^2, rows) first index and length of each block row around each grid cell, from the
    per-world cell offsets ``start`` (B, cells^2 + 1). A block row is ``BLOCK_SPAN`` cells either
    side of the cell (clipped to the grid), so its pebbles are one contiguous slice."""
    gy, gx = np.divmod(np.arange(cells * cells), cells)
    rows = gy[:, None] + BLOCK_ROWS  # (cells^2, rows)
    on_grid = (rows >= 0) & (rows < cells)
    row_start = np.clip(rows, 0, cells - 1) * cells
    left = np.maximum(gx - BLOCK_SPAN, 0)[:, None]
    right = np.minimum(gx + BLOCK_SPAN, cells - 1)[:, None]
    first = np.ascontiguousarray(start[:, row_start + left])  # fancy indexing may leave it strided
    return first, np.where(on_grid, start[:, row_start + right + 1] - first, 0)


def candidates(field: PebbleField, centres: np.ndarray, half_extent: float, active: np.ndarray
               ) -> tuple[np.ndarray, np.ndarray]:
    """Every (vessel slot, pebble) pair whose pebble lies in the grid block around an active vessel.

    centres (B, A, 2) metres; active (B, A). Returns ``per_slot`` (B * A,) candidate counts and
    ``pebble`` (M,) flat pebble indices ``b * N + k``, grouped by slot ``b * A + a`` in order, so
    ``np.repeat(values, per_slot)`` spreads per-vessel values over the candidates.
    """
    batch = centres.shape[0]
    cells, count, rows = field.cells, field.z.shape[1], field.first.shape[2]
    # Clipping the centre into the world keeps every pebble within reach inside the block.
    grid = np.minimum(np.maximum(((centres + half_extent) * (1.0 / field.cell_m)).astype(np.int64), 0), cells - 1)
    worlds = np.arange(batch)[:, None]
    key = grid[..., 1] * cells + grid[..., 0] + worlds * (cells * cells)
    first = field.first.reshape(-1, rows)[key] + (worlds * count)[..., None]  # (B, A, rows)
    length = field.length.reshape(-1, rows)[key] * active[..., None]
    lengths = length.reshape(-1)
    before = np.cumsum(lengths) - lengths
    pebble = np.repeat(first.reshape(-1) - before, lengths) + np.arange(int(before[-1] + lengths[-1]))
    return length.sum(axis=2).reshape(-1), pebble


@dataclass(frozen=True)
class Sensing:
    """The outcome of one sensing pass over B worlds of A vessels."""

    alive: np.ndarray  # (B, N) bool pebbles still floating afterwards
    collected: np.ndarray  # (B, A) int64 pebbles each vessel collected
    camera: np.ndarray  # (B, A, CAMERA_CELLS, CAMERA_CELLS) int64 pebble counts per cell
    nearby: np.ndarray  # (B, A) int64 pebbles nearer than the nearby radius


def sense(field: PebbleField, position: np.ndarray, facing: np.ndarray, speed: np.ndarray,
          active: np.ndarray, geometry: Geometry, collect: bool) -> Sensing:
    """Collect (if ``collect``) with every active vessel, then read its camera and nearby count.

    position (B, A, 2) metres, facing (B, A) complex unit headings exp(i heading), speed (B, A)
    metres per step. A pebble is collected when it
    lies in the rectangle the collector covered this step: ``-speed <= forward <= collector_reach``
    and ``|left| <= collector_half_width`` (the collector moved ``speed`` metres along the heading,
    so this is the area it swept). A pebble two vessels reach goes to the lower agent index.
    Inactive vessels neither collect nor see (their camera and count are 0).
    """
    batch, agents = facing.shape
    slots = batch * agents
    per_slot, pebble = candidates(field, position, geometry.half_extent, active)
    slot = np.repeat(np.arange(slots), per_slot)
    # Complex arithmetic: (p - v) * exp(-i heading) = forward + i left, in one multiply.
    turn = facing.reshape(-1).conj()
    centre = (position[..., 0] + 1j * position[..., 1]).reshape(-1) * turn
    local = np.take(field.z, pebble) * np.repeat(turn, per_slot) - np.repeat(centre, per_slot)
    forward, left = local.real, local.imag
    floating = np.take(field.alive, pebble)
    alive, collected = field.alive, np.zeros(slots, np.int64)
    if collect:
        swept = ((forward <= geometry.collector_reach) & (forward >= np.repeat(-speed.reshape(-1), per_slot))
                 & (np.abs(left) <= geometry.collector_half_width) & floating)
        hits = np.flatnonzero(swept)
        if hits.size:
            alive, collected = _collect(field.alive, pebble[hits], slot[hits], slots)
            floating &= np.take(alive, pebble)
    camera = _camera_counts(slot, forward, left, floating, slots, geometry)
    near = (forward * forward + left * left < geometry.nearby_radius ** 2) & floating
    nearby = np.bincount(np.where(near, slot, slots), minlength=slots + 1)[:slots]
    return Sensing(alive=alive, collected=collected.reshape(batch, agents),
                   camera=camera.reshape(batch, agents, CAMERA_CELLS, CAMERA_CELLS),
                   nearby=nearby.reshape(batch, agents))


def _collect(alive: np.ndarray, hit_pebble: np.ndarray, hit_slot: np.ndarray, slots: int):
    """Remove the hit pebbles; each goes to its first (lowest) slot, hits being ordered by slot.

    Returns the new alive mask (B, N) and collected counts per slot (slots,).
    """
    taken, first = np.unique(hit_pebble, return_index=True)  # first occurrence = lowest slot
    alive = alive.copy()
    alive.reshape(-1)[taken] = False
    return alive, np.bincount(hit_slot[first], minlength=slots)


def _camera_counts(slot: np.ndarray, forward: np.ndarray, left: np.ndarray, floating: np.ndarray,
                   slots: int, geometry: Geometry) -> np.ndarray:
    """(slots, CAMERA_CELLS**2) floating pebble counts per (slot, camera cell). Column 0 is the
    farthest left, so the column counts cells from the left edge exactly as the row does from the top."""
    shift, width, table = geometry.lookup
    top = CAMERA_HALF_M + shift * CAMERA_CELL_M  # shifted row 0 starts this far ahead (column: left)
    row = ((top - forward) * (1.0 / CAMERA_CELL_M)).astype(np.int64)
    col = ((top - left) * (1.0 / CAMERA_CELL_M)).astype(np.int64)
    cell = np.where(floating, np.take(table, row * width + col), CAMERA_BINS - 1)
    counts = np.bincount(slot * CAMERA_BINS + cell, minlength=slots * CAMERA_BINS)
    return counts.reshape(slots, CAMERA_BINS)[:, :-1]
