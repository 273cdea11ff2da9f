"""The joint-Discrete views of the MultiDiscrete environments: one Discrete action is the branches' choices."""

from __future__ import annotations

import numpy as np
import pytest
from gymnasium import spaces
from pettingzoo.test import parallel_api_test

import hivex_dsl
from hivex_dsl.adapters.flat import flat_vector_env
from hivex_dsl.adapters.joint import JointDiscreteParallelEnv, joint_vector_env, split_joint
from hivex_dsl.base.errors import ActionError



def short(env_id: str):
    return hivex_dsl.compile({"hivex": 1, "environment": env_id, "episode_length": 12, "decision_period": 1})


def test_the_joint_index_is_the_branches_choices_in_mixed_radix():
    wrm = spaces.MultiDiscrete([3, 3, 3, 3])
    # j = 27 a0 + 9 a1 + 3 a2 + a3: 50 = 27 + 2 x 9 + 1 x 3 + 2
    np.testing.assert_array_equal(split_joint(wrm, np.array([0, 50, 80])), [[0, 0, 0, 0], [1, 2, 1, 2], [2, 2, 2, 2]])
    opc = spaces.MultiDiscrete([2, 3])
    np.testing.assert_array_equal(split_joint(opc, np.arange(6)), [[0, 0], [0, 1], [0, 2], [1, 0], [1, 1], [1, 2]])


@pytest.mark.parametrize("env_id, joint", [("wildfire_resource_management", 81), ("ocean_plastic_collection", 6)])
def test_the_joint_parallel_env_plays_what_the_branches_would(env_id, joint):
    raw = hivex_dsl.parallel_env(short(env_id))
    env = JointDiscreteParallelEnv(hivex_dsl.parallel_env(short(env_id)))
    assert env.action_space(env.possible_agents[0]) == spaces.Discrete(joint)
    branches = raw.action_space(raw.possible_agents[0])
    raw.reset(seed=3)
    env.reset(seed=3)
    rng = np.random.default_rng(0)
    while env.agents:
        chosen = {agent: int(rng.integers(joint)) for agent in env.agents}
        expected = raw.step({agent: split_joint(branches, j) for agent, j in chosen.items()})
        got = env.step(chosen)
        for ours, theirs in zip(got[1:4], expected[1:4]):
            assert ours == theirs
    with pytest.raises(ActionError, match=rf"Discrete\({joint}\)"):
        env.reset(seed=0)
        env.step({agent: joint for agent in env.agents})


def test_the_joint_parallel_env_passes_pettingzoo_s_api_test():
    parallel_api_test(JointDiscreteParallelEnv(hivex_dsl.parallel_env(short("wildfire_resource_management"))),
                      num_cycles=20)


def test_the_joint_vector_env_plays_what_the_branches_would_and_keeps_the_autoreset_mode():
    raw = hivex_dsl.vector_env(short("ocean_plastic_collection"), num_worlds=2)
    env = joint_vector_env(hivex_dsl.vector_env(short("ocean_plastic_collection"), num_worlds=2))
    assert env.single_action_space == spaces.Discrete(6) and env.autoreset_mode == raw.autoreset_mode
    raw.reset(seed=1)
    env.reset(seed=1)
    for joint in np.random.default_rng(2).integers(0, 6, (14, env.num_envs)):
        expected, got = raw.step(split_joint(raw.single_action_space, joint)), env.step(joint)
        np.testing.assert_array_equal(got[1], expected[1])
        np.testing.assert_array_equal(got[0]["vector"], expected[0]["vector"])
    with pytest.raises(ActionError, match=r"Discrete\(6\)"):
        env.step(np.full(env.num_envs, 6))


def test_the_flat_views_keep_the_autoreset_mode():
    env = flat_vector_env(hivex_dsl.vector_env(short("aerial_wildfire_suppression"), num_worlds=1,
                                               autoreset_mode="same_step"))
    assert env.autoreset_mode == env.unwrapped.autoreset_mode


def test_an_environment_without_branches_to_join_is_refused():
    with pytest.raises(ValueError, match="joins the branches of a MultiDiscrete action; this environment's action "
                                         r"space is Discrete\(3\)"):
        JointDiscreteParallelEnv(hivex_dsl.parallel_env("wind_farm_control/main"))
