"""What an expression may read in Bee Foraging."""

from __future__ import annotations

import math

import numpy as np

from hivex_dsl.sim.reward.vocabulary import Vocabulary, quantity

from .simulator import ENV_ID


def declare(compiled) -> dict:
    p = compiled.params
    items = [
        quantity("load", "agent", "number", "1", 0.0, p.capacity, "The nectar the bee carries."),
        quantity("hive_distance_m", "agent", "number", "m", 0.0, math.sqrt(2) * p.meadow_half_extent_m,
                 "How far the bee is from the hive."),
        quantity("nectar_left", "world", "number", "1", 0.0, p.flowers * p.nectar_per_flower,
                 "The nectar left on every flower of the meadow."),
    ]
    return {q.name: q for q in items}


READERS = {
    "load": lambda s, e, c: s.load,
    "hive_distance_m": lambda s, e, c: np.hypot(s.positions[..., 0], s.positions[..., 1]),
    "nectar_left": lambda s, e, c: s.nectar.sum(axis=1),
}

VOCABULARY = Vocabulary(ENV_ID, declare, READERS)
