"""The PettingZoo ParallelEnv: API conformance, spaces, infos, errors and multi-step determinism."""

from __future__ import annotations

import numpy as np
import pytest
from pettingzoo.test import api_test, parallel_api_test
from pettingzoo.utils.conversions import parallel_to_aec

import hivex_dsl
from hivex_dsl.runtime import StepOutcome


def make(**fields):
    return hivex_dsl.parallel_env({"hivex": 1, "environment": "wind_farm_control", **fields})


def test_parallel_api():
    parallel_api_test(make(episode_length=300), num_cycles=1000)


def test_aec_api_through_the_pettingzoo_converter():
    api_test(parallel_to_aec(make(episode_length=200)), num_cycles=300)


def test_observations_lie_in_their_spaces_with_the_right_dtype():
    env = make(agents=5, pattern="random")
    obs, _ = env.reset(seed=11)
    for _ in range(50):
        for agent, o in obs.items():
            space = env.observation_space(agent)
            assert o.dtype == space.dtype and space.contains(o)
        obs, *_ = env.step({a: env.action_space(a).sample() for a in env.agents})


def test_spaces_are_the_same_object_on_every_call():
    env = make()
    for agent in env.possible_agents:
        assert env.observation_space(agent) is env.observation_space(agent)
        assert env.action_space(agent) is env.action_space(agent)
    assert env.action_space("turbine_0") is env.action_space("turbine_7")


def trajectory(seed, steps=1000, agents=4):
    env = make(agents=agents, pattern="random", episode_length=steps)
    actions_rng = np.random.default_rng(99)
    obs, _ = env.reset(seed=seed)
    observations, rewards = [np.stack(list(obs.values()))], []
    while env.agents:
        acts = {a: int(actions_rng.integers(3)) for a in env.agents}
        obs, rew, *_ = env.step(acts)
        observations.append(np.stack(list(obs.values())))
        rewards.append(list(rew.values()))
    return np.array(observations), np.array(rewards)


def test_same_seed_same_1000_step_trajectory_and_different_seeds_differ():
    obs_a, rew_a = trajectory(seed=123)
    obs_b, rew_b = trajectory(seed=123)
    obs_c, _ = trajectory(seed=124)
    assert obs_a.shape == (1001, 4, 6)
    np.testing.assert_array_equal(obs_a, obs_b)
    np.testing.assert_array_equal(rew_a, rew_b)
    assert not np.array_equal(obs_a, obs_c)
    assert not np.array_equal(obs_a[-1], obs_c[-1])


def test_reset_without_seed_follows_the_scenario_seeds():
    first = make(seeds={"train": 41, "test": 42})
    second = make(seeds={"train": 41, "test": 42})
    np.testing.assert_array_equal(first.reset()[0]["turbine_0"], second.reset(seed=41)[0]["turbine_0"])
    test_split = hivex_dsl.parallel_env({"hivex": 1, "environment": "wind_farm_control",
                                         "seeds": {"train": 41, "test": 42}}, split="test")
    np.testing.assert_array_equal(test_split.reset()[0]["turbine_0"], make().reset(seed=42)[0]["turbine_0"])


def test_list_seeds_give_each_episode_its_seed_in_turn():
    env = make(seeds={"train": [7, 8], "test": [9]})
    firsts = [env.reset()[0]["turbine_0"] for _ in range(3)]
    np.testing.assert_array_equal(firsts[0], firsts[2])
    assert not np.array_equal(firsts[0], firsts[1])
    np.testing.assert_array_equal(firsts[1], make().reset(seed=8)[0]["turbine_0"])


