"""The untrained flight: ML-Agents' initial policy in this toolkit against the original's first training points
(issue 52; the reward table's note "Decided (issue 52, session 31)").

The initial policy samples each continuous action from a unit Gaussian clipped to +/-3 and scaled by 1/3, and a
uniform drop. The original's first points (6,000 agent-steps, before the first update) are that policy's, at
every terrain level. Tolerances are about two standard errors of a first point (about 15 drone-episodes) or of
the rollout here (12 drone-episodes), whichever is wider.
"""

from __future__ import annotations

import numpy as np
import pytest

import hivex_dsl
from hivex_dsl.evaluation.original.curves import original_curves
from hivex_dsl.evaluation.rollout import rollout

ENV = "drone_based_reforestation"
PAGES = {"main": 0, "find_closest_tree": 1, "pick_up_seed": 2, "find_high_potential_area": 4, "explore_furthest": 6}


def initial_policy(seed: int):
    rng = np.random.default_rng(seed)

    def act(observations):
        shape = observations["vector"].shape[:2]
        continuous = np.clip(rng.standard_normal(shape + (3,)), -3.0, 3.0) / 3.0
        return {"continuous": continuous.astype(np.float32), "discrete": rng.integers(0, 2, shape + (1,))}

    return act


def untrained(task: str, **params):
    compiled = hivex_dsl.compile({"hivex": 1, "environment": ENV, "task": task, "agents": 3, "terrain_level": 1,
                                  "params": params})
    return rollout(compiled, initial_policy(1), 4, split="train", seed=5000)


def first(task: str, panel: str) -> float:
    return float(original_curves(ENV, PAGES[task], 1).panel(panel).training.mean[0])


def test_untrained_drones_explore_as_far_as_the_originals_and_the_signed_throttle_did_not():
    """Explore Furthest's first point: 117.9 m. A zero-mean signed throttle random-walks about 31 m out."""
    original = first("explore_furthest", "Furthest Distance Explored")
    assert original == pytest.approx(117.9, abs=0.5)
    ours = untrained("explore_furthest").statistics["Furthest Distance Explored"].mean()
    signed = untrained("explore_furthest", throttle="signed").statistics["Furthest Distance Explored"].mean()
    assert abs(ours - original) < 40.0 and signed < original / 2


def test_untrained_seed_holders_fly_about_30_m_before_a_drop():
    """The main task's first point: 24.2 m of path over 0.81 drops, about 30 m a drop; a drop possible right
    outside the charge radius (7.5 m, the reading before) came after about 12 m."""
    original = first("main", "Cumulative Distance Until Tree Drop") / first("main", "Tree Drop Count")
    assert original == pytest.approx(29.9, abs=0.3)
    done = untrained("main")
    ours = done.statistics["Cumulative Distance Until Tree Drop"].sum() / done.statistics["Tree Drop Count"].sum()
    near = untrained("main", drop_min_distance_m=7.5)
    before = near.statistics["Cumulative Distance Until Tree Drop"].sum() / near.statistics["Tree Drop Count"].sum()
    assert abs(ours - original) < 8.0 and before < original / 2


def test_untrained_docked_steps_run_from_the_start_where_the_station_serves():
    """The main task's first point docks 41 steps a drone-episode, Find Closest Tree's and Find High Potential
    Area's 0: the count includes the start on the pad (tens of steps under the initial policy, which flies
    forward at a mean 0.13 of full throttle), and the inert stations count nothing."""
    assert first("main", "Recharge Energy Count") == pytest.approx(40.95, abs=0.1)
    ours = untrained("main").statistics["Recharge Energy Count"].mean()
    assert 25.0 < ours < 80.0
    for task in ("find_closest_tree", "find_high_potential_area"):
        assert first(task, "Recharge Energy Count") == 0.0
        assert untrained(task).statistics["Recharge Energy Count"].sum() == 0.0
