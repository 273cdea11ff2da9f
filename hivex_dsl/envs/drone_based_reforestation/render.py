"""Top-down picture of one Drone-Based Reforestation world: shaded terrain, forest, planted trees,
the station with its charge radius, and the drones coloured by altitude."""

from __future__ import annotations

import numpy as np

from ...sim.render.canvas import Canvas, colormap
from ...sim.grids import sample_bilinear
from .fertility import FAR_M
from .types import STATION_PAD_M, DroneState

SIZE_PX = 480
# low ground olive -> dry grass -> bare rock, by height over the height bound
TERRAIN_STOPS = np.array([[92, 110, 62], [150, 150, 92], [196, 178, 128], [228, 220, 204]], dtype=np.uint8)
FOREST = (28, 78, 36)
PLANTED = (120, 230, 60)
POOR = (190, 120, 70)  # a planted tree whose seed had no quality (under the canopy, too far out or crowded)
STATION = (250, 250, 250)
CHARGE_RING = (60, 60, 200)
DEAD = (130, 130, 130)
SEED = (240, 140, 20)


def _terrain(canvas: Canvas, heights: np.ndarray, sim) -> np.ndarray:
    """(H, W, 3) terrain coloured by height (lowland to the world's highest point) with hill shading from
    the north-west, exaggerated so the relief shows at every terrain level."""
    x, y = canvas.pixel_centres()
    points = np.stack([x.ravel(), y.ravel()], axis=-1)[None]
    height = sample_bilinear(heights[None], sim.terrain_grid, points)[0].reshape(x.shape)
    top = max(float(heights.max()), 1.0)
    base = colormap(height, 0.0, top, TERRAIN_STOPS).astype(np.float64)
    slope_y, slope_x = np.gradient(height * (4.0 * sim.params.height_bound_m / top), 1.0 / canvas.px_per_m)
    shade = np.clip(1.0 + 0.5 * (slope_x + slope_y) / np.sqrt(1.0 + slope_x**2 + slope_y**2), 0.55, 1.35)
    return np.clip(base * shade[..., None], 0, 255)


def draw_reforestation(state: DroneState, index: int, sim) -> np.ndarray:
    """(SIZE_PX, SIZE_PX, 3) uint8. Drones: white-rimmed disks coloured by altitude (viridis, 0 to the
    height bound) and growing with it, a black pointer for the heading, an orange dot while carrying a
    seed, grey once the battery is empty. The forest is dark green, planted trees light green (brown where
    the seed had no quality)."""
    p = sim.params
    canvas = Canvas(SIZE_PX, sim.half, background=(0, 0, 0))
    canvas.fill(_terrain(canvas, state.heights[index], sim))
    trees = state.tree_xy[index].reshape(-1, 2)
    canvas.disks(trees[trees[:, 0] < FAR_M].astype(np.float64), p.tree_crown_radius_m, FOREST)
    planted = state.new_trees[index, : state.new_count[index]].astype(np.float64)
    if len(planted):
        quality = state.new_quality[index, : state.new_count[index], None]
        canvas.disks(planted, p.tree_crown_radius_m + 1.0, (20, 60, 20))
        canvas.disks(planted, p.tree_crown_radius_m + 0.3, np.where(quality > 0, PLANTED, POOR))
    station = state.station[index, None, :2]
    canvas.rings(station, p.charge_radius_m, 2.0, CHARGE_RING)
    canvas.rectangles(station - STATION_PAD_M, station + STATION_PAD_M, STATION)

    xy = state.position[index, :, :2]
    altitude = state.position[index, :, 2] / p.height_bound_m
    alive = state.alive[index]
    colours = np.where(alive[:, None], colormap(altitude), np.array(DEAD, np.uint8))
    radius = 3.5 + 4.0 * altitude
    facing = np.stack([np.cos(state.heading[index]), np.sin(state.heading[index])], axis=-1)
    canvas.disks(xy, radius + 1.2, (255, 255, 255))
    canvas.disks(xy, radius, colours)
    canvas.segments(xy, xy + facing * (radius + 5.0)[:, None], 2.5, (20, 20, 20))
    carrying = state.holding[index] & alive
    if carrying.any():
        canvas.disks(xy[carrying], 1.5, SEED)
    return canvas.image()
