"""What the cameras see, kept as one palette image per world, and the cameras that read it in one gather.

``look`` holds the palette index of every cell of a square frame of S x S forest cells centred on
the island: the trees drawn over the ground on the island, and around it the water ring or the dark
outside, classified exactly as :func:`.camera.palette_index_at` classifies points. A camera pixel
then needs no bounds test and no second gather. The frame cells that the border line crosses hold
``MIXED``: the few pixels that land there are classified from their coordinates.

Large batches store the image in tiles of 8 x 8 cells (64 bytes, one cache line): a camera's rotated
footprint then touches about half as many memory lines as in row-major order, and the gather is bound by
them. A look that fits in cache (one or two worlds) stays row-major, where a cell's offset costs two
operations instead of nine; every reader and writer follows the layout of the array it is given.

``look`` is part of the state and, like the fire's ``trees``, written in place: the simulator redraws
the cells whose trees changed after every drop and fire step, and whole worlds on a reset.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import lru_cache

import numpy as np

from ...sim.fire import FireState, TreeState
from .camera import OUTSIDE, PALETTE_FLOAT, TREE_BASE, WATER_RING, cameras

MIXED = TREE_BASE  # palette index of tree state NONE: never drawn (a cell without a tree shows its ground)
TILE = 8  # cells per tile side; the frame's padding and side are multiples of it
EDGE_CELLS = 2  # spare frame cells beyond the farthest pixel of a plane inside ViewFrame.safe_m
TRIPLES_FROM = 100_000  # pixels from which colour triples pay
ROW_MAJOR_BYTES = 1 << 20  # looks up to this size stay row-major (B, S, S); larger ones are tiled
KEEP_METRES_UP_TO = 100_000  # pixel coordinates kept for the border test up to this size (in cache)
MAX_GROWTH = 9  # a frame holds at most this many times the island's cells; planes beyond take the exact path


@dataclass(frozen=True)
class ViewFrame:
    """The geometry shared by ``look`` and the cameras.

    forward (P,) / right (P,) float32: metres ahead of the plane of each pixel row / to its right of
    each pixel column; right_left (2, 1, 1, P) float32: right and its negative; cells: forest cells C
    per island side; pad: frame cells before the island on each axis; side: frame cells S per side
    (C + 2 pad rounded up to whole tiles); island_half_m, border_half_m: the scenario's extents;
    island_half, per_m, border_half: the float32 constants of the pixel -> cell mapping, rounded as the
    exact path rounds them; safe_m: every pixel of a plane within +/- safe_m of the centre lies in the
    frame; clear_m: no pixel of a plane within +/- clear_m of the centre lies on a MIXED cell (it may be
    negative: then any plane may see one); blind_m: no pixel of a plane farther than blind_m from the
    centre on either axis lies on the island.
    """

    forward: np.ndarray
    right: np.ndarray
    right_left: np.ndarray
    cells: int
    pad: int
    side: int
    island_half_m: float
    border_half_m: float
    safe_m: float
    clear_m: float
    blind_m: float
    island_half: np.float32
    per_m: np.float32
    border_half: np.float32

    @property
    def pixels(self) -> int:
        return len(self.forward)


def view_frame(offsets: tuple[np.ndarray, np.ndarray], cells: int, island_half_m: float, border_half_m: float,
               plane_reach_m: float) -> ViewFrame:
    """The frame for cameras with pixel ``offsets`` (see :func:`.camera.pixel_offsets`) over planes that
    stay within +/- ``plane_reach_m`` of the centre (the border plus one step beyond it)."""
    pixels = int(round(math.sqrt(offsets[0].size)))
    forward, right = offsets[0][::pixels].copy(), offsets[1][:pixels].copy()
    reach = float(np.hypot(np.abs(forward).max(), np.abs(right).max())) + 1.0  # a metre for rounding
    per_m = cells / (2.0 * island_half_m)
    needed = math.ceil((plane_reach_m + reach - island_half_m) * per_m) + EDGE_CELLS
    widest = int((math.sqrt(MAX_GROWTH) - 1.0) * cells / 2.0)
    pad = _whole_tiles(max(EDGE_CELLS + 1, min(needed, widest)))
    safe = island_half_m + (pad - EDGE_CELLS) / per_m - reach
    constants = (np.float32(island_half_m), np.float32(per_m), np.float32(border_half_m))
    clear = _clear_of_border(*constants, per_m) - reach
    blind = _beyond_island(constants[0], constants[1], cells, per_m) + reach
    right_left = np.stack([right, -right]).reshape(2, 1, 1, -1)
    return ViewFrame(forward, right, right_left, cells, pad, _whole_tiles(cells + 2 * pad), island_half_m,
                     border_half_m, safe, clear, blind, *constants)


def drawn_border_m(params, pixels: int) -> float:
    """The border as the cameras of ``pixels`` x ``pixels`` draw it under AerialWildfireParams ``params``: the
    scenario's, or (camera_sees_border false) one past every pixel of a plane that stopped a step beyond the
    border, so the water ring runs on past it (a camera's side exceeds its farthest pixel's distance)."""
    if params.camera_sees_border:
        return params.border_half_extent_m
    return params.border_half_extent_m + params.plane_speed_m + pixels * params.camera_pixel_m


def _beyond_island(island_half: np.float32, per_m: np.float32, cells: int, cells_per_m: float) -> float:
    """Metres b such that every float32 coordinate beyond +/- b maps to a cell off the island: a cell
    beyond its edge, checked with the mapping."""
    def cell(metres: float) -> int:
        return _mapped_cell(metres, island_half, per_m)

    beyond = float(island_half) + 1.0 / cells_per_m
    while not (cell(beyond) >= cells and cell(-beyond) < 0):  # the mapping is monotone
        beyond += 1.0 / cells_per_m
    return beyond


def _clear_of_border(island_half: np.float32, per_m: np.float32, border_half: np.float32, cells_per_m: float) -> float:
    """Metres b such that every float32 coordinate within +/- b maps to a cell strictly between the
    cells of the border lines (the MIXED ones): two cells inside the border, checked with the mapping."""
    def cell(metres: float) -> int:
        return _mapped_cell(metres, island_half, per_m)

    edge = float(border_half)
    low, high = cell(-edge), cell(edge)
    clear = edge - 2.0 / cells_per_m
    while clear > 0.0 and not low < cell(-clear) <= cell(clear) < high:  # the mapping is monotone
        clear -= 1.0 / cells_per_m
    return clear


def _mapped_cell(metres: float, island_half: np.float32, per_m: np.float32) -> int:
    """The island cell index of one coordinate, by :func:`cell_of`'s float32 mapping."""
    return int(np.floor((np.float32(metres) + island_half) * per_m))


