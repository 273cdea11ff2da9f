"""What an expression may read in Wildfire Resource Management: towers, resources, the fire each one sees.

Readers take the simulator's state: the sighting (distance, approaching, performance) is the one
the simulator computed for the step; nothing is searched again. The vocabulary holds numbers per agent
or per world, not per-agent vectors, so each of an agent's three neighbours has its own quantities
(``neighbour1_distance_to_fire_m`` ...): its tower's value, gathered through the neighbour table.
"""

from __future__ import annotations

import numpy as np

from ...sim.fire import burning_count
from ...sim.reward.vocabulary import Vocabulary, flag, quantity
from .resources import NEIGHBOURS, NEIGHBOURS_PER_TOWER, TARGETS_PER_AGENT
from .terms import performance_of

_NEAREST = {1: "the nearest", 2: "the second nearest", 3: "the third nearest"}


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
    items += [item for k in range(1, NEIGHBOURS_PER_TOWER + 1) for item in _neighbour_items(k, p, agents)]
    return {q.name: q for q in items}


def _neighbour_items(k: int, p, agents: int) -> list:
    """The quantities of the agent's neighbour ``k`` (1 nearest, see the neighbour table), read at its tower."""
    tower = f"neighbour {k}'s tower ({_NEAREST[k]} other tower)"
    return [
        quantity(f"resources_given_to_neighbour{k}", "agent", "number", "1", 0.0, 1.0,
                 f"The share the agent gives to its neighbour {k} ({_NEAREST[k]} other tower; see the neighbour "
                 "table)."),
        quantity(f"neighbour{k}_resources_received", "agent", "number", "1", 0.0, float(agents),
                 f"Resources {tower} receives from every agent (its resources_received)."),
        flag(f"neighbour{k}_sees_fire", "agent", f"A burning tree lies within the detection radius of {tower}."),
        quantity(f"neighbour{k}_distance_to_fire_m", "agent", "number", "m", 0.0, p.detection_radius_m,
                 f"3-D distance from {tower} to the closest burning tree in its range; the detection radius when "
                 "none is."),
        quantity(f"neighbour{k}_tower_performance", "agent", "number", "1", 0.0, 1.0,
                 f"The tower performance P of {tower}."),
    ]


def _performance(state, events, compiled) -> np.ndarray:
    sighting = state.sighting
    if sighting.performance is not None:
        return sighting.performance
    return performance_of(sighting.distance, sighting.approaching, sighting.seen, compiled.params)


_AT_NEIGHBOURS = ("resources_received", "sees_fire", "distance_to_fire_m", "tower_performance")


def _at_neighbour(k: int, read):
    """A reader of ``read``'s (B, 9) per-tower value at each agent's neighbour ``k`` (1 to 3): one gather."""
    towers = NEIGHBOURS[:, k - 1]  # (9,) the tower of each agent's neighbour k
    return lambda s, e, c: read(s, e, c)[:, towers]


def _given_to(k: int):
    """A reader of the (B, 9) share each agent gives its neighbour ``k``."""
    return lambda s, e, c: s.allocation[..., k] / 10.0


def _neighbour_readers() -> dict:
    """The readers of the per-neighbour quantities, built once at import (no loop when stepping)."""
    readers = {}
    for k in range(1, NEIGHBOURS_PER_TOWER + 1):
        readers[f"resources_given_to_neighbour{k}"] = _given_to(k)
        readers.update({f"neighbour{k}_{name}": _at_neighbour(k, READERS[name]) for name in _AT_NEIGHBOURS})
    return readers


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

READERS.update(_neighbour_readers())

VOCABULARY = Vocabulary("wildfire_resource_management", declare, READERS)
