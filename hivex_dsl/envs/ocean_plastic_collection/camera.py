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
from functools import cached_property, lru_cache
from typing import NamedTuple, Optional

import numpy as np

from ...sim.grids import Grid, sample_bilinear
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
    ordered = np.take_along_axis(positions, order[..., None], axis=1)
    return PebbleField(z=ordered[..., 0] + 1j * ordered[..., 1], alive=np.ones((batch, count), bool),
                       blocks=_block_rows(start, cells), cells=cells, cell_m=cell_m)


def _block_rows(start: np.ndarray, cells: int) -> np.ndarray:
    """(B, cells^2, rows, 2) first index and length of each block row around each grid cell, from the
    per-world cell offsets ``start`` (B, cells^2 + 1). A block row is ``BLOCK_SPAN`` cells either
    side of the cell (clipped to the grid), so its pebbles are one contiguous slice."""
    gy, gx = np.divmod(np.arange(cells * cells), cells)
    rows = gy[:, None] + BLOCK_ROWS  # (cells^2, rows)
    on_grid = (rows >= 0) & (rows < cells)
    row_start = np.clip(rows, 0, cells - 1) * cells
    left = np.maximum(gx - BLOCK_SPAN, 0)[:, None]
    right = np.minimum(gx + BLOCK_SPAN, cells - 1)[:, None]
    first = start[:, row_start + left]
    blocks = np.stack([first, np.where(on_grid, start[:, row_start + right + 1] - first, 0)], axis=-1)
    return np.ascontiguousarray(blocks)  # fancy indexing leaves it strided; steps reshape it


