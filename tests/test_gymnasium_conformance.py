"""Gymnasium conformance of the vector env: ids, autoreset modes, key names, fresh observations,
distinct copies, the worlds parameter, and one world following the parallel env across episodes."""

from __future__ import annotations

import gymnasium
import numpy as np
import pytest
from gymnasium.vector import AutoresetMode

import hivex_dsl
from hivex_dsl.compiler import registry
from hivex_dsl.adapters.registration import bundled_scenarios, camel

ENV_IDS = list(registry.environments())
WFC = {"hivex": 1, "environment": "wind_farm_control", "agents": 3, "episode_length": 4}


@pytest.mark.ecosystem("gymnasium")
@pytest.mark.parametrize("env_id", ENV_IDS)
def test_make_vec_with_an_id_and_scenario_keywords(env_id):
    venv = gymnasium.make_vec(f"hivex/{camel(env_id)}-v0", num_envs=2, episode_length=5)
    assert venv.num_worlds == 2 and venv.num_envs == 2 * venv.agents_per_world
    assert venv.compiled.episode_length == 5 and venv.compiled.environment == env_id
    obs, _ = venv.reset(seed=0)
    assert venv.observation_space.contains(obs)


def test_make_vec_takes_task_and_level_and_bundled_scenario_ids_exist():
    venv = gymnasium.make_vec("hivex/AerialWildfireSuppression-v0", task="find_fire", level=3, episode_length=5)
    assert venv.compiled.task_name == "find_fire" and venv.compiled.level == 3
    assert "main" in bundled_scenarios("ocean_plastic_collection")
    named = gymnasium.make_vec("hivex/AerialWildfireSuppression-FindFire-v0", episode_length=5)
    assert named.compiled.task_name == "find_fire"
    with pytest.raises(ValueError, match="no difficulty levels"):
        gymnasium.make_vec("hivex/OceanPlasticCollection-v0", level=2)


def test_gymnasium_make_says_the_environment_is_multi_agent_and_where_to_go():
    # without an entry_point Gymnasium said only 'registered but entry_point is not specified'
    with pytest.raises(hivex_dsl.HivexError) as refused:
        gymnasium.make("hivex/AerialWildfireSuppression-FindFire-v0")
    assert str(refused.value) == (
        "hivex/AerialWildfireSuppression-FindFire-v0 is a multi-agent environment, which gymnasium.make cannot "
        "build: gymnasium.make_vec('hivex/AerialWildfireSuppression-FindFire-v0', num_envs=N) gives N worlds with a "
        "slot per agent, and hivex_dsl.zoo.aerial_wildfire_suppression_v0.parallel_env() gives PettingZoo's "
        "parallel API")
    from hivex_dsl.zoo import aerial_wildfire_suppression_v0  # the module it names

    assert aerial_wildfire_suppression_v0.parallel_env().possible_agents


def test_the_old_num_envs_keyword_is_refused_with_the_reason():
    with pytest.raises(hivex_dsl.HivexError, match="num_worlds="):
        hivex_dsl.vector_env(WFC, num_envs=4)
    venv = hivex_dsl.vector_env(WFC, num_worlds=4)
    assert (venv.num_worlds, venv.num_envs) == (4, 12)


@pytest.mark.parametrize("mode", [AutoresetMode.NEXT_STEP, AutoresetMode.SAME_STEP])
def test_both_autoreset_modes_are_declared(mode):
    venv = hivex_dsl.vector_env(WFC, autoreset_mode=mode)
    assert venv.metadata["autoreset_mode"] is mode and venv.autoreset_mode is mode
    with pytest.raises(ValueError, match="autoreset_mode"):
        hivex_dsl.vector_env(WFC, autoreset_mode=AutoresetMode.DISABLED)


def test_same_step_returns_first_observations_at_once_and_the_last_in_infos():
    same = hivex_dsl.vector_env(WFC, autoreset_mode="same_step")
    nxt = hivex_dsl.vector_env(WFC)
    same.reset(seed=5)
    nxt.reset(seed=5)
    actions = np.zeros(3, np.int64)
    for _ in range(4):
        s_obs, s_rew, _, s_trunc, s_info = same.step(actions)
        n_obs, n_rew, _, n_trunc, n_info = nxt.step(actions)
    assert s_trunc.all() and n_trunc.all()
    np.testing.assert_array_equal(s_rew, n_rew)
    np.testing.assert_array_equal(np.stack(list(s_info["final_obs"])), n_obs)  # SAME_STEP keeps the last one aside
    assert s_info["_final_obs"].all()
    restarted, *_ = nxt.step(actions)  # NEXT_STEP's restart gives the first observation a step later
    np.testing.assert_array_equal(s_obs, restarted)


