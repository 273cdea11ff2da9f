"""OPC's Local and Global Reward as running means (hivex_dsl.sim.statistics), on whole test episodes of the scripted
skipper and the random policy in the main task and Avoid Plastic, checked against what the vessels did.

The pebbles a vessel collects are counted from the simulator's per-step ``collected`` (the Collect Trash term's
unweighted value), the crashes from its border and vessel-collision flags; the running mean is then worked out
by hand. Local counts Collect Trash alone (tests/fidelity/test_opc_local.py): in the main task the running total
steps by +k on a step collecting k pebbles, and the crash, paid in the return, does not move it: with m
collection steps and C_j pebbles after the j-th, Local = (C_1 + ... + C_m) / m. Where every collection step
collects one pebble (C_j = j, m = n) Local = (n + 1) / 2, crashed or not. In Avoid Plastic a touch of k pebbles
steps it by -k (Collect Trash at -1; Collide with Trash's -1 is paid, not counted), -1 for one pebble.
"""

from __future__ import annotations

from functools import lru_cache

import numpy as np
import pytest

import hivex_dsl
from hivex_dsl.evaluation.policies import make_policy
from hivex_dsl.runtime import BatchedEnv
from hivex_dsl.sim.spaces import check_actions

EPISODES = 2


@lru_cache(maxsize=None)
def played(task: int, policy: str, length: int = 5000, pebble_count: int | None = None,
           pace: tuple[float, float] | None = None):
    """Per agent-episode: (pebbles per step (T,), crashed per step (T,), Local, Global, Global's episode sum);
    ``pebble_count`` overrides the world's supply, ``pace`` (acceleration, turn_rate_deg) the vessels'."""
    supply = {} if pebble_count is None else {"generators": {"pollution": {"pebble_count": pebble_count}}}
    if pace is not None:
        supply["params"] = {"acceleration": pace[0], "turn_rate_deg": pace[1]}
    # period 1, so that an env step is a physics step and the per-step state counted by hand is every step's: the
    # running means tick per physics step whatever the period (the default, 5, holds each action five steps)
    compiled = hivex_dsl.compile({"hivex": 1, "environment": "ocean_plastic_collection", "task": task, "agents": 3,
                                  "episode_length": length, "decision_period": 1,
                                  "seeds": {"train": 5000, "test": 6000}, **supply})
    env = BatchedEnv(compiled, batch=1, split="test")
    act = make_policy(policy, compiled, env.sim.action_space, env.shape, seed=0)
    out = []
    for episode in range(EPISODES):
        observations = env.reset()
        pebbles, crashes = [], []
        while env.alive.any():
            live = env.alive[0].copy()
            result = env.step(check_actions(env.sim.action_space, act(observations), compiled.agent_names,
                                            env.sim.action_meanings))
            observations, state = result.observations, env.state
            pebbles.append(np.where(live, state.collected[0], 0))
            crashes.append(live & (state.crossed_border[0] | state.collided_vessel[0]))
        stats = env.statistic_sums()
        global_sum = compiled.weights["lowest_collected_trash_count"] * env.term_sums.get(
            "lowest_collected_trash_count", np.zeros(env.shape))
        pebbles, crashes = np.array(pebbles), np.array(crashes)
        np.testing.assert_array_equal(pebbles.sum(axis=0), env.term_sums["collect_trash"][0])
        out += [(pebbles[:, a], crashes[:, a], stats["Local Reward"][0, a], stats["Global Reward"][0, a],
                 global_sum[0, a]) for a in range(env.agents)]
    return out


def by_hand(pebbles: np.ndarray, sign: int) -> float:
    """The running mean of the vessel's Collect Trash total: +k a collection step (main task, ``sign`` 1) or -k a
    touch (Avoid Plastic, ``sign`` -1, Collect Trash at weight -1); nothing for a crash."""
    totals, total = [], 0.0
    for k in pebbles:
        step = sign * float(k)
        if step:
            total += step
            totals.append(total)
    return float(np.mean(totals)) if totals else 0.0


@pytest.mark.parametrize("policy", ["scripted", "random"])
def test_main_task_local_is_the_mean_collected_count_over_the_collection_steps(policy):
    cases = set()
    for pebbles, crashes, local, _, _ in played(0, policy):
        n, m, c = int(pebbles.sum()), int(np.count_nonzero(pebbles)), int(crashes.sum())
        assert c <= 1
        assert local == pytest.approx(by_hand(pebbles, 1), abs=1e-9)
        if m == n and n and not c:
            cases.add("one a step")
            assert local == pytest.approx((n + 1) / 2, abs=1e-9)
        elif m == n and n and c:
            cases.add("one a step, crashed")
            assert local == pytest.approx((n + 1) / 2, abs=1e-9)  # the crash's -100 is not counted
        elif m < n:
            cases.add("several on a step")
            counts = np.cumsum(pebbles[pebbles > 0])
            assert local == pytest.approx(counts.sum() / m, abs=1e-9)
    # the scripted skipper never crashes and now and then collects two pebbles at once; random play crashes
    assert cases >= ({"several on a step"} if policy == "scripted" else {"one a step, crashed"})


def test_a_short_scripted_episode_collecting_one_pebble_a_step_logs_n_plus_one_over_two():
    """Test episodes 250 steps long in a sparse world (1,000 pebbles) of slow vessels (0.5 m a step at the top, the
    pace before issue 52's fit): no vessel collects two pebbles on one step yet (at the default pace, 2 m a step,
    some do within 250 steps even among 300 pebbles)."""
    checked = 0
    for pebbles, crashes, local, _, _ in played(0, "scripted", 250, pebble_count=1000, pace=(0.05, 3.0)):
        n = int(pebbles.sum())
        assert pebbles.max() <= 1 and not crashes.any() and n > 0
        assert local == pytest.approx((n + 1) / 2, abs=1e-9)
        checked += 1
    assert checked == 3 * EPISODES


@pytest.mark.parametrize("policy", ["scripted", "random"])
def test_avoid_plastic_local_steps_by_minus_one_a_touched_pebble(policy):
    for pebbles, crashes, local, global_mean, global_sum in played(3, policy):
        assert local == pytest.approx(by_hand(pebbles, -1), abs=1e-9)
        m = int(np.count_nonzero(pebbles))
        if m == pebbles.sum():  # m touches of one pebble: -1, -2, ..., -m, crashed or not
            assert local == pytest.approx(-(m + 1) / 2 if m else 0.0, abs=1e-9)
        assert global_mean == global_sum == 0.0  # the lowest count has weight 0 in Avoid Plastic


@pytest.mark.parametrize("policy", ["scripted", "random"])
def test_global_is_at_most_its_episode_sum_and_about_a_third_of_it_when_the_team_collects(policy):
    """Global's running total only grows (0.01 x the lowest count per pebble collected), so its mean over the
    steps it changed on is at most its final value, the episode sum."""
    for _, _, _, global_mean, global_sum in played(0, policy):
        assert 0.0 <= global_mean <= global_sum + 1e-9
        if policy == "scripted":  # a total growing as the square of time averages about a third of its end
            assert 0.25 * global_sum <= global_mean <= 0.45 * global_sum
