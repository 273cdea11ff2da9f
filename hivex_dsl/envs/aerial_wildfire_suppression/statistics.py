"""The statistics Aerial Wildfire Suppression logs ("AerialWildfireSuppression/<name>"), from the simulator's events."""

from __future__ import annotations

import numpy as np

from ...sim.statistics import StatisticSet

STATISTICS = StatisticSet("aerial_wildfire_suppression", "AerialWildfireSuppression")


def _every_plane(state, world_events: np.ndarray) -> np.ndarray:
    """(B,) -> (B, A): a world's event counted for each of its planes (a read-only view)."""
    return np.broadcast_to(world_events[:, None], state.flying.shape)


@STATISTICS.counter("Crash Count", "Times the plane crossed the border (its episode ends).")
def crash_count(prev, state, actions, params):
    return state.crossed


@STATISTICS.counter("Water Pickup", "Times the plane filled up with water in the ring around the island.")
def water_pickup(prev, state, actions, params):
    return state.picked_up


@STATISTICS.counter("Water Drop", "Times the plane dropped its water.")
def water_drop(prev, state, actions, params):
    return state.dropped


@STATISTICS.counter("Extinguishing Trees", "Burning trees this plane's drops turned wet.")
def extinguishing_trees(prev, state, actions, params):
    return state.extinguished


@STATISTICS.counter("Preparing Trees", "Existing (not burning) trees this plane's drops turned wet.")
def preparing_trees(prev, state, actions, params):
    return state.prepared


@STATISTICS.counter("Fire Out", "Times the fire on the island went out (counted for every plane of the world).")
def fire_out(prev, state, actions, params):
    counted = _every_plane(state, state.fire_went_out)
    return counted & state.flying if params.finished_planes == "wait" else counted  # not a waiting plane's


@STATISTICS.counter("Fire too Close to City",
                    "Times a burning tree first came into the village's zone (every plane of the world).")
def fire_too_close_to_city(prev, state, actions, params):
    return _every_plane(state, state.village_threatened)


STATISTICS.mirror("Extinguishing Trees Reward", "What the task paid for extinguishing trees (weighted).",
                  "extinguishing_tree")
STATISTICS.mirror("Preparing Trees Reward", "What the task paid for preparing trees (weighted).", "preparing_tree")
