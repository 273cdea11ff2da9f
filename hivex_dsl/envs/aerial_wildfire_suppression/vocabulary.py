"""What an expression may read in Aerial Wildfire Suppression: planes, water, the fire they see, the village.

Readers take the simulator's state and the step's events; the distances are the hypotenuses of the
state's positions (the state keeps positions, not the distances between them).
"""

from __future__ import annotations

import math

import numpy as np

from ...sim.fire import TreeState, burning_count
from ...sim.reward.vocabulary import Vocabulary, flag, quantity
from .simulator import EVENTS
from .terms import MAX_TREES_PER_DROP


def declare(compiled) -> dict:
    p = compiled.params
    reach = p.border_half_extent_m + p.plane_speed_m  # a plane stops where it crossed the border
    island = p.island_half_extent_m
    cells = compiled.generators["forest"].cells
    view = p.fire_view_half_m * math.sqrt(2.0)
    items = [
        quantity("x_m", "agent", "number", "m", -reach, reach, "The plane's position east of the island centre."),
        quantity("y_m", "agent", "number", "m", -reach, reach, "The plane's position north of the island centre."),
        quantity("heading_rad", "agent", "number", "rad", -math.pi, math.pi,
                 "Where the plane flies, counter-clockwise from east."),
        flag("holding_water", "agent", "The plane carries water."),
        flag("flying", "agent", "The plane is still in the game (it has not crossed the border or ended its task)."),
        quantity("village_x_m", "world", "number", "m", -island, island, "The village centre, east of the island centre."),
        quantity("village_y_m", "world", "number", "m", -island, island, "The village centre, north of the island centre."),
        quantity("distance_to_village_m", "agent", "number", "m", 0.0, math.sqrt(2.0) * (reach + island),
                 "Distance from the plane to the village centre."),
        flag("sees_fire", "agent", "A burning tree lies within the plane's view square (fire_view_half_m)."),
        quantity("distance_to_fire_m", "agent", "number", "m", 0.0, view,
                 "Distance to the closest burning tree in view; the view's corner distance when none is in view."),
        quantity("fire_to_village_m", "agent", "number", "m", 0.0, 2.0 * math.sqrt(2.0) * island,
                 "Distance from the closest burning tree in the plane's view to the village; 0 when none is in view."),
        quantity("burning_trees", "world", "number", "trees", 0.0, float(cells * cells),
                 "Trees burning on the island after the step."),
        flag("fire_near_village", "world", "A burning tree lies in the village's zone (params.village_zone)."),
        quantity("extinguished_trees", "agent", "number", "trees", 0.0, MAX_TREES_PER_DROP,
                 "Burning trees the plane's drop made wet this step."),
        quantity("prepared_trees", "agent", "number", "trees", 0.0, MAX_TREES_PER_DROP,
                 "Unburnt trees the plane's drop made wet this step."),
        quantity("trees_near_village", "world", "number", "trees", 0.0, float(_window(compiled)[0].size),
                 "Unburnt trees (existing or wet) whose cell centre lies within village_radius_m of the village."),
        quantity("burning_near_village", "world", "number", "trees", 0.0, float(_window(compiled)[0].size),
                 "Burning trees whose cell centre lies within village_radius_m of the village."),
        flag("crossed_border", "agent", "The plane crossed the border this step (its episode ends)."),
        flag("village_threatened", "world", "Fire came into the village's zone for the first time."),
    ]
    items += [flag(event, "world" if event == "fire_out" else "agent", description[:1].upper() + description[1:] + ".")
              for event, description in EVENTS.items()]
    return {q.name: q for q in items}


def _window(compiled) -> tuple[np.ndarray, np.ndarray]:
    """Row and column offsets (K,) of the cells around the village's cell that may lie within the radius."""
    forest = compiled.generators["forest"]
    reach = int(math.ceil(compiled.params.village_radius_m / forest.spacing_m)) + 1
    rows, cols = np.mgrid[-reach:reach + 1, -reach:reach + 1]
    return rows.ravel(), cols.ravel()


