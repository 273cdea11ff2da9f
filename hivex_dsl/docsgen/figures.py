"""The generator sample figures that docs/generators.md shows (the same ones `hivex preview` writes)."""

from __future__ import annotations

import numpy as np

from ..procgen.preview import layout_figure


def preview_figures() -> dict[str, tuple[str, np.ndarray]]:
    """docs-relative PNG path -> (caption, (H, W, 3) uint8 picture)."""
    return {
        "images/wind_farm_control_layouts.png": (
            "Wind Farm Control layout patterns 0-7 (Default, Grid, Chain, Circle; Square, Cross, Two Rows, Field) "
            "with 8 turbines at the default spacing, then pattern 8 (Random) for seeds 0-3, on the 1200 m farm.",
            layout_figure()),
    }
