"""The scripted pilot puts out fire; random flying does not, over the same seeds."""

from __future__ import annotations

import numpy as np
import pytest

import hivex_dsl
from hivex_dsl.evaluation.report import collect_returns

SEEDS = (6000, 6001)


@pytest.fixture(scope="module")
def main_task():
    return hivex_dsl.compile({"hivex": 1, "environment": "aerial_wildfire_suppression", "episode_length": 3000})


def extinguished(compiled, policy: str) -> float:
    """Trees turned from burning to wet over one test episode per seed (the term pays 5 per tree)."""
    total = 0.0
    for seed in SEEDS:
        _, sums = collect_returns(compiled, policy, episodes=1, split="test", seed=seed)
        total += sums["extinguishing_tree"].sum() / 5.0
    return total


def test_scripted_extinguishes_clearly_more_trees_than_random(main_task):
    scripted, random = extinguished(main_task, "scripted"), extinguished(main_task, "random")
    assert scripted >= 30
    assert scripted >= 5 * max(random, 1.0)


def test_scripted_pilots_never_cross_the_border(main_task):
    _, sums = collect_returns(main_task, "scripted", episodes=1, split="test", seed=SEEDS[0])
    assert np.all(sums["crossed_border"] == 0.0)
