"""The batched state of Ocean Plastic Collection."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np


@dataclass(frozen=True)
class PebbleField:
    """The floating plastic of B worlds: a fixed-size pebble array with an alive mask.

    Pebbles never move; they are stored sorted by the cell of a square grid (``cells`` x ``cells``
    cells of ``cell_m`` metres over the world, row-major with the row along y). The pebbles near
    grid cell ``k`` of world ``b`` -- its block of surrounding cells -- are the row slices
    ``first : first + length`` of ``z[b]``, one per block row ``r``, with
    ``first, length = blocks[b, k, r]``.
    """

    z: np.ndarray  # (B, N) complex128 positions x + i y in metres (one gather fetches both coordinates)
    alive: np.ndarray  # (B, N) bool: still floating
    blocks: np.ndarray  # (B, cells * cells, block rows, 2) int64 a block row's first pebble and length (0 off the grid)
    cells: int  # grid cells per side
    cell_m: float  # side of one grid cell in metres

    @property
    def positions(self) -> np.ndarray:
        """(B, N, 2) pebble positions in metres."""
        return np.stack([self.z.real, self.z.imag], axis=-1)


@dataclass(frozen=True)
class OceanState:
    """B worlds of A vessels. Headings are radians counter-clockwise from +x."""

    position: np.ndarray  # (B, A, 2) metres
    heading: np.ndarray  # (B, A)
    speed: np.ndarray  # (B, A) metres per step, >= 0
    active: np.ndarray  # (B, A) bool: still in the world (False once a crash ended it)
    crashed: np.ndarray  # (B, A) bool: crossed the border or hit a vessel this step
    crossed_border: np.ndarray  # (B, A) bool, this step
    collided_vessel: np.ndarray  # (B, A) bool, this step
    closest: np.ndarray  # (B, A) metres to the closest other active vessel (inf without one)
    collected: np.ndarray  # (B, A) int64 pebbles collected this step
    collected_total: np.ndarray  # (B, A) int64 pebbles collected this episode
    decision_collected: np.ndarray  # (B, A) int64 pebbles collected since the decision began (0 without a cap)
    tick: np.ndarray  # (B,) int64 physics steps since the world's reset: a decision begins where tick % period == 0
    nearby: np.ndarray  # (B, A) int64 pebbles within the nearby radius (0 at reset)
    nearby_best: np.ndarray  # (B, A) int64 highest nearby count of the vessel's episode (0 at reset: ntc_old = 0)
    pebbles: PebbleField
    heat: np.ndarray  # (B, R, R) pollution heat map the pebbles were drawn from (for rendering)
    vector: np.ndarray  # (B, A, 12) float32 vector observation, newest stack first
    visual: np.ndarray  # (B, A, 25, 25, 2) float32 trash camera, newest stack first on the last axis