def _near_village(state, compiled) -> tuple[np.ndarray, np.ndarray]:
    """(B, K) tree states of the cells around each village and whether each cell centre is within the radius."""
    forest = compiled.generators["forest"]
    spacing, half, cells = forest.spacing_m, forest.half_extent_m, forest.cells
    village = state.maps.village
    centre = np.floor((village + half) / spacing).astype(np.int64)  # (B, 2) column (x), row (y)
    d_rows, d_cols = _window(compiled)
    rows, cols = centre[:, 1:2] + d_rows, centre[:, 0:1] + d_cols
    on_grid = (rows >= 0) & (rows < cells) & (cols >= 0) & (cols < cells)
    x = -half + (cols + 0.5) * spacing - village[:, 0:1]
    y = -half + (rows + 0.5) * spacing - village[:, 1:2]
    inside = on_grid & (np.hypot(x, y) <= compiled.params.village_radius_m)
    worlds = np.arange(len(village))[:, None]
    trees = state.fire.trees[worlds, np.clip(rows, 0, cells - 1), np.clip(cols, 0, cells - 1)]
    return trees, inside


def _trees_near_village(state, events, compiled) -> np.ndarray:
    trees, inside = _near_village(state, compiled)
    unburnt = (trees == TreeState.EXISTING) | (trees == TreeState.WET)
    return np.count_nonzero(unburnt & inside, axis=1).astype(np.float64)


def _burning_near_village(state, events, compiled) -> np.ndarray:
    trees, inside = _near_village(state, compiled)
    return np.count_nonzero((trees == TreeState.BURNING) & inside, axis=1).astype(np.float64)


def _village_gap(state) -> np.ndarray:
    return state.position - state.maps.village[:, None, :]


def _fire_distance(state, events, compiled) -> np.ndarray:
    gap = state.sighting.plane_xy - state.position
    far = compiled.params.fire_view_half_m * math.sqrt(2.0)
    return np.where(state.sighting.plane_found, np.minimum(np.hypot(gap[..., 0], gap[..., 1]), far), far)


def _fire_to_village(state, events, compiled) -> np.ndarray:
    gap = state.sighting.plane_xy - state.maps.village[:, None, :]
    return np.where(state.sighting.plane_found, np.hypot(gap[..., 0], gap[..., 1]), 0.0)


READERS = {
    "x_m": lambda s, e, c: s.position[..., 0],
    "y_m": lambda s, e, c: s.position[..., 1],
    "heading_rad": lambda s, e, c: s.heading,
    "holding_water": lambda s, e, c: s.water,
    "flying": lambda s, e, c: s.flying,
    "village_x_m": lambda s, e, c: s.maps.village[:, 0],
    "village_y_m": lambda s, e, c: s.maps.village[:, 1],
    "distance_to_village_m": lambda s, e, c: np.hypot(*np.moveaxis(_village_gap(s), -1, 0)),
    "sees_fire": lambda s, e, c: s.sighting.plane_found,
    "distance_to_fire_m": _fire_distance,
    "fire_to_village_m": _fire_to_village,
    "burning_trees": lambda s, e, c: burning_count(s.fire).astype(np.float64),
    "fire_near_village": lambda s, e, c: s.sighting.village_threat,
    "extinguished_trees": lambda s, e, c: s.extinguished.astype(np.float64),
    "prepared_trees": lambda s, e, c: s.prepared.astype(np.float64),
    "trees_near_village": _trees_near_village,
    "burning_near_village": _burning_near_village,
    "crossed_border": lambda s, e, c: s.crossed,
    "village_threatened": lambda s, e, c: s.village_threatened,
    "picked_up_water": lambda s, e, c: s.picked_up,
    "dropped_water": lambda s, e, c: s.dropped,
    "found_fire": lambda s, e, c: s.found_fire,
    "found_village": lambda s, e, c: s.found_village,
    "fire_out": lambda s, e, c: s.fire_went_out,
}

VOCABULARY = Vocabulary("aerial_wildfire_suppression", declare, READERS)
