"""SuperSuit's vector conversion runs every environment (the flat parallel env with ``respawn=True``, as
docs/ecosystem.md says): slot i is possible agent i, the rewards and observations are the parallel env's step for
step across world ends, and concatenated copies step together. Deaths are test_agent_death's."""

from __future__ import annotations

import numpy as np
import pytest

import hivex_dsl
from hivex_dsl.compiler import registry
from hivex_dsl.adapters.flat import FlatParallelEnv
from hivex_dsl.adapters.registration import make_scenario

ENV_IDS = list(registry.environments())
CYCLES = 4  # decisions per world episode: the loop below crosses two world ends


def flat_env(env_id: str):
    """The flat parallel env SuperSuit takes, of the environment's main scenario with short episodes."""
    return FlatParallelEnv(hivex_dsl.parallel_env(make_scenario(env_id, "main", max_cycles=CYCLES), respawn=True))


@pytest.mark.ecosystem("supersuit")
@pytest.mark.parametrize("env_id", ENV_IDS)
def test_supersuit_vector_conversion_steps_as_the_parallel_env_does(env_id):
    supersuit = pytest.importorskip("supersuit")
    venv, reference = supersuit.pettingzoo_env_to_vec_env_v1(flat_env(env_id)), flat_env(env_id)
    agents = reference.possible_agents
    obs, _ = venv.reset(seed=4)
    expected, _ = reference.reset(seed=4)
    space = reference.action_space(agents[0])
    space.seed(0)
    world_ends = 0
    for _ in range(2 * CYCLES + 1):
        np.testing.assert_array_equal(obs, np.stack([expected[a] for a in agents]))
        actions = np.stack([space.sample() for _ in agents])
        obs, rewards, terminated, truncated, infos = venv.step(actions)
        expected, p_rewards, p_term, p_trunc, _ = reference.step(dict(zip(agents, actions)))
        np.testing.assert_array_equal(rewards, np.array([p_rewards[a] for a in agents], np.float32))
        np.testing.assert_array_equal(truncated.astype(bool), [p_trunc[a] for a in agents])
        if not reference.agents:  # the world ended: SuperSuit reset it within the step
            world_ends += 1
            assert all("terminal_observation" in info for info in infos)
            expected, _ = reference.reset()
    assert world_ends == 2


@pytest.mark.ecosystem("supersuit")
@pytest.mark.parametrize("env_id", ENV_IDS)
def test_supersuit_concatenated_copies_step_together(env_id):
    supersuit = pytest.importorskip("supersuit")
    single = supersuit.pettingzoo_env_to_vec_env_v1(flat_env(env_id))
    copies = supersuit.concat_vec_envs_v1(single, 2, base_class="gymnasium")
    assert copies.num_envs == 2 * single.num_envs
    obs, _ = copies.reset(seed=1)
    copies.action_space.seed(0)  # one slot's space, as SB3 takes it
    for _ in range(CYCLES + 1):
        actions = np.stack([copies.action_space.sample() for _ in range(copies.num_envs)])
        obs, rewards, terminated, truncated, _ = copies.step(actions)
        assert obs.shape == (copies.num_envs, *single.observation_space.shape) and np.isfinite(rewards).all()
    assert not np.array_equal(obs[:single.num_envs], obs[single.num_envs:])  # two worlds, not one twice
