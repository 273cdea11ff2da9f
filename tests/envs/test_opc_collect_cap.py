"""params.collect_per_decision: at most that many pebbles a vessel collects within one decision, the nearest first.

The original's training pace stays near one pebble a decision in every collecting task (the reward table's pace
note); a release whose collector takes one pebble an action would give it. Worked by hand on a vessel at its top
speed (2 m a step) along +x through a line of pebbles 0.5 m apart, at decision period 5: its collector sweeps
forward in [-2, 3] m and across in [-1.5, 1.5] m of its new position each step.
"""

from __future__ import annotations

import numpy as np
import pytest

import hivex_dsl
from hivex_dsl.envs.ocean_plastic_collection.camera import _collect
from hivex_dsl.evaluation.policies import make_policy
from hivex_dsl.runtime.batched import BatchedEnv

from .test_opc_mechanics import GO, floating, hand_built, step

ENV = "ocean_plastic_collection"
LINE = [(x, 0.0) for x in np.arange(0.5, 40.0, 0.5)]  # 79 pebbles on the vessel's path


def capped_simulator(cap: int, period: int = 5):
    sc = hivex_dsl.compile({"hivex": 1, "environment": ENV, "agents": 1, "decision_period": period,
                            "params": {"collect_per_decision": cap}})
    return sc.entry.make_simulator(sc)


def collected_per_step(cap: int, steps: int, period: int = 5) -> list[int]:
    sim = capped_simulator(cap, period)
    state = hand_built(sim, [(0, 0)], [0], LINE, speeds=[2.0])
    counts = []
    for _ in range(steps):
        state, _ = step(sim, state, [GO])
        counts.append(int(state.collected[0, 0]))
    return counts


def test_without_a_cap_the_first_step_takes_every_pebble_the_collector_swept():
    # the vessel moves to x = 2: forward in [0, 5] holds the pebbles at 0.5 .. 5.0, ten of them
    assert collected_per_step(0, 1) == [10]


def test_a_cap_of_one_takes_one_pebble_a_decision_the_rest_float_on():
    counts = collected_per_step(1, 10)
    assert counts == [1, 0, 0, 0, 0, 1, 0, 0, 0, 0]  # two decisions of five steps


def test_the_cap_takes_the_nearest_pebble_and_leaves_the_others_for_the_next_decision():
    sim = capped_simulator(1)
    state = hand_built(sim, [(0, 0)], [0], LINE, speeds=[2.0])
    state, _ = step(sim, state, [GO])  # at x = 2: the nearest swept pebble is the one at 2.0
    assert (2.0, 0.0) not in floating(state) and (2.5, 0.0) in floating(state) and (0.5, 0.0) in floating(state)


def test_a_cap_of_three_spreads_over_the_steps_of_a_decision_and_renews_with_the_next():
    assert collected_per_step(3, 10) == [3, 0, 0, 0, 0, 3, 0, 0, 0, 0]
    # at period 1 every step is a decision
    assert collected_per_step(1, 4, period=1) == [1, 1, 1, 1]


def test_collect_keeps_each_slot_s_nearest_hits_within_its_allowance():
    """Three hits of slot 0 at 3, 1 and 2 m, two of slot 1 at 5 and 4 m; allowances 2 and 0."""
    alive = np.ones((1, 10), bool)
    pebble, slot = np.array([0, 1, 2, 3, 4]), np.array([0, 0, 0, 1, 1])
    distance = np.array([3.0, 1.0, 2.0, 5.0, 4.0])
    left, counts = _collect(alive, pebble, slot, 2, np.array([2, 0]), distance)
    assert counts.tolist() == [2, 0]
    assert (~left[0]).nonzero()[0].tolist() == [1, 2]  # slot 0's two nearest; slot 1 took nothing


@pytest.mark.parametrize("cap", [1, 2])
def test_no_decision_collects_more_than_the_cap_in_random_play(cap):
    """Random play on 8 test worlds through the runtime (decision period 5): a decision's Collect Trash, summed
    over its five steps, never exceeds the cap, and without one some decisions take more."""
    decisions = {c: random_decisions(c) for c in (0, cap)}
    assert 0 < decisions[cap].max() <= cap < decisions[0].max()


def random_decisions(cap: int) -> np.ndarray:
    """Collect Trash of every vessel-decision of random play, 100 decisions of 8 test worlds."""
    compiled = hivex_dsl.compile({"hivex": 1, "environment": ENV, "agents": 3,
                                  "params": {"collect_per_decision": cap}})
    core = BatchedEnv(compiled, batch=8, split="test")
    act = make_policy("random", compiled, core.sim.action_space, core.shape, seed=0)
    observations, paid = core.reset(), []
    for _ in range(100):
        transition = core.step(act(observations))
        observations = transition.observations
        paid.append(transition.terms["collect_trash"].ravel())
    return np.concatenate(paid)
