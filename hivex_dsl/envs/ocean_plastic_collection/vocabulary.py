"""What an expression may read in Ocean Plastic Collection: vessels, their neighbours and the pebbles.

Readers take the simulator's state: the closest other vessel and the nearby pebble count are the
ones the simulator sensed this step (the state keeps them; nothing is searched again).
"""

from __future__ import annotations

import math

import numpy as np

from ...sim.reward.vocabulary import Vocabulary, flag, quantity


def _reach(compiled) -> tuple[float, float]:
    """(top speed, how far from the centre a vessel can be): it stops where it crossed the border."""
    p = compiled.params
    top_speed = p.top_speed_m  # speed <- speed (1 - drag) + acceleration * throttle from rest, at most the cap
    return top_speed, compiled.generators["pollution"].half_extent_m + top_speed


def declare(compiled) -> dict:
    top_speed, reach = _reach(compiled)
    far = 2.0 * math.sqrt(2.0) * reach
    count = float(compiled.generators["pollution"].pebble_count)
    items = [
        quantity("x_m", "agent", "number", "m", -reach, reach, "The vessel's position east of the world centre."),
        quantity("y_m", "agent", "number", "m", -reach, reach, "The vessel's position north of the world centre."),
        quantity("heading_rad", "agent", "number", "rad", -math.pi, math.pi,
                 "Where the vessel faces, counter-clockwise from east."),
        quantity("speed_m", "agent", "number", "m", 0.0, top_speed, "Metres the vessel moved this step."),
        quantity("distance_to_nearest_vessel_m", "agent", "number", "m", 0.0, far,
                 "Distance to the closest other vessel still in the world; the world's diagonal when there is none."),
        quantity("pebbles_nearby", "agent", "number", "pebbles", 0.0, count,
                 "Floating pebbles within nearby_radius_m of the vessel."),
        quantity("pebbles_nearby_best", "agent", "number", "pebbles", 0.0, count,
                 "The highest pebbles_nearby of the vessel's episode so far (Nearby Trash Count Delta's running "
                 "maximum; 0 before the first step)."),
        quantity("pebbles_collected", "agent", "number", "pebbles", 0.0, count, "Pebbles the vessel collected this step."),
        quantity("pebbles_collected_total", "agent", "number", "pebbles", 0.0, count,
                 "Pebbles the vessel collected this episode."),
        quantity("pebbles_left", "world", "number", "pebbles", 0.0, count, "Pebbles still floating in the world."),
        flag("active", "agent", "The vessel is still in the world."),
        flag("crossed_border", "agent", "The vessel left the square world this step."),
        flag("collided_with_other_vessel", "agent",
             "The vessel came closer than collision_distance_m to another vessel this step."),
        flag("collided_with_trash", "agent", "The vessel's collector picked up at least one pebble this step."),
    ]
    return {q.name: q for q in items}


def _nearest(state, events, compiled) -> np.ndarray:
    return np.minimum(state.closest, 2.0 * math.sqrt(2.0) * _reach(compiled)[1])


READERS = {
    "x_m": lambda s, e, c: s.position[..., 0],
    "y_m": lambda s, e, c: s.position[..., 1],
    "heading_rad": lambda s, e, c: s.heading,
    "speed_m": lambda s, e, c: s.speed,
    "distance_to_nearest_vessel_m": _nearest,
    "pebbles_nearby": lambda s, e, c: s.nearby.astype(np.float64),
    "pebbles_nearby_best": lambda s, e, c: s.nearby_best.astype(np.float64),
    "pebbles_collected": lambda s, e, c: s.collected.astype(np.float64),
    "pebbles_collected_total": lambda s, e, c: s.collected_total.astype(np.float64),
    "pebbles_left": lambda s, e, c: np.count_nonzero(s.pebbles.alive, axis=1).astype(np.float64),
    "active": lambda s, e, c: s.active,
    "crossed_border": lambda s, e, c: s.crossed_border,
    "collided_with_other_vessel": lambda s, e, c: s.collided_vessel,
    "collided_with_trash": lambda s, e, c: s.collected > 0,
}

VOCABULARY = Vocabulary("ocean_plastic_collection", declare, READERS)
