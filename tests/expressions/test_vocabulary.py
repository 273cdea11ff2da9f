"""Every environment's vocabulary: values have the declared shape and kind and never leave the declared range."""

from __future__ import annotations

import os

import numpy as np
import pytest

import hivex_dsl
from hivex_dsl.compiler import registry
from hivex_dsl.lang.expr import input_problems
from hivex_dsl.sim.reward.vocabulary import vocabulary_of
from hivex_dsl.runtime import BatchedEnv

from .rollouts import recorded

# (environment, extra scenario keys, steps): small worlds where the environment allows, so the test stays quick
ROLLOUTS = {
    "wind_farm_control": ({"agents": 4, "episode_length": 60}, 150),
    "aerial_wildfire_suppression": ({"agents": 3, "episode_length": 40, "params": {"border_half_extent_m": 700.0}}, 70),
    "ocean_plastic_collection": ({"agents": 3, "episode_length": 50}, 90),
    "drone_based_reforestation": ({"agents": 3, "episode_length": 50}, 90),
    "wildfire_resource_management": ({"episode_length": 30}, 60),
}


def _has_vocabulary(env_id: str) -> bool:
    try:
        vocabulary_of(env_id)
    except ModuleNotFoundError:
        return False
    return True


@pytest.mark.parametrize("env_id", [e for e in ROLLOUTS if _has_vocabulary(e)])
def test_random_rollouts_stay_inside_the_declared_ranges(env_id):
    """Every value after a step and before it (a reset's on a world's first step), on random rollouts; with
    HIVEX_FUZZ_LONG=1 twenty times longer, over several episodes of every world."""
    extra, steps = ROLLOUTS[env_id]
    quantities, pairs = recorded(env_id, extra, steps * (20 if os.environ.get("HIVEX_FUZZ_LONG") else 1))
    seen = {name: [np.inf, -np.inf] for name in quantities}
    for now, before in pairs:
        assert set(now) == set(quantities)
        assert input_problems(quantities, now) == []  # dtype, shape and range, as the compiler's guarantees need
        # before: the reset state's values on a world's first step (prev() reads them), which `now` never shows
        assert input_problems(quantities, before) == []
        for name, q in quantities.items():
            if q.kind == "number":
                seen[name] = [min(seen[name][0], now[name].min()), max(seen[name][1], now[name].max())]
    moving = [n for n, q in quantities.items() if q.kind == "number" and seen[n][0] < seen[n][1]]
    assert len(moving) >= len([q for q in quantities.values() if q.kind == "number"]) // 2  # readers are not constants


@pytest.mark.parametrize("env_id", [e for e in ROLLOUTS if _has_vocabulary(e)])
def test_every_quantity_is_described_with_a_unit_and_a_finite_range(env_id):
    compiled = hivex_dsl.compile({"hivex": 1, "environment": env_id})
    for name, q in vocabulary_of(env_id).quantities(compiled).items():
        assert q.name == name and q.description.endswith(".") and (q.unit or q.kind == "bool")
        assert np.isfinite(q.low) and np.isfinite(q.high) and q.low <= q.high
        assert q.per in ("agent", "world") and q.kind in ("number", "bool")
    assert registry.get(env_id)


def test_trees_near_the_village_match_a_scan_of_the_whole_grid():
    compiled = hivex_dsl.compile({"hivex": 1, "environment": "aerial_wildfire_suppression", "agents": 2})
    env = BatchedEnv(compiled, batch=2)
    env.reset(seed=1)
    for _ in range(40):  # let the fire spread a little
        env.step({"continuous": np.zeros(env.shape + (1,), np.float32), "discrete": np.zeros(env.shape + (1,), int)})
    values = vocabulary_of(compiled.environment).values(env.state, {}, compiled,
                                                       ["trees_near_village", "burning_near_village"])
    forest, state = compiled.generators["forest"], env.state
    centres = -forest.half_extent_m + (np.arange(forest.cells) + 0.5) * forest.spacing_m
    for world in range(env.batch):
        vx, vy = state.maps.village[world]
        near = np.hypot(centres[None, :] - vx, centres[:, None] - vy) <= compiled.params.village_radius_m
        trees = state.fire.trees[world]
        assert values["trees_near_village"][world] == np.count_nonzero(near & ((trees == 1) | (trees == 4)))
        assert values["burning_near_village"][world] == np.count_nonzero(near & (trees == 2))
