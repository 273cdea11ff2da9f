"""Every adapter hands the drop's action mask on in the form its consumers read (issue 52): the vector env as one
(num_envs, N) int8 array in the infos, the parallel env as the mask ``action_space.sample(mask=...)`` takes (as
PettingZoo's own environments and its API test read it), the flat views of a hybrid action under
``discrete_action_mask`` (TorchRL's view without it), the joint view joined, SB3 per slot."""

from __future__ import annotations

import numpy as np
import pytest
from gymnasium import spaces

from hivex_dsl.adapters.factory import parallel_env, vector_env
from hivex_dsl.adapters.flat import DISCRETE_MASK_KEY, FlatParallelEnv, flat_vector_env
from hivex_dsl.adapters.joint import joint_mask
from hivex_dsl.sim.spaces import mask_row, sampling_mask

AWS, DBR = "aerial_wildfire_suppression/main", "drone_based_reforestation/main"


def hybrid_actions(env, rng):
    return {"continuous": rng.uniform(-1, 1, (env.num_envs, env.single_action_space["continuous"].shape[0])
                                      ).astype(np.float32),
            "discrete": rng.integers(0, 2, (env.num_envs, 1))}


@pytest.mark.parametrize("mode", ["next_step", "same_step"])
def test_the_vector_env_reports_the_mask_of_the_decision_its_observations_ask_for(mode):
    env = vector_env(AWS, num_worlds=2, autoreset_mode=mode)
    _, infos = env.reset(seed=0)
    rng = np.random.default_rng(0)
    seen_open = seen_closed = 0
    for _ in range(60):
        mask = infos["action_mask"]
        assert mask.shape == (env.num_envs, 2) and mask.dtype == np.int8
        np.testing.assert_array_equal(mask, env.unwrapped.core.action_mask().reshape(env.num_envs, 2))
        assert (mask[:, 0] == 1).all()
        seen_open, seen_closed = seen_open + int(mask[:, 1].sum()), seen_closed + int((mask[:, 1] == 0).sum())
        *_, infos = env.step(hybrid_actions(env, rng))
    assert seen_open and seen_closed  # planes with water over land, and planes that dropped it


def test_an_environment_without_masks_reports_none():
    env = vector_env("wind_farm_control/main", num_worlds=1)
    _, infos = env.reset(seed=0)
    assert "action_mask" not in infos
    _, infos = parallel_env("wildfire_resource_management/main").reset(seed=0)
    assert all("action_mask" not in info for info in infos.values())


def test_the_parallel_env_s_mask_is_what_the_space_samples_with():
    env = parallel_env(DBR)
    _, infos = env.reset(seed=0)
    space = env.action_space("drone_0")
    mask = infos["drone_0"]["action_mask"]
    assert mask["continuous"] is None and len(mask["discrete"]) == 1
    assert mask["discrete"][0].tolist() == [1, 0]  # the drones start at their station: nothing to drop yet
    assert {int(space.sample(mask)["discrete"][0]) for _ in range(200)} == {0}
    core = env.core.action_mask()[0]
    assert all(mask_row(infos[a]["action_mask"]).tolist() == core[i].tolist() for i, a in enumerate(env.agents))


def test_sampling_mask_and_mask_row_are_inverse_for_every_action_space():
    row = np.array([1, 0, 1, 0, 1], np.int8)
    multi = spaces.MultiDiscrete([3, 2])
    assert [part.tolist() for part in sampling_mask(multi, row)] == [[1, 0, 1], [0, 1]]
    assert sampling_mask(spaces.Discrete(5), row) is row
    hybrid = spaces.Dict({"continuous": spaces.Box(-1, 1, (2,)), "discrete": multi})
    for space in (multi, spaces.Discrete(5), hybrid):
        assert mask_row(sampling_mask(space, row)).tolist() == row.tolist()


def test_the_flat_views_move_a_hybrid_mask_off_the_flat_box():
    flat = flat_vector_env(vector_env(AWS, num_worlds=1))
    _, infos = flat.reset(seed=0)
    assert "action_mask" not in infos and infos[DISCRETE_MASK_KEY].shape == (3, 2)
    *_, infos = flat.step(np.zeros((3, 2), np.float32))
    assert infos[DISCRETE_MASK_KEY].shape == (3, 2)
    per_agent = FlatParallelEnv(parallel_env(AWS))
    _, infos = per_agent.reset(seed=0)
    assert all(list(info) == [DISCRETE_MASK_KEY] and info[DISCRETE_MASK_KEY].shape == (2,) for info in infos.values())
    _, infos = FlatParallelEnv(parallel_env(AWS), discrete_mask=False).reset(seed=0)
    assert all(info == {} for info in infos.values())  # TorchRL's view: its info spec comes from these


def test_the_joint_mask_opens_a_joint_action_where_every_branch_choice_is_open():
    space = spaces.MultiDiscrete([2, 3])
    # branch 0 allows 0 only, branch 1 allows 0 and 1: joint j = 3 a_0 + a_1 opens 0 and 1
    assert joint_mask(space, np.array([1, 0, 1, 1, 0])).tolist() == [1, 1, 0, 0, 0, 0]
    both = np.array([[1, 0, 1, 1, 0], [0, 1, 0, 0, 1]])
    assert joint_mask(space, both).tolist() == [[1, 1, 0, 0, 0, 0], [0, 0, 0, 0, 0, 1]]
    assert joint_mask(space, (np.array([1, 1]), np.array([0, 0, 1]))).tolist() == [0, 0, 1, 0, 0, 1]


def test_sb3_slots_carry_their_row_of_the_mask():
    pytest.importorskip("stable_baselines3", reason="the sb3 extra is not installed")
    from hivex_dsl.adapters.sb3 import SB3VecEnv

    env = SB3VecEnv(DBR)
    env.reset()
    assert [info[DISCRETE_MASK_KEY].tolist() for info in env.reset_infos] == [[1, 0]] * 3
    env.step_async(np.zeros((3, 4), np.float32))
    *_, infos = env.step_wait()
    assert all(info[DISCRETE_MASK_KEY].shape == (2,) for info in infos)
