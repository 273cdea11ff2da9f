"""Top-down picture of one Wind Farm Control world: the wind field, turbines with heading and power."""

from __future__ import annotations

import numpy as np

from ...sim.procgen.wind import WindSpec, local_wind, wind_worlds
from ...sim.render.canvas import Canvas, colormap, hue_wheel, upscale
from .params import WindFarmControlParams
from .types import WindFarmState

SIZE_PX = 480
FIELD_CELLS = 60  # wind field colour samples per side
ARROW_CELLS = 12  # wind arrows per side


def _grid(half_extent: float, cells: int) -> np.ndarray:
    """(cells*cells, 2) cell centres covering the square, rows from the top (+y) down."""
    centres = (np.arange(cells) + 0.5) / cells * 2.0 * half_extent - half_extent
    x, y = np.meshgrid(centres, centres[::-1])
    return np.stack([x.ravel(), y.ravel()], axis=-1)


def _world_wind(state: WindFarmState, index: int, points: np.ndarray, spec: WindSpec) -> np.ndarray:
    """Wind direction of world ``index`` at (N, 2) points -> (N,)."""
    return local_wind(wind_worlds(state.wind, slice(index, index + 1)), points[None], spec)[0]


def draw_wind_farm(state: WindFarmState, index: int, params: WindFarmControlParams, spec: WindSpec) -> np.ndarray:
    """(SIZE_PX, SIZE_PX, 3) uint8. Background hue = local wind direction; grey arrows show it;
    each turbine is a disk coloured by its power (dark = 0, yellow = 1) with a black rotor bar
    across its heading and a short pointer toward where it faces."""
    half = params.farm_half_extent_m
    canvas = Canvas(SIZE_PX, half, background=(255, 255, 255))
    field = _world_wind(state, index, _grid(half, FIELD_CELLS), spec).reshape(FIELD_CELLS, FIELD_CELLS)
    canvas.fill(upscale(hue_wheel(field), SIZE_PX // FIELD_CELLS))
    arrow_points = _grid(half, ARROW_CELLS)
    arrow_dirs = _world_wind(state, index, arrow_points, spec)
    arrow_len = 1.2 * half / ARROW_CELLS
    vectors = arrow_len * np.stack([np.cos(arrow_dirs), np.sin(arrow_dirs)], axis=-1)
    canvas.arrows(arrow_points - vectors / 2, vectors, 1.5, (120, 120, 120))

    positions = state.positions[index]
    heading = state.heading[index]
    facing = np.stack([np.cos(heading), np.sin(heading)], axis=-1)
    across = np.stack([-facing[:, 1], facing[:, 0]], axis=-1)
    size = 0.45 * params.turbine_spacing_m
    power = np.clip(state.performance[index], 0.0, 1.0)
    canvas.disks(positions, size * 0.7, colormap(power))
    canvas.segments(positions - across * size, positions + across * size, 4.0, (20, 20, 20))
    canvas.segments(positions, positions + facing * size * 0.9, 2.5, (20, 20, 20))

    main = state.wind.main[index]
    corner = np.array([[-0.85 * half, 0.85 * half]])
    main_vector = 0.12 * half * np.array([[np.cos(main), np.sin(main)]])
    canvas.disks(corner, 0.1 * half, (255, 255, 255))
    canvas.arrows(corner - main_vector / 2, main_vector, 4.0, (30, 60, 160))
    return canvas.image()
