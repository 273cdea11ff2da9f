"""The paper's sample figures, drawn from the live generators as RGB arrays (PNG via `hivex preview`)."""

from __future__ import annotations

from typing import Sequence

import numpy as np

from ..render.canvas import Canvas, colormap
from .layouts import PATTERN_NAMES, turbine_layout

GAP_PX = 4
WHITE = (255, 255, 255)


def tile(images: Sequence[np.ndarray], columns: int, gap: int = GAP_PX) -> np.ndarray:
    """Equal-sized (H, W, 3) uint8 images laid out row by row on white, ``gap`` pixels apart."""
    if not images:
        raise ValueError("tile needs at least one image")
    height, width = images[0].shape[:2]
    if any(image.shape != images[0].shape for image in images):
        raise ValueError("tile needs images of one shape")
    rows = -(-len(images) // columns)
    sheet = np.full((rows * (height + gap) + gap, columns * (width + gap) + gap, 3), 255, np.uint8)
    for k, image in enumerate(images):  # a handful of figure tiles, not a hot path
        r, c = divmod(k, columns)
        top, left = gap + r * (height + gap), gap + c * (width + gap)
        sheet[top:top + height, left:left + width] = image
    return sheet


def layout_figure(agents: int = 8, random_seeds: Sequence[int] = (0, 1, 2, 3), spacing: float = 70.0,
                  half_extent: float = 600.0, size_px: int = 160) -> np.ndarray:
    """Patterns 0-7 with ``agents`` turbines, then pattern 8 (Random) for each seed: the paper's figure."""
    tiles = []
    for pattern in range(len(PATTERN_NAMES) - 1):
        tiles.append(_turbines(turbine_layout(pattern, agents, spacing, half_extent), half_extent, size_px))
    for seed in random_seeds:
        positions = turbine_layout(8, agents, spacing, half_extent, np.random.default_rng(seed))
        tiles.append(_turbines(positions, half_extent, size_px, color=(200, 90, 40)))
    return tile(tiles, columns=4)


def _turbines(positions: np.ndarray, half_extent: float, size_px: int, color=(30, 60, 160)) -> np.ndarray:
    canvas = Canvas(size_px, half_extent, background=(236, 242, 248))
    canvas.disks(positions, half_extent / 30, color)
    return canvas.image()


def heat_tile(values: np.ndarray, low: float, high: float, size_px: int) -> np.ndarray:
    """A (R, R) field, row index increasing with y, as a (size_px, size_px, 3) picture with +y up."""
    rows = np.linspace(values.shape[0] - 1, 0, size_px).round().astype(int)
    cols = np.linspace(0, values.shape[1] - 1, size_px).round().astype(int)
    return colormap(values[np.ix_(rows, cols)], low, high)
