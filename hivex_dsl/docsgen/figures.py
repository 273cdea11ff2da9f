"""The generator sample figures that docs/generators.md shows (the same ones `hivex preview` writes)."""

from __future__ import annotations

from functools import lru_cache

import numpy as np

from ..sim.procgen.preview import layout_figure, pollution_figure, terrain_figure


FIGURES = {  # docs-relative PNG path -> (caption, the function drawing it)
    "images/wind_farm_control_layouts.png": (
        "Wind Farm Control layout patterns 0-7 (Default, Grid, Chain, Circle; Square, Cross, Two Rows, Field) "
        "with 8 turbines at the default spacing, then pattern 8 (Random) for seeds 0-3, on the 1200 m farm.",
        layout_figure),
    "images/terrain_levels.png": (
        "Terrain elevation levels 1-10 (rows, top to bottom) for seeds 0-7 (columns), on one colour scale from "
        "sea (blue) to the highest peak (white); the red dot is the flattened village.",
        terrain_figure),
    "images/ocean_pollution.png": (
        "Ocean Plastic Collection pollution heat maps for seeds 0-19 (dark: clean, yellow: most polluted) with the "
        "spawn points of 3 vessels.",
        pollution_figure),
}


@lru_cache(maxsize=None)
def preview_figure(rel: str) -> tuple[str, np.ndarray]:
    """One figure of :data:`FIGURES`: (caption, (H, W, 3) uint8 picture), drawn once."""
    caption, draw = FIGURES[rel]
    return caption, draw()


def preview_figures() -> dict[str, tuple[str, np.ndarray]]:
    """docs-relative PNG path -> (caption, (H, W, 3) uint8 picture), for every figure."""
    return {rel: preview_figure(rel) for rel in FIGURES}
