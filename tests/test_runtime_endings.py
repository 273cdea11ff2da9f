"""BatchedEnv's episode bookkeeping against a plain reference: who ends, how, and when.

The runtime skips work on steps where nobody can end (every agent plays and no world reaches the
episode length); this drives it through random terminations, truncations and partial restarts and
checks every step against the textbook rules computed here from scratch.
"""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import hivex_dsl
from hivex_dsl.runtime import BatchedEnv, StepOutcome


def random_endings(chance: float, seed: int):
    """A WFC step after which each agent terminates with probability ``chance`` (own seeded draws)."""
    draws = np.random.default_rng(seed)

    def step(sim, state, actions, rng):
        new, outcome = sim.step(state, actions, rng)
        return new, StepOutcome(draws.random(outcome.terminated.shape) < chance, {})

    return step


def _env(restepped, batch: int, length: int, chance: float, seed: int) -> BatchedEnv:
    sc = hivex_dsl.compile({"hivex": 1, "environment": "wind_farm_control", "agents": 3, "episode_length": length})
    return BatchedEnv(restepped(sc, random_endings(chance, seed)), batch=batch)


@settings(max_examples=25, deadline=None)
@given(batch=st.integers(1, 4), length=st.integers(1, 9), chance=st.sampled_from([0.0, 0.02, 0.2, 1.0]),
       seed=st.integers(0, 2**16), restart_via_step=st.booleans())
def test_endings_follow_the_rules_step_by_step(restepped, batch, length, chance, seed, restart_via_step):
    env = _env(restepped, batch, length, chance, seed)
    env.reset(seed=seed)
    clock = np.zeros(batch, np.int64)
    alive = np.ones((batch, 3), bool)
    lengths = np.zeros((batch, 3), np.int64)
    restart = np.zeros(batch, bool)
    for _ in range(40):
        actions = np.zeros((batch, 3), np.int64)
        if restart_via_step and restart.any():
            result = env.step(actions, restart=restart)
        else:
            result = env.step(actions)
        clock += 1
        lengths += alive
        terminated = result.terminated
        assert not (terminated & ~alive).any(), "only playing agents terminate"
        expected_truncated = alive & (clock >= length)[:, None]  # a terminated agent too, at the clock's end
        np.testing.assert_array_equal(result.truncated, expected_truncated)
        np.testing.assert_array_equal(result.ended, terminated | expected_truncated)
        alive = alive & ~result.ended
        if restart_via_step and restart.any():
            clock[restart], lengths[restart], alive[restart] = 0, 0, True
        np.testing.assert_array_equal(env.lengths, lengths)
        np.testing.assert_array_equal(env.alive, alive)
        assert env.everyone_playing == bool(alive.all())
        assert env.oldest_clock == clock.max()
        restart = ~alive.any(axis=1)
        if not restart_via_step and restart.any():
            env.reset_worlds(restart)
            clock[restart], lengths[restart], alive[restart] = 0, 0, True
            restart = np.zeros(batch, bool)


def test_terminations_are_those_the_simulator_reports_for_playing_agents(restepped):
    env = _env(restepped, batch=2, length=100, chance=0.3, seed=7)
    env.reset(seed=7)
    reported = []
    real_step = env.sim.step

    def spy(state, actions, rng):
        new, outcome = real_step(state, actions, rng)
        reported.append(outcome.terminated.copy())
        return new, outcome

    env.sim.step = spy
    alive = np.ones((2, 3), bool)
    for _ in range(10):
        result = env.step(np.zeros((2, 3), np.int64))
        np.testing.assert_array_equal(result.terminated, reported[-1] & alive)
        alive &= ~result.ended


def crash_on_the_last_step(length: int):
    """A WFC step after which turbine 0 terminates on step ``length`` of its episode (the clock's end)."""
    steps = [0]

    def step(sim, state, actions, rng):
        new, outcome = sim.step(state, actions, rng)
        steps[0] += 1
        crashed = np.zeros(outcome.terminated.shape, bool)
        crashed[:, 0] = steps[0] % length == 0
        return new, StepOutcome(crashed, {})

    return step


def test_an_agent_that_terminates_on_the_last_step_is_truncated_too_so_every_library_sees_the_world_end(restepped):
    """The RLlib crash: a plane crashing on the world's last step came back terminated and its teammates
    truncated, so neither RLlib's "all terminated" nor its "all truncated" held and it stepped a finished
    world. Now every agent is truncated at the clock's end; the crashed one is terminated too."""
    from hivex_dsl.adapters.pettingzoo import HivexParallelEnv

    length = 4
    compiled = hivex_dsl.compile({"hivex": 1, "environment": "wind_farm_control", "agents": 3, "episode_length": length})
    env = HivexParallelEnv(restepped(compiled, crash_on_the_last_step(length)))
    env.reset(seed=0)
    for _ in range(length):
        _, _, terminations, truncations, _ = env.step({agent: 0 for agent in env.agents})
    assert terminations == {"turbine_0": True, "turbine_1": False, "turbine_2": False}
    assert all(truncations.values()) and not env.agents  # RLlib's __all__: all(truncations.values())
    try:
        from ray.rllib.env.wrappers.pettingzoo_env import ParallelPettingZooEnv
    except ImportError:  # the rllib extra (its own CI step)
        return
    from hivex_dsl.adapters.flat import FlatParallelEnv

    rllib = ParallelPettingZooEnv(FlatParallelEnv(HivexParallelEnv(restepped(compiled, crash_on_the_last_step(length)))))
    rllib.reset(seed=0)
    for _ in range(length):
        _, _, terminateds, truncateds, _ = rllib.step({agent: 0 for agent in rllib.par_env.agents})
    assert truncateds["__all__"]


def test_an_action_for_an_agent_that_ended_is_accepted_and_ignored(restepped):
    """TorchRL sends actions for every agent of a group: 'action for turbine_0, which is not a live agent' ended
    its rollouts at the first crash. A name that is no agent is still refused."""
    from hivex_dsl.adapters.pettingzoo import HivexParallelEnv
    from hivex_dsl.base.errors import ActionError

    compiled = hivex_dsl.compile({"hivex": 1, "environment": "wind_farm_control", "agents": 3, "episode_length": 6})
    every, live_only = (HivexParallelEnv(restepped(compiled, crash_on_the_last_step(2))) for _ in range(2))
    every.reset(seed=4)
    live_only.reset(seed=4)
    for step in range(5):
        got = every.step({agent: 1 for agent in every.possible_agents})
        expected = live_only.step({agent: 1 for agent in live_only.agents})
        assert got[1:4] == expected[1:4]
        if step >= 1:
            assert "turbine_0" not in every.agents  # it crashed on step 2; its action is ignored since
    with pytest.raises(ActionError, match="action for 'turbine_7', which is not a live agent"):
        every.step({agent: 1 for agent in [*every.possible_agents, "turbine_7"]})
