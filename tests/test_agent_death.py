"""Agent death as stock consumers see it: per-slot episodes with a flag on the death step and a respawn.

Deaths are forced deterministically: vessels at full throttle and planes flying straight ahead
cross the border (OPC's crash ends a vessel's episode; AWS's border ends a plane's).
RecordEpisodeStatistics, SuperSuit's vector conversion and the flat wrappers must all count the
same per-agent returns and lengths as the toolkit's own ``hivex_episode`` sums, and those must
equal the rewards summed by hand under Gymnasium's autoreset rules.
"""

from __future__ import annotations

import numpy as np
import pytest
from gymnasium import spaces
from gymnasium.vector import AutoresetMode
from gymnasium.wrappers.vector import RecordEpisodeStatistics

import hivex_dsl
from hivex_dsl.adapters.flat import FlatParallelEnv, flat_vector_env

LENGTH = {"ocean_plastic_collection": 400, "aerial_wildfire_suppression": 160}


def scenario(environment: str) -> dict:
    return {"hivex": 1, "environment": environment, "episode_length": LENGTH[environment],
            "seeds": {"train": 1, "test": 2}}


def straight_ahead(environment: str, slots: int, flat: bool = False):
    """Full throttle, no steering (OPC); no steering, no drop (AWS): every agent ends at the border."""
    if environment == "ocean_plastic_collection":
        return np.tile([1, 0], (slots, 1))
    if flat:  # continuous 0 (straight), discrete bin 0 (no drop)
        return np.tile(np.array([0.0, -1.0], np.float32), (slots, 1))
    return {"continuous": np.zeros((slots, 1), np.float32), "discrete": np.zeros((slots, 1), np.int64)}


def hand_counted(rewards, dones, mode):
    """Per-slot (return, length) of finished episodes, from the raw step results by Gymnasium's rules."""
    slots = rewards[0].shape[0]
    ret, length, prev, out = np.zeros(slots), np.zeros(slots, int), np.zeros(slots, bool), []
    for r, d in zip(rewards, dones):
        counted = np.ones(slots, bool) if mode is AutoresetMode.SAME_STEP else ~prev
        if mode is AutoresetMode.NEXT_STEP:
            assert np.all(r[prev] == 0.0)  # the restart step of a slot gives reward 0
            ret[prev], length[prev] = 0.0, 0
        ret[counted] += r[counted]
        length[counted] += 1
        out.append([(s, ret[s], length[s]) for s in np.flatnonzero(d)])
        if mode is AutoresetMode.SAME_STEP:
            ret[d], length[d] = 0.0, 0
        prev = d
    return out


@pytest.mark.parametrize("environment", list(LENGTH))
@pytest.mark.parametrize("mode", ["next_step", "same_step"])
@pytest.mark.parametrize("flat", [False, True])
def test_record_episode_statistics_counts_what_the_toolkit_sums_including_deaths(environment, mode, flat):
    venv = hivex_dsl.vector_env(scenario(environment), num_worlds=2, autoreset_mode=mode)
    if flat:
        venv = flat_vector_env(venv)
    stats = RecordEpisodeStatistics(venv)
    stats.reset(seed=3)
    actions = straight_ahead(environment, stats.num_envs, flat)
    rewards, dones, ours, deaths, finished = [], [], [], 0, 0
    for _ in range(LENGTH[environment] + 3):
        obs, reward, terminated, truncated, infos = stats.step(actions)
        assert stats.observation_space.contains(obs)
        done = terminated | truncated
        rewards.append(reward)
        dones.append(done)
        ours.append([(s, infos["hivex_episode"]["return"][s], infos["hivex_episode"]["length"][s])
                     for s in np.flatnonzero(done)])
        if not done.any():
            assert "hivex_episode" not in infos and "episode" not in infos
            continue
        # the wrapper's episode stats and ours agree slot by slot, and so do the flags
        np.testing.assert_array_equal(infos["_episode"], done)
        np.testing.assert_array_equal(infos["_hivex_episode"], done)
        np.testing.assert_allclose(infos["episode"]["r"], infos["hivex_episode"]["return"], rtol=1e-9, atol=1e-9)
        np.testing.assert_array_equal(infos["episode"]["l"], infos["hivex_episode"]["length"])
        deaths += int(np.count_nonzero(terminated & ~truncated))
        finished += int(np.count_nonzero(done))
    assert deaths >= 2 and finished > deaths  # agents died alone, and worlds ran out of time later
    by_hand = hand_counted(rewards, dones, stats.metadata["autoreset_mode"])
    assert sum(len(step) for step in by_hand) == finished
    for mine, theirs in zip(ours, by_hand):
        assert [(s, length) for s, _, length in mine] == [(s, length) for s, _, length in theirs]
        np.testing.assert_allclose([r for _, r, _ in mine], [r for _, r, _ in theirs], rtol=1e-9, atol=1e-9)


@pytest.mark.parametrize("environment", list(LENGTH))
def test_a_dead_slot_comes_back_with_a_first_observation_and_plays_on(environment):
    venv = hivex_dsl.vector_env(scenario(environment), num_worlds=1)
    venv.reset(seed=3)
    actions = straight_ahead(environment, venv.num_envs)
    for _ in range(LENGTH[environment]):
        obs, reward, terminated, truncated, infos = venv.step(actions)
        if terminated.any() and not truncated.any():
            break
    slot = int(np.flatnonzero(terminated)[0])
    assert infos["hivex_episode"]["length"][slot] > 0
    obs, reward, terminated, truncated, infos = venv.step(actions)  # NEXT_STEP: the slot restarts
    assert reward[slot] == 0.0 and not terminated[slot] and not truncated[slot]
    assert abs(obs["vector"][slot, 0]) < 1.0 and abs(obs["vector"][slot, 1]) < 1.0  # back inside the border
    for _ in range(3):
        obs, reward, terminated, truncated, infos = venv.step(actions)
    assert not terminated[slot]  # it plays on: its steps count in its new episode


