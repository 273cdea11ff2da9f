"""The Gymnasium vector env: slots are (world, agent) pairs, NEXT_STEP autoreset per world."""

from __future__ import annotations

import numpy as np
import pytest
from gymnasium import spaces
from gymnasium.vector import AutoresetMode

import hivex_dsl

SCENARIO = {"hivex": 1, "environment": "wind_farm_control", "agents": 3, "episode_length": 4}


def test_spaces_single_and_batched():
    venv = hivex_dsl.vector_env(SCENARIO, num_worlds=5)
    assert venv.num_envs == 15 and venv.num_worlds == 5 and venv.agents_per_world == 3
    assert venv.single_observation_space == spaces.Box(-1, 1, (6,), np.float32)
    assert venv.single_action_space == spaces.Discrete(3)
    assert venv.observation_space.shape == (15, 6)
    assert venv.action_space == spaces.MultiDiscrete([3] * 15)
    assert venv.metadata["autoreset_mode"] is AutoresetMode.NEXT_STEP


def test_next_step_autoreset_and_episode_infos():
    # worlds drawn afresh at each reset (by default a WFC episode continues its world)
    venv = hivex_dsl.vector_env(SCENARIO | {"params": {"episodes_continue": 0}}, num_worlds=2)
    obs, _ = venv.reset(seed=1)
    assert obs.shape == (6, 6) and venv.observation_space.contains(obs)
    for step in range(1, 5):
        obs, rewards, terminated, truncated, infos = venv.step(np.zeros(6, np.int64))
        assert rewards.shape == (6,) and not terminated.any()
        assert truncated.all() == (step == 4)
    assert infos["_hivex_episode"].all()
    np.testing.assert_array_equal(infos["hivex_episode"]["length"], 4)
    np.testing.assert_allclose(infos["hivex_episode"]["return"], infos["hivex_episode"]["reward_terms"]["generate_energy"])
    last_obs = obs
    obs, rewards, terminated, truncated, infos = venv.step(np.zeros(6, np.int64))
    np.testing.assert_array_equal(rewards, 0.0)
    assert not truncated.any() and "hivex_episode" not in infos and "active" not in infos
    np.testing.assert_array_equal(infos["reward_terms/generate_energy"], 0.0)  # every step has its terms
    assert not np.array_equal(obs, last_obs)  # new layout of headings and wind after the reset


def test_one_world_matches_the_parallel_env():
    venv = hivex_dsl.vector_env(SCENARIO | {"episode_length": 50}, num_worlds=1)
    penv = hivex_dsl.parallel_env(SCENARIO | {"episode_length": 50})
    v_obs, _ = venv.reset(seed=8)
    p_obs, _ = penv.reset(seed=8)
    rng = np.random.default_rng(0)
    for _ in range(40):
        np.testing.assert_array_equal(v_obs, np.stack([p_obs[a] for a in penv.possible_agents]))
        actions = rng.integers(0, 3, 3)
        v_obs, v_rew, *_ = venv.step(actions)
        p_obs, p_rew, *_ = penv.step({a: int(actions[i]) for i, a in enumerate(penv.possible_agents)})
        np.testing.assert_allclose(v_rew, [p_rew[a] for a in penv.possible_agents])


def test_bad_slot_action_names_agent_and_world():
    venv = hivex_dsl.vector_env(SCENARIO, num_worlds=2)
    venv.reset(seed=0)
    actions = np.zeros(6, np.int64)
    actions[4] = 7
    with pytest.raises(hivex_dsl.ActionError, match=r"action for turbine_1 in env 1 is 7, not in Discrete\(3\)"):
        venv.step(actions)
    with pytest.raises(hivex_dsl.ActionError, match=r"leading size \(5,\); expected 6 slots \(2 worlds x 3 agents\)"):
        venv.step(np.zeros(5, np.int64))


def test_per_episode_seed_lists_are_refused_with_the_reason():
    with pytest.raises(ValueError, match="per-episode list \\[7, 8\\].*use parallel_env"):
        hivex_dsl.vector_env(SCENARIO | {"seeds": {"train": [7, 8], "test": 9}}, num_worlds=2)
    hivex_dsl.vector_env(SCENARIO | {"seeds": {"train": [7, 8], "test": 9}}, num_worlds=2, split="test")


def test_an_agent_whose_episode_ended_gets_the_placeholder_action_until_its_world_resets(restepped):
    from hivex_dsl.runtime import StepOutcome

    seen = []

    def recording_spins(sim, state, actions, rng):
        """WFC whose agents end their episode ('spun') when they rotate left; records the actions it gets."""
        seen.append(np.array(actions))
        new, outcome = sim.step(state, actions, rng)
        return new, StepOutcome(outcome.terminated, {"spun": np.asarray(actions) == 1})

    sc = hivex_dsl.compile(SCENARIO | {"episode_length": 10})
    env = hivex_dsl.vector_env(restepped(sc, recording_spins, {"spun": "rotated left"}, ("spun",)), num_worlds=1)
    env.reset(seed=0)
    env.step(np.array([0, 1, 0]))  # agent 1 ends its episode
    env.step(np.array([2, 1, 2]))  # its action is replaced; the others act
    assert seen[-1].tolist() == [[2, 0, 2]]


@pytest.mark.parametrize("environment", ["wind_farm_control", "ocean_plastic_collection", "aerial_wildfire_suppression"])
def test_restarting_worlds_observe_as_a_separate_reset_would(environment):
    """The vector env restarts pending worlds inside the step and observes once; that must give what
    stepping, then resetting those worlds on their own, then observing gives."""
    from hivex_dsl.evaluation.policies import random_policy
    from hivex_dsl.runtime import BatchedEnv

    compiled = hivex_dsl.compile({"hivex": 1, "environment": environment, "episode_length": 6, "decision_period": 1,
                                  "seeds": {"train": 4}})  # 6 physics steps, one a step() call
    venv = hivex_dsl.vector_env(compiled, num_worlds=3)
    manual = BatchedEnv(compiled, batch=3)
    draw = random_policy(venv.single_action_space, (venv.num_envs,), np.random.default_rng(1))
    obs, _ = venv.reset(seed=4)
    expected = manual.reset(seed=4)
    pending = np.zeros(3, bool)
    respawning = np.zeros((3, compiled.agents), bool)
    restarts = 0
    for _ in range(20):
        actions = draw(None)
        obs, *_ = venv.step(actions)
        batched = {k: v.reshape((3, -1) + v.shape[1:]) for k, v in actions.items()} if isinstance(actions, dict) \
            else actions.reshape((3, -1) + actions.shape[1:])
        if pending.all():  # every world restarts: no simulator step on discarded actions
            expected = manual.reset_worlds(pending)
            ended = np.zeros_like(respawning)
        else:
            result = manual.step(batched, respawn=respawning & ~pending[:, None])
            expected, ended = result.observations, result.ended
            if pending.any():
                expected = manual.reset_worlds(pending)
        restarts += pending.any()
        respawning = ended & ~pending[:, None] & manual.alive.any(axis=1)[:, None]
        pending = ~manual.alive.any(axis=1)
        flat = {k: v.reshape((venv.num_envs,) + v.shape[2:]) for k, v in expected.items()} if isinstance(expected, dict) \
            else expected.reshape((venv.num_envs,) + expected.shape[2:])
        if isinstance(obs, dict):
            for key in obs:
                np.testing.assert_array_equal(obs[key], flat[key])
        else:
            np.testing.assert_array_equal(obs, flat)
    assert restarts >= 2