@lru_cache(maxsize=32)
def _batch_offsets(batch: int, agents: int, count: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Constant indices of a batch shape (read-only): the worlds (B, 1), each block row's offset
    ``b * N`` (B * A * rows,) into the flattened pebble arrays, and its vessel slot ``b * A + a``
    (B * A * rows,)."""
    rows = BLOCK_ROWS.size
    worlds = np.arange(batch)[:, None]
    world_pebble = np.repeat(np.arange(batch) * count, agents * rows)
    row_slot = np.repeat(np.arange(batch * agents), rows)
    for array in (worlds, world_pebble, row_slot):
        array.setflags(write=False)
    return worlds, world_pebble, row_slot


def candidates(field: PebbleField, centres: np.ndarray, half_extent: float, active: np.ndarray
               ) -> tuple[np.ndarray, np.ndarray]:
    """Every (vessel slot, pebble) pair whose pebble lies in the grid block around an active vessel.

    centres (B, A, 2) metres; active (B, A). Returns ``slot`` (M,) vessel slots ``b * A + a`` in
    increasing order and ``pebble`` (M,) flat pebble indices ``b * N + k``, so ``values.take(slot)``
    spreads per-vessel values (B * A,) over the candidates.
    """
    batch, agents = active.shape
    cells = field.cells
    worlds, world_pebble, row_slot = _batch_offsets(batch, agents, field.z.shape[1])
    # Clipping the centre into the world keeps every pebble within reach inside the block.
    grid = ((centres + half_extent) * (1.0 / field.cell_m)).astype(np.int64)
    np.minimum(np.maximum(grid, 0, out=grid), cells - 1, out=grid)
    blocks = field.blocks.reshape(batch, cells, cells, BLOCK_ROWS.size, 2)[worlds, grid[..., 1], grid[..., 0]]
    lengths = (blocks[..., 1] * active[..., None]).reshape(-1)
    ends = np.add.accumulate(lengths)
    # Candidate i of a block row is pebble first + i: repeat (first - candidates before the row), add 0..M-1.
    shifted = blocks[..., 0].reshape(-1) + world_pebble - (ends - lengths)
    return row_slot.repeat(lengths), shifted.repeat(lengths) + np.arange(ends[-1])


class Sensing(NamedTuple):
    """The outcome of one sensing pass over B worlds of A vessels."""

    alive: np.ndarray  # (B, N) bool pebbles still floating afterwards
    collected: np.ndarray  # (B, A) int64 pebbles each vessel collected
    camera: np.ndarray  # (B, A, CAMERA_CELLS, CAMERA_CELLS) int64 pebble counts per cell
    nearby: np.ndarray  # (B, A) int64 pebbles nearer than the nearby radius


def as_complex(xy: np.ndarray) -> np.ndarray:
    """(...) complex128 x + i y of (..., 2) coordinates, as a view where the layout allows it."""
    return np.ascontiguousarray(xy, np.float64).view(np.complex128)[..., 0]


def as_pairs(z: np.ndarray) -> np.ndarray:
    """(..., 2) float64 (x, y) of (...) complex128 x + i y, as a view where the layout allows it."""
    return np.ascontiguousarray(z, np.complex128)[..., None].view(np.float64)


def sense(field: PebbleField, position: np.ndarray, facing: np.ndarray, speed: np.ndarray,
          active: np.ndarray, geometry: Geometry, sweeping: Optional[np.ndarray],
          allowance: Optional[np.ndarray] = None) -> Sensing:
    """Collect with every sweeping vessel, then read every active vessel's camera and nearby count.

    position (B, A, 2) metres, facing (B, A) complex unit headings exp(i heading), speed (B, A)
    metres per step, sweeping (B, A) bool: the active vessels whose collector moved this step (None:
    no vessel collects). A pebble is collected when it
    lies in the rectangle the collector covered this step: ``-speed <= forward <= collector_reach``
    and ``|left| <= collector_half_width`` (the collector moved ``speed`` metres along the heading,
    so this is the area it swept). A collector that did not move sweeps nothing, so a vessel spawned
    over pebbles does not take them before it moves. A pebble two vessels reach goes to the lower agent
    index. ``allowance`` (slots,), if given, caps how many each vessel collects, the nearest to its centre
    first; the rest float on (a pebble two vessels reach stays with the lower index even where its cap leaves
    it). Inactive vessels neither collect nor see (their camera and count are 0).
    """
    batch, agents = facing.shape
    slots = batch * agents
    slot, pebble = candidates(field, position, geometry.half_extent, active)
    # Complex arithmetic: (p - v) * exp(-i heading) = forward + i left, in one multiply.
    turn = facing.reshape(-1).conj()
    centre = as_complex(position).reshape(-1) * turn
    # ndarray.take: the fastest gather both for one world and for hundreds
    local = field.z.take(pebble) * turn.take(slot) - centre.take(slot)  # (M,) forward + i left
    floating = field.alive.take(pebble)
    alive, collected = field.alive, np.zeros(slots, np.int64)
    if sweeping is not None and np.count_nonzero(sweeping):
        hits = (_swept(local, speed.take(slot), floating, geometry) & sweeping.reshape(-1).take(slot)).nonzero()[0]
        if hits.size:
            distance = np.abs(local[hits]) if allowance is not None else None
            alive, collected = _collect(field.alive, pebble[hits], slot[hits], slots, allowance, distance)
            floating &= alive.take(pebble)
    counts = np.bincount(_camera_bins(slot, local, floating, geometry), minlength=slots * CAMERA_BINS)
    camera = counts.reshape(slots, CAMERA_BINS)[:, :-1]  # without the unseen bin
    return Sensing(alive=alive, collected=collected.reshape(batch, agents),
                   camera=camera.reshape(batch, agents, CAMERA_CELLS, CAMERA_CELLS),
                   nearby=_nearby(slot, local, floating, slots, geometry).reshape(batch, agents))


def _swept(local: np.ndarray, speed: np.ndarray, floating: np.ndarray, geometry: Geometry) -> np.ndarray:
    """(M,) bool: floating candidates at ``local`` (M,) forward + i left metres inside the rectangle the
    collector of their vessel swept at ``speed`` (M,) metres per step."""
    forward, left = local.real, local.imag
    return ((forward <= geometry.collector_reach) & (forward >= -speed)
            & (np.abs(left) <= geometry.collector_half_width) & floating)


def _nearby(slot: np.ndarray, local: np.ndarray, floating: np.ndarray, slots: int, geometry: Geometry) -> np.ndarray:
    """(slots,) int64 floating candidates nearer than the nearby radius to their vessel."""
    coordinates = local.view(np.float64)  # forward, left interleaved
    square = coordinates * coordinates
    near = (square[0::2] + square[1::2] < geometry.nearby_radius ** 2) & floating
    return np.bincount(slot[near], minlength=slots)


def _collect(alive: np.ndarray, hit_pebble: np.ndarray, hit_slot: np.ndarray, slots: int,
             allowance: Optional[np.ndarray] = None, hit_distance: Optional[np.ndarray] = None):
    """Remove the hit pebbles; each goes to its first (lowest) slot, hits being ordered by slot. With
    ``allowance`` (slots,) a slot takes at most that many, the smallest ``hit_distance`` (hits,) first.

    Returns the new alive mask (B, N) and collected counts per slot (slots,).
    """
    taken, first = np.unique(hit_pebble, return_index=True)  # first occurrence = lowest slot
    owner = hit_slot[first]
    if allowance is not None:
        order = np.lexsort((hit_distance[first], owner))  # by slot, the nearest first
        ranked = owner[order]
        rank = np.arange(order.size) - np.searchsorted(ranked, ranked)  # place within its slot's hits
        keep = order[rank < allowance[ranked]]
        taken, owner = taken[keep], owner[keep]
    alive = alive.copy()
    alive.reshape(-1)[taken] = False
    return alive, np.bincount(owner, minlength=slots)


def heat_camera(heat: np.ndarray, position: np.ndarray, facing: np.ndarray, active: np.ndarray,
                half_extent: float) -> np.ndarray:
    """(B, A, 25, 25) float32 the pollution heat map under every vessel's camera, read as a satellite would:
    each cell the map's density at the cell's centre (bilinear between the map's cell centres) over the world's
    densest cell, so in [0, 1]; 0 beyond the border and for inactive vessels. The pebbles themselves, and the
    water a vessel swept, do not show (params.camera_source 'heat_map').

    heat (B, R, R) as :func:`hivex_dsl.sim.procgen.pollution.pollution_map` (row i along y, column j along x);
    position (B, A, 2) metres; facing (B, A) complex unit headings; active (B, A) bool."""
    batch, resolution = heat.shape[:2]
    cell_m = 2.0 * half_extent / resolution
    centres = Grid(-half_extent + cell_m / 2.0, cell_m, resolution)  # the map's cell centres, row i along y
    points = as_complex(position)[..., None, None] + facing[..., None, None] * _CELL_CENTRES  # (B, A, 25, 25)
    x, y = points.real, points.imag
    inside = (np.abs(x) <= half_extent) & (np.abs(y) <= half_extent) & active[..., None, None]
    value = sample_bilinear(heat, centres, np.stack([x, y], axis=-1).reshape(batch, -1, 2)).reshape(x.shape)
    value *= 1.0 / heat.reshape(batch, -1).max(axis=1)[:, None, None, None]
    return np.where(inside, value, 0.0).astype(np.float32)


def _cell_centres() -> np.ndarray:
    """(25, 25) complex128 every camera cell's centre in a vessel's frame, forward + i left metres: row 0 the
    farthest ahead, column 0 the farthest left (as :func:`_camera_bins` bins pebbles)."""
    offsets = CAMERA_HALF_M - (np.arange(CAMERA_CELLS) + 0.5) * CAMERA_CELL_M
    centres = offsets[:, None] + 1j * offsets[None, :]
    centres.setflags(write=False)
    return centres


_CELL_CENTRES = _cell_centres()


def _camera_bins(slot: np.ndarray, local: np.ndarray, floating: np.ndarray, geometry: Geometry) -> np.ndarray:
    """(M,) bin ``slot * CAMERA_BINS + cell`` of every candidate at ``local`` (M,) forward + i left metres:
    its camera cell, or the unseen bin outside the camera and for collected pebbles. Column 0 is the
    farthest left, so the column counts cells from the left edge exactly as the row does from the top."""
    shift, width, table = geometry.lookup
    top = CAMERA_HALF_M + shift * CAMERA_CELL_M  # shifted row 0 starts this far ahead (column: left)
    # (top - forward, top - left) / cell, interleaved; truncation is floor as both are positive.
    shifted = ((top + 1j * top - local).view(np.float64) * (1.0 / CAMERA_CELL_M)).astype(np.int64)
    # Shifted row and column 0 lie outside the camera, so index 0 sends collected pebbles to the unseen bin.
    return slot * CAMERA_BINS + table[(shifted[0::2] * width + shifted[1::2]) * floating]
