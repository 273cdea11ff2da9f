"""Top-down picture of one Ocean Plastic Collection world: heat map, floating pebbles, vessels."""

from __future__ import annotations

import numpy as np

from ...sim.procgen.preview import resample
from ...sim.render.canvas import Canvas, colormap
from .params import OceanPlasticCollectionParams
from .types import OceanState

SIZE_PX = 480
# Dark navy (clean water) to sandy orange (most polluted): pebbles and vessels stay visible on both.
SEA_STOPS = np.array([[10, 40, 90], [30, 90, 140], [90, 150, 160], [200, 170, 110]], np.uint8)
PEBBLE_COLOR = (250, 250, 250)
VESSEL_COLORS = np.array([[230, 60, 50], [60, 200, 80], [250, 210, 40], [200, 80, 220], [40, 200, 230],
                          [250, 140, 30]], np.uint8)
ENDED_COLOR = (120, 120, 120)
VESSEL_MIN_PX = 6.0


def draw_ocean(state: OceanState, index: int, params: OceanPlasticCollectionParams, half_extent: float) -> np.ndarray:
    """(SIZE_PX, SIZE_PX, 3) uint8. Background: the pollution heat map (navy clean, sand polluted);
    white dots: floating pebbles; each vessel a black-rimmed coloured disk (grey once ended) with a
    black pointer along its heading and a thin ring at the close distance."""
    canvas = Canvas(SIZE_PX, half_extent)
    heat = state.heat[index]
    canvas.fill(colormap(resample(heat, SIZE_PX), 0.0, float(heat.max()), SEA_STOPS))
    field = state.pebbles
    floating = field.positions[index][field.alive[index]]
    if len(floating):
        canvas.disks(floating, 0.7, PEBBLE_COLOR)

    position, heading, active = state.position[index], state.heading[index], state.active[index]
    facing = np.stack([np.cos(heading), np.sin(heading)], axis=-1)
    colors = VESSEL_COLORS[np.arange(len(position)) % len(VESSEL_COLORS)]
    colors = np.where(active[:, None], colors, np.array(ENDED_COLOR, np.uint8))
    # Drawn larger than life (a 400 m world is 480 px) so every vessel and its heading stay visible.
    size = max(params.collision_distance_m / 2.0, VESSEL_MIN_PX / canvas.px_per_m)
    canvas.rings(position, params.close_distance_m, 1.0, colors)
    canvas.disks(position, size + 1.5 / canvas.px_per_m, (0, 0, 0))
    canvas.disks(position, size, colors)
    canvas.segments(position, position + facing * 2.2 * size, 3.0, (0, 0, 0))
    return canvas.image()
