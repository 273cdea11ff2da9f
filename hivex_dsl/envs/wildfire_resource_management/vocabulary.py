"""What an expression may read in Wildfire Resource Management: towers, resources, the fire each one sees.

Readers take the simulator's state: the sighting (distance, approaching, performance) is the one
the simulator computed for the step; nothing is searched again.
"""

from __future__ import annotations

import numpy as np

from ...fire import burning_count
from ...reward.vocabulary import Vocabulary, flag, quantity
from .resources import TARGETS_PER_AGENT
from .terms import performance_of


def declare(compiled) -> dict:
    p, agents = compiled.params, compiled.agents
    cells = compiled.generators["forest"].cells
    items = [
        quantity("resources_received", "agent", "number", "1", 0.0, float(agents),
                 "Resources the tower receives from every agent, itself included (1 = one agent's whole share)."),
        quantity("resources_unallocated", "agent", "number", "1", 0.0, 1.0, "The share the agent has not given away."),
        quantity("resources_kept", "agent", "number", "1", 0.0, 1.0, "The share the agent gives to its own tower."),
        flag("sees_fire", "agent", "A burning tree lies within the tower's detection radius."),
        quantity("distance_to_fire_m", "agent", "number", "m", 0.0, p.detection_radius_m,
                 "3-D distance to the closest burning tree in range; the detection radius when none is."),
        flag("fire_approaching", "agent", "The closest fire in range came closer at the last fire step."),
        quantity("tower_performance", "agent", "number", "1", 0.0, 1.0,
                 "The paper's tower performance P from the distance to the fire (idle_performance when none)."),
        quantity("impossible_moves", "agent", "number", "moves", 0.0, float(TARGETS_PER_AGENT),
                 "Add or subtract components of the agent's last action that could not happen."),
        quantity("burning_trees", "world", "number", "trees", 0.0, float(cells * cells), "Trees burning after the step."),
        flag("fire_out", "world", "The fire on the whole island went out this step."),
    ]
    return {q.name: q for q in items}


def _performance(state, events, compiled) -> np.ndarray:
    sighting = state.sighting
    if sighting.performance is not None:
        return sighting.performance
    return performance_of(sighting.distance, sighting.approaching, sighting.seen, compiled.params)


READERS = {
    "resources_received": lambda s, e, c: s.support / 10.0,
    "resources_unallocated": lambda s, e, c: s.budget / 10.0,
    "resources_kept": lambda s, e, c: s.allocation[..., 0] / 10.0,
    "sees_fire": lambda s, e, c: s.sighting.seen,
    "distance_to_fire_m": lambda s, e, c: np.minimum(s.sighting.distance, c.params.detection_radius_m),
    "fire_approaching": lambda s, e, c: s.sighting.approaching,
    "tower_performance": _performance,
    "impossible_moves": lambda s, e, c: s.impossible.astype(np.float64),
    "burning_trees": lambda s, e, c: burning_count(s.fire).astype(np.float64),
    "fire_out": lambda s, e, c: s.fire_went_out,
}

VOCABULARY = Vocabulary("wildfire_resource_management", declare, READERS)