def _whole_tiles(count: int) -> int:
    return -(-count // TILE) * TILE


def cell_of(metres: np.ndarray, frame: ViewFrame, keep: bool = False) -> np.ndarray:
    """int32 island cell index (row of y, col of x) of float32 ``metres``, rounded as the exact path;
    ``metres`` is used up (it holds the scaled coordinate afterwards) unless ``keep``."""
    scaled = np.add(metres, frame.island_half, out=None if keep else metres)
    np.multiply(scaled, frame.per_m, out=scaled)
    return np.floor(scaled, out=np.empty(scaled.shape, np.int32), casting="unsafe")


def tiled_offset(row: np.ndarray, col: np.ndarray, frame: ViewFrame) -> np.ndarray:
    """Offsets in one world's tiled ``look`` of island cells ``row``, ``col`` (int arrays, frame pad included
    here); ``row`` and ``col`` are used up, the result is ``row``'s array.

    Tile (r // 8, c // 8) starts at (r // 8 * S / 8 + c // 8) * 64 and holds cell (r, c) at (r % 8) * 8 + c % 8,
    which is 8 r + (r // 8) (8 S - 64) + c + (c // 8) 56; the pad is whole tiles, so it only adds a constant.
    """
    side, shift = frame.side, TILE.bit_length() - 1
    kind = row.dtype.type
    part = np.right_shift(row, shift)
    part *= kind(TILE * side - TILE * TILE)
    row <<= shift
    row += part
    np.right_shift(col, shift, out=part)
    part *= kind(TILE * TILE - TILE)
    row += part
    row += col
    row += kind(_pad_offset(frame))
    return row


def _pad_offset(frame: ViewFrame) -> int:
    tiles = frame.pad // TILE
    return TILE * frame.pad + tiles * (TILE * frame.side - TILE * TILE) + frame.pad + tiles * (TILE * TILE - TILE)


def cell_offsets(row: np.ndarray, col: np.ndarray, look: np.ndarray, frame: ViewFrame) -> np.ndarray:
    """Offsets in one world of ``look`` (either layout) of island cells ``row``, ``col`` (int arrays, frame
    pad included here); ``row`` and ``col`` are used up, the result is ``row``'s array."""
    if is_tiled(look):
        return tiled_offset(row, col, frame)
    kind = row.dtype.type
    row *= kind(frame.side)
    row += col
    row += kind(frame.pad * (frame.side + 1))
    return row


def is_tiled(look: np.ndarray) -> bool:
    """Whether ``look`` is tiled (B, S / 8, S / 8, 8, 8) rather than row-major (B, S, S)."""
    return look.ndim != 3


def tiled_for(batch: int, frame: ViewFrame) -> bool:
    """Whether a new look of ``batch`` worlds is tiled (B, S / 8, S / 8, 8, 8) or row-major (B, S, S)."""
    return batch * frame.side * frame.side > ROW_MAJOR_BYTES


def to_tiles(image: np.ndarray) -> np.ndarray:
    """(M, S / 8, S / 8, 8, 8) contiguous tiles of (M, S, S) images."""
    count, side = image.shape[0], image.shape[1]
    tiles = side // TILE
    return np.ascontiguousarray(image.reshape(count, tiles, TILE, tiles, TILE).transpose(0, 1, 3, 2, 4))


def frame_template(frame: ViewFrame) -> np.ndarray:
    """(S, S) uint8 palette index of the frame cells off the island: WATER_RING, OUTSIDE or MIXED.

    The cell mapping is monotone, so the cells holding the border's two lines (x or y = +/- border)
    split the others: beyond them every point is outside, between them every point inside.
    """
    edges = cell_of(np.array([-frame.border_half, frame.border_half], np.float32), frame)
    low, high = int(edges[0]), int(edges[1])
    cell = np.arange(frame.side) - frame.pad
    beyond = (cell < low) | (cell > high)
    within = (cell > low) & (cell < high)
    inside = np.where(within[:, None] & within[None, :], np.uint8(WATER_RING), np.uint8(MIXED))
    return np.where(beyond[:, None] | beyond[None, :], np.uint8(OUTSIDE), inside)


def tree_or_ground(trees: np.ndarray, ground: np.ndarray) -> np.ndarray:
    """uint8 palette index of cells with tree states ``trees`` over ground indices ``ground`` (same shape)."""
    return np.where(trees > 0, trees + np.uint8(TREE_BASE), ground)


def build_look(trees: np.ndarray, ground: np.ndarray, template: np.ndarray, frame: ViewFrame,
               tiled: bool | None = None) -> np.ndarray:
    """uint8 ``look`` of M worlds from their trees and ground (M, C, C) and the frame template (S, S):
    tiled (M, S / 8, S / 8, 8, 8) or row-major (M, S, S), by default as :func:`tiled_for` M worlds."""
    image = np.empty((len(trees),) + template.shape, np.uint8)
    image[:] = template
    island = slice(frame.pad, frame.pad + frame.cells)
    image[:, island, island] = tree_or_ground(trees, ground)
    return to_tiles(image) if (tiled_for(len(trees), frame) if tiled is None else tiled) else image


def redraw_cells(look: np.ndarray, trees: np.ndarray, flat: np.ndarray, frame: ViewFrame) -> None:
    """Redraw in ``look`` the tree cells among flat indices ``flat`` (N,) of ``trees`` (B, C, C), in place.

    Cells without a tree keep their ground: no tree appears or vanishes but through a reset.
    """
    if flat.size == 0:
        return
    state = trees.reshape(-1).take(flat)
    held = np.flatnonzero(state)
    paint_cells(look, flat.take(held), state.take(held), frame)


def redraw_fire_step(look: np.ndarray, burning_before: np.ndarray, fire: FireState, frame: ViewFrame) -> None:
    """Redraw in ``look`` what a fire step changed: the trees of ``burning_before`` (K,) that burnt out, and
    the new ignitions of ``fire`` (the state after the step: age 0), those the release's list showed burnt at
    once (``burn_list`` 'release', on the doused list at age 0) too."""
    trees = fire.trees.reshape(-1)
    ended = burning_before[trees.take(burning_before) == np.uint8(TreeState.BURNT)]
    changed = np.concatenate([ended, fire.burning[fire.age == 0], fire.doused[fire.doused_age == 0]])
    paint_cells(look, changed, trees.take(changed), frame)


def paint_cells(look: np.ndarray, flat: np.ndarray, state: np.ndarray | np.uint8, frame: ViewFrame) -> None:
    """Draw tree ``state`` (N,) or one state for all at flat tree-grid indices ``flat`` (N,) into ``look``."""
    if flat.size == 0:
        return
    cells = frame.cells
    world, inside = np.divmod(flat.astype(np.int64, copy=False), cells * cells)
    row, col = np.divmod(inside, cells)
    target = cell_offsets(row, col, look, frame)
    target += world * (frame.side * frame.side)
    look.reshape(-1)[target] = state + np.uint8(TREE_BASE)


def window_cells(world: np.ndarray, rows: np.ndarray, cols: np.ndarray, radius: float, cells: int) -> np.ndarray:
    """Flat indices (N * W * W,) int64 of windows holding every cell within ``radius`` (cell units) of
    each of N points at fractional cell coordinates ``rows``, ``cols`` (N,) of worlds ``world`` (N,)."""
    half = math.ceil(radius) + 1
    size = min(2 * half + 1, cells)
    top = np.clip(np.floor(rows) - half, 0, cells - size).astype(np.int64)
    left = np.clip(np.floor(cols) - half, 0, cells - size).astype(np.int64)
    span = np.arange(size)
    row_start = (world.astype(np.int64) * cells + top)[:, None] + span  # (N, W)
    return (row_start[:, :, None] * cells + (left[:, None, None] + span)).reshape(-1)


def look_cameras(position: np.ndarray, heading: np.ndarray, look: np.ndarray, frame: ViewFrame,
                 facing: np.ndarray | None = None, mixed: bool = True) -> np.ndarray:
    """(B, A, P, P, 3) float32 downward views of planes at ``position`` (B, A, 2) / ``heading`` (B, A) over
    ``look`` (B worlds, either layout), identical to :func:`.camera.cameras` over the trees and ground.
    ``facing`` (B, A, 2) may give (cos, sin) of the headings when the caller has them; ``mixed`` False
    says that no pixel lies on a MIXED cell (every plane within ``frame.clear_m``), so none is looked for."""
    batch, agents = heading.shape
    pixels, area = frame.pixels, frame.side * frame.side
    rows, cols = _pixel_axes(position, heading, frame, facing)
    metres = np.add(rows[..., :, None], cols[..., None, :])  # (2, B, A, P, P): x, y
    keep = mixed and metres.size <= KEEP_METRES_UP_TO  # else the mixed pixels' coordinates are formed again
    cells = cell_of(metres, frame, keep=keep)  # col, row
    if batch * area >= 2**31:
        cells = cells.astype(np.int64)
    flat = cell_offsets(cells[1], cells[0], look, frame)
    if batch > 1:
        flat += (np.arange(batch, dtype=flat.dtype) * flat.dtype.type(area))[:, None, None, None]
    index = look.reshape(-1).take(flat)
    if mixed:
        _classify_mixed(index, metres if keep else None, rows, cols, frame)
    return colours(index).reshape(batch, agents, pixels, pixels, 3)


def _pixel_axes(position: np.ndarray, heading: np.ndarray, frame: ViewFrame,
                facing: np.ndarray | None) -> tuple[np.ndarray, np.ndarray]:
    """rows, cols (2, B, A, P) float32: pixel (r, c) lies at x = rows[0, ..., r] + cols[0, ..., c] and
    y = rows[1, ..., r] + cols[1, ..., c].

    These are the exact path's float32 operations in its order, x = (px + forward * cos) + right * sin
    and y = (py + forward * sin) - right * cos (adding -(right * cos) = (-right) * cos is subtracting it):
    the bracketed part depends on the pixel row only, the rest on the column only, so one broadcast pass
    forms both.
    """
    if facing is None:
        trig = np.stack([np.cos(heading), np.sin(heading)]).astype(np.float32)[..., None]  # (2, B, A, 1)
    else:
        trig = facing.transpose(2, 0, 1).astype(np.float32)[..., None]
    rows = position.transpose(2, 0, 1).astype(np.float32)[..., None] + frame.forward * trig
    cols = np.multiply(trig[::-1], frame.right_left)
    return rows, cols


def _classify_mixed(index: np.ndarray, metres: np.ndarray | None, rows: np.ndarray, cols: np.ndarray,
                    frame: ViewFrame) -> None:
    """Water ring or outside, by the exact test, for the pixels of ``index`` (B, A, P, P) on MIXED cells:
    on their coordinates ``metres`` (2, B, A, P, P) when given, else formed again from ``rows`` and ``cols``
    as :func:`look_cameras` formed them."""
    (mixed,) = np.nonzero(index.reshape(-1) == MIXED)
    if mixed.size == 0:
        return
    if metres is not None:
        xy = np.take(metres.reshape(2, -1), mixed, axis=1)
    else:
        pixels = frame.pixels
        row_of, col = np.divmod(mixed, pixels)  # row_of: camera * P + row
        col_of = row_of - row_of % pixels + col  # camera * P + col
        xy = np.take(rows.reshape(2, -1), row_of, axis=1) + np.take(cols.reshape(2, -1), col_of, axis=1)
    inside = np.logical_and.reduce(np.abs(xy) <= frame.border_half, axis=0)
    index.reshape(-1)[mixed] = np.where(inside, np.uint8(WATER_RING), np.uint8(OUTSIDE))


def colours(index: np.ndarray) -> np.ndarray:
    """(N, 3) float32 palette colours of uint8 palette indices ``index`` (any shape, N elements).

    Three pixels at a time through a table of every colour triple (a 36-byte copy per triple is
    faster than three 12-byte ones); one at a time for few pixels (the 2.5 MB table would not be in
    cache) or when N is not a multiple of 3.
    """
    flat = index.reshape(-1)
    if flat.size % 3 or flat.size < TRIPLES_FROM:
        return PALETTE_FLOAT.take(flat, axis=0)
    count = len(PALETTE_FLOAT)
    triple = np.multiply(flat[0::3], count * count, dtype=np.intp)
    triple += np.multiply(flat[1::3], count, dtype=np.intp)
    triple += flat[2::3]
    return _triple_palette().take(triple, axis=0).reshape(-1, 3)


@lru_cache(maxsize=1)
def _triple_palette() -> np.ndarray:
    """(K**3, 9) float32: the colours of palette indices (i, j, k) side by side at row (i * K + j) * K + k."""
    count = len(PALETTE_FLOAT)
    table = np.empty((count, count, count, 3, 3), np.float32)
    table[:, :, :, 0] = PALETTE_FLOAT[:, None, None, :]
    table[:, :, :, 1] = PALETTE_FLOAT[None, :, None, :]
    table[:, :, :, 2] = PALETTE_FLOAT[None, None, :, :]
    table.flags.writeable = False
    return table.reshape(count ** 3, 9)


def plane_cameras(position: np.ndarray, heading: np.ndarray, look: np.ndarray, trees: np.ndarray,
                  ground: np.ndarray, frame: ViewFrame, offsets: tuple[np.ndarray, np.ndarray],
                  facing: np.ndarray | None = None) -> np.ndarray:
    """(B, A, P, P, 3) float32 cameras: through ``look`` when every plane is within the frame's reach (planes
    stay within a step of the border, which the frame covers unless the border is very wide, see
    MAX_GROWTH), else by the exact path over trees and ground."""
    far = np.abs(position).max() if position.size else 0.0
    if far <= frame.safe_m:
        return look_cameras(position, heading, look, frame, facing, mixed=far > frame.clear_m)
    return cameras(position, heading, trees, ground, offsets, frame.island_half_m, frame.border_half_m)