@pytest.mark.ecosystem("gymnasium")
@pytest.mark.parametrize("env_id", ENV_IDS)
def test_observations_are_fresh_writable_arrays(env_id):
    scenario = {"hivex": 1, "environment": env_id, "episode_length": 5}
    venv = hivex_dsl.vector_env(scenario)
    obs, _ = venv.reset(seed=0)
    penv = hivex_dsl.parallel_env(scenario)
    p_obs, _ = penv.reset(seed=0)
    actions = venv.action_space.sample()
    stepped, *_ = venv.step(actions)
    for tree in (obs, stepped, *p_obs.values()):
        for array in (tree.values() if isinstance(tree, dict) else [tree]):
            assert array.flags.writeable
            array[...] = 0  # never a view of the simulator's state
    again, *_ = venv.step(actions)
    assert any(np.any(a != 0) for a in (again.values() if isinstance(again, dict) else [again]))


def test_copies_of_one_scenario_are_different_worlds_unless_seeded():
    scenario = WFC | {"seeds": {"train": 11, "test": 12}}
    first, second = hivex_dsl.vector_env(scenario), hivex_dsl.vector_env(scenario)
    assert not np.array_equal(first.reset()[0], second.reset()[0])
    np.testing.assert_array_equal(first.reset(seed=3)[0], second.reset(seed=3)[0])
    p1, p2 = hivex_dsl.parallel_env(scenario), hivex_dsl.parallel_env(scenario)
    assert not np.array_equal(p1.reset()[0]["turbine_0"], p2.reset()[0]["turbine_0"])


@pytest.mark.ecosystem("gymnasium")
@pytest.mark.parametrize("env_id", ["wind_farm_control", "wildfire_resource_management", "aerial_wildfire_suppression"])
def test_one_world_follows_the_parallel_env_across_episodes(env_id):
    """Issue 16: the autoreset step no longer steps the simulator on discarded actions."""
    scenario = {"hivex": 1, "environment": env_id, "episode_length": 6}
    venv = hivex_dsl.vector_env(scenario)
    penv = hivex_dsl.parallel_env(scenario)
    v_obs, _ = venv.reset(seed=2)
    p_obs, _ = penv.reset(seed=2)
    rng = np.random.default_rng(0)
    for _ in range(3):  # three episodes
        for _ in range(6):
            venv.single_action_space.seed(int(rng.integers(2**31)))
            one = [venv.single_action_space.sample() for _ in penv.possible_agents]
            actions = {k: np.stack([a[k] for a in one]) for k in one[0]} if isinstance(one[0], dict) else np.stack(one)
            v_obs, v_rew, *_ = venv.step(actions)
            p_obs, p_rew, *_ = penv.step(dict(zip(penv.possible_agents, one)))
            np.testing.assert_allclose(v_rew, [p_rew[a] for a in penv.possible_agents])
        p_obs, _ = penv.reset()
        v_obs, *_ = venv.step(actions)  # NEXT_STEP restart
        for i, agent in enumerate(penv.possible_agents):
            for key in (p_obs[agent] if isinstance(p_obs[agent], dict) else [None]):
                mine = v_obs[i] if key is None else v_obs[key][i]
                np.testing.assert_array_equal(mine, p_obs[agent] if key is None else p_obs[agent][key])


def test_human_rendering_opens_a_window_or_is_skipped_cleanly(monkeypatch):
    pytest.importorskip("pygame")
    monkeypatch.setenv("SDL_VIDEODRIVER", "dummy")
    venv = hivex_dsl.vector_env(WFC, render_mode="human")
    venv.reset(seed=0)
    venv.step(np.zeros(3, np.int64))
    assert venv.render() is None and venv._window.screen is not None
    venv.close()
    monkeypatch.setenv("SDL_VIDEODRIVER", "no-such-driver")
    venv = hivex_dsl.vector_env(WFC, render_mode="human")
    with pytest.warns(UserWarning, match="no window"):
        venv.reset(seed=0)
    venv.step(np.zeros(3, np.int64))  # runs on
    venv.close()


def test_supersuit_concatenated_copies_are_different_worlds():
    supersuit = pytest.importorskip("supersuit")
    env = hivex_dsl.parallel_env(WFC | {"seeds": {"train": 21, "test": 22}})
    copies = supersuit.concat_vec_envs_v1(supersuit.pettingzoo_env_to_vec_env_v1(env), 3, base_class="gymnasium")
    for seed in (None, 4):
        obs, _ = copies.reset(seed=seed)
        worlds = obs.reshape(3, 3, -1)
        assert not np.array_equal(worlds[0], worlds[1]) and not np.array_equal(worlds[1], worlds[2])
