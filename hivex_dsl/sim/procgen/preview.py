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


def resample(values: np.ndarray, size_px: int) -> np.ndarray:
    """Nearest-neighbour (size_px, size_px) view of an (R, R) field whose row index increases with y,
    flipped so that row 0 is the top (+y up, as on a Canvas)."""
    rows = np.linspace(values.shape[0] - 1, 0, size_px).round().astype(int)
    cols = np.linspace(0, values.shape[1] - 1, size_px).round().astype(int)
    return values[np.ix_(rows, cols)]


TERRAIN_STOPS = np.array([[70, 120, 60], [120, 150, 80], [170, 150, 100], [140, 110, 80], [245, 245, 245]], np.uint8)
SEA = np.array([70, 130, 190], np.uint8)


def terrain_figure(levels: Sequence[int] = tuple(range(1, 11)), seeds: Sequence[int] = tuple(range(8)),
                   size_px: int = 72) -> np.ndarray:
    """Terrain elevation levels (rows, top to bottom) x seeds (columns), the paper's figure.

    One shared colour scale (0 m to the highest peak shown) so the levels compare; sea is blue,
    the flattened village a red dot."""
    from .terrain import generate_terrain, terrain_spec_for_level

    terrains = [generate_terrain(np.random.default_rng(seed), terrain_spec_for_level(level))
                for level in levels for seed in seeds]
    top = max(float(t.heights.max()) for t in terrains)
    return tile([_terrain_tile(t, top, size_px) for t in terrains], columns=len(seeds), gap=2)


def _terrain_tile(terrain, top_m: float, size_px: int) -> np.ndarray:
    heights = resample(terrain.heights, size_px)
    canvas = Canvas(size_px, terrain.extent_m / 2)
    canvas.fill(np.where((heights <= 0.0)[..., None], SEA, colormap(heights, 0.0, top_m, TERRAIN_STOPS)))
    canvas.disks(terrain.village[None], terrain.extent_m / 40, (210, 40, 40))
    return canvas.image()


def pollution_figure(seeds: Sequence[int] = tuple(range(20)), agents: int = 3, size_px: int = 120) -> np.ndarray:
    """Pollution heat maps for ``seeds`` with the vessels' spawn points (white), 5 per row."""
    from .pollution import load_pollution_preset, pollution_map, spawn_vessels

    preset = load_pollution_preset()
    tiles = []
    for seed in seeds:
        rng = np.random.default_rng(seed)
        heat = pollution_map(rng, preset.pollution)[0]
        spawns, _ = spawn_vessels(rng, preset.spawn, 1, agents)
        canvas = Canvas(size_px, preset.pollution.half_extent_m)
        canvas.fill(colormap(resample(heat, size_px), 0.0, float(heat.max())))
        canvas.disks(spawns[0], preset.pollution.half_extent_m / 14, (20, 20, 20))
        canvas.disks(spawns[0], preset.pollution.half_extent_m / 22, (255, 255, 255))
        tiles.append(canvas.image())
    return tile(tiles, columns=5)