@pytest.mark.parametrize("environment", list(LENGTH))
def test_supersuit_vector_conversion_counts_per_agent_returns_including_deaths(environment):
    supersuit = pytest.importorskip("supersuit")
    env = FlatParallelEnv(hivex_dsl.parallel_env(scenario(environment), respawn=True))
    venv = supersuit.pettingzoo_env_to_vec_env_v1(env)
    venv.reset(seed=3)
    actions = straight_ahead(environment, venv.num_envs, flat=True)
    ret, length = np.zeros(venv.num_envs), np.zeros(venv.num_envs, int)
    deaths = episodes = 0
    for _ in range(LENGTH[environment] + 3):
        obs, reward, terminated, truncated, infos = venv.step(actions)
        ret += reward
        length += 1
        for slot in np.flatnonzero(terminated | truncated):  # SuperSuit restarts a slot within the step
            summary = infos[slot]["hivex_episode"]
            assert summary["length"] == length[slot]
            assert summary["return"] == pytest.approx(ret[slot], rel=1e-5, abs=1e-4)  # SuperSuit sums float32
            assert "terminal_observation" in infos[slot]
            ret[slot], length[slot] = 0.0, 0
            deaths += bool(terminated[slot]) and not truncated.any()
            episodes += 1
    assert deaths >= 2 and episodes > deaths


@pytest.mark.parametrize("environment", list(LENGTH))
def test_the_parallel_env_keeps_pettingzoo_semantics_by_default(environment):
    env = hivex_dsl.parallel_env(scenario(environment))
    env.reset(seed=3)
    left = None
    for _ in range(LENGTH[environment]):
        actions = {a: (np.array([1, 0]) if environment == "ocean_plastic_collection" else
                       {"continuous": np.zeros(1, np.float32), "discrete": np.zeros(1, np.int64)}) for a in env.agents}
        _, _, terminated, truncated, infos = env.step(actions)
        gone = [a for a in terminated if terminated[a] and not truncated[a]]
        if gone and env.agents:
            left = gone[0]
            break
    assert left is not None and left not in env.agents and "hivex_episode" in infos[left]


@pytest.mark.parametrize("environment", list(LENGTH))
def test_sb3_vec_monitor_counts_per_agent_returns_including_deaths(environment):
    pytest.importorskip("stable_baselines3")
    from stable_baselines3.common.vec_env import VecMonitor

    from hivex_dsl.adapters.sb3 import SB3VecEnv

    venv = VecMonitor(SB3VecEnv(scenario(environment), num_worlds=2))
    venv.seed(3)
    venv.reset()
    actions = straight_ahead(environment, venv.num_envs, flat=True)
    deaths = episodes = 0
    for _ in range(LENGTH[environment] + 3):
        obs, reward, dones, infos = venv.step(actions)
        assert all(venv.observation_space.contains(o) for o in obs)  # SB3 spaces are one slot's
        for slot in np.flatnonzero(dones):
            mine, monitor = infos[slot]["hivex_episode"], infos[slot]["episode"]
            assert monitor["l"] == mine["length"]
            assert monitor["r"] == pytest.approx(mine["return"], rel=1e-5, abs=1e-4)  # VecMonitor sums float32
            assert venv.observation_space.contains(infos[slot]["terminal_observation"])
            deaths += not infos[slot]["TimeLimit.truncated"]
            episodes += 1
    assert deaths >= 2 and episodes > deaths


@pytest.mark.parametrize("environment", ["ocean_plastic_collection", "aerial_wildfire_suppression",
                                         "drone_based_reforestation"])
def test_respawn_where_restarts_only_the_masked_agents(environment):
    from hivex_dsl.runtime import BatchedEnv

    core = BatchedEnv(hivex_dsl.compile({"hivex": 1, "environment": environment, "episode_length": 50}), batch=2)
    core.reset(seed=0)
    space = core.sim.action_space
    space.seed(0)
    for _ in range(5):
        sample = [space.sample() for _ in range(2 * core.agents)]
        actions = ({k: np.stack([s[k] for s in sample]).reshape((2, core.agents) + space[k].shape) for k in space.spaces}
                   if isinstance(space, spaces.Dict) else np.stack(sample).reshape((2, core.agents) + space.shape))
        core.step(actions)
    before = core.observe()
    mask = np.zeros((2, core.agents), bool)
    mask[1, 0] = True
    state = core.sim.respawn_where(core.state, mask, np.random.default_rng(1))
    after = core.sim.observe(state)
    for key in before:
        np.testing.assert_array_equal(after[key][~mask], before[key][~mask])  # the others are untouched
        assert core.sim.observation_space[key].contains(np.asarray(after[key][1, 0]))
    if environment == "drone_based_reforestation":
        assert state.energy[1, 0] == 1.0 and state.alive[1, 0]
        np.testing.assert_array_equal(after["vector"][1, 0, :10], after["vector"][1, 0, 10:])  # a first observation
    if environment == "ocean_plastic_collection":
        assert state.active[1, 0] and state.speed[1, 0] == 0.0 and state.collected_total[1, 0] == 0
    if environment == "aerial_wildfire_suppression":
        assert state.flying[1, 0] and not state.seen_fire[1, 0]