def test_infos_carry_reward_terms_and_episode_sums_at_the_end():
    env = make(agents=2, episode_length=5, task="avoid_damage")
    env.reset(seed=0)
    total = {a: 0.0 for a in env.possible_agents}
    for step in range(5):
        _, rewards, terms, truncs, infos = env.step({a: 1 for a in env.agents})
        for a in rewards:
            assert set(infos[a]["reward_terms"]) == {"avoid_damage"}
            assert rewards[a] == pytest.approx(infos[a]["reward_terms"]["avoid_damage"])
            total[a] += rewards[a]
    assert all(truncs.values()) and not any(terms.values())
    assert env.agents == []
    for a in env.possible_agents:
        assert infos[a]["hivex_episode"] == {"return": pytest.approx(total[a]), "length": 5, "decisions": 5,
                                       "reward_terms": {"avoid_damage": pytest.approx(total[a])},
                                       "statistics": {"Individual Performance": 0.0,
                                                      "Avoid Damage Reward": pytest.approx(total[a])}}


def test_weight_overrides_scale_the_reward():
    plain, doubled = make(agents=2), make(agents=2, weights={"generate_energy": 2.0, "avoid_damage": 0.5})
    plain.reset(seed=3), doubled.reset(seed=3)
    for _ in range(30):
        _, r1, *_ , i1 = plain.step({a: 2 for a in plain.agents})
        _, r2, *_ , i2 = doubled.step({a: 2 for a in doubled.agents})
    for a in r1:
        assert r2[a] == pytest.approx(2.0 * r1[a] + 0.5 * i2[a]["reward_terms"]["avoid_damage"])


@pytest.mark.parametrize("bad, message", [
    ({"turbine_0": 3}, r"action for turbine_0 is 3, not in Discrete\(3\) \(0 do nothing, 1 rotate left, 2 rotate right\)"),
    ({"turbine_1": -1}, r"action for turbine_1 is -1, not in Discrete\(3\)"),
    ({"turbine_0": 0.5}, r"action for turbine_0 is 0.5, not in Discrete\(3\)"),
    ({"turbine_9": 0}, r"'turbine_9', which is not a live agent"),
])
def test_wrong_actions_name_the_agent_and_the_space(bad, message):
    env = make(agents=2)
    env.reset(seed=0)
    actions = {"turbine_0": 0, "turbine_1": 0} | bad
    with pytest.raises(hivex_dsl.ActionError, match=message):
        env.step(actions)


def test_missing_action_is_named():
    env = make(agents=2)
    env.reset(seed=0)
    with pytest.raises(hivex_dsl.ActionError, match="no action for turbine_1"):
        env.step({"turbine_0": 0})


def test_render_gives_an_rgb_picture():
    env = make(agents=3)
    env.render_mode = "rgb_array"
    env.reset(seed=0)
    frame = env.render()
    assert frame.dtype == np.uint8 and frame.ndim == 3 and frame.shape[2] == 3
    assert len(np.unique(frame.reshape(-1, 3), axis=0)) > 10


def spin_when_rotating_left(sim, state, actions, rng):
    """WFC's step, with an event 'spun' for every agent that rotates left."""
    new, outcome = sim.step(state, actions, rng)
    return new, StepOutcome(outcome.terminated, {"spun": np.asarray(actions) == 1})


def test_task_events_end_single_agents_and_the_others_go_on(restepped):
    sc = hivex_dsl.compile({"hivex": 1, "environment": "wind_farm_control", "agents": 3, "episode_length": 10})
    env = hivex_dsl.parallel_env(restepped(sc, spin_when_rotating_left, {"spun": "rotated left"}, ("spun",)))
    env.reset(seed=0)
    _, _, terms, truncs, infos = env.step({"turbine_0": 0, "turbine_1": 1, "turbine_2": 0})
    assert terms == {"turbine_0": False, "turbine_1": True, "turbine_2": False}
    assert env.agents == ["turbine_0", "turbine_2"] and infos["turbine_1"]["hivex_episode"]["length"] == 1
    for _ in range(9):
        _, rewards, terms, truncs, _ = env.step({a: 0 for a in env.agents})
        assert "turbine_1" not in rewards
    assert truncs == {"turbine_0": True, "turbine_2": True} and env.agents == []
