"""Stacked observations shift once a decision, as ML-Agents' stacking sensors do (hivex_dsl.sim.stacking).

Drone-Based Reforestation and Ocean Plastic Collection decide every 5th physics step and stack two frames, newest
first: the older stack a decision shows is the newest of the previous decision, 5 physics steps back, and at a
period of 1 the previous physics step's. The motions are held fixed so that the positions are computed by hand from
the simulators' equations: a vessel from rest under full throttle and no steer gains speed
s_n = s_(n-1) (1 - drag) + acceleration and moves s_n along its heading each step; a drone climbing at full
up control rises climb_speed_m a step.
"""

from __future__ import annotations

import numpy as np
import pytest

import hivex_dsl
from hivex_dsl.runtime import BatchedEnv
from hivex_dsl.runtime.global_state import AGENT_OBSERVATIONS

OPC, DBR = "ocean_plastic_collection", "drone_based_reforestation"


def env_of(env_id: str, period: int, **fields) -> BatchedEnv:
    return BatchedEnv(hivex_dsl.compile({"hivex": 1, "environment": env_id, "decision_period": period} | fields))


def full_ahead(agents: int) -> np.ndarray:
    """(1, A, 2) OPC actions: throttle 1, steer 0 (straight on)."""
    return np.tile(np.array([1, 0]), (1, agents, 1))


def climb(agents: int) -> dict:
    """(1, A) DBR actions: no throttle, no steer, full up; no drop."""
    return {"continuous": np.tile(np.array([0.0, 0.0, 1.0], np.float32), (1, agents, 1)),
            "discrete": np.zeros((1, agents, 1), np.int64)}


def vessel_path(params, steps: int) -> np.ndarray:
    """(steps + 1,) metres a vessel from rest has moved along its heading after 0..steps full-throttle steps."""
    speed, path = 0.0, [0.0]
    for _ in range(steps):
        speed = speed * (1.0 - params.drag) + params.acceleration
        path.append(path[-1] + speed)
    return np.array(path)


@pytest.mark.parametrize("period", [5, 1])
def test_a_vessel_s_older_stack_is_where_it_was_at_the_previous_decision(period):
    env = env_of(OPC, period)
    half = env.compiled.generators["pollution"].half_extent_m
    first = env.reset(seed=0)["vector"][0]
    start, facing = first[:, 0:2] * half, first[:, 2:4]
    path = vessel_path(env.compiled.params, 2 * period)
    obs = [first]
    for decision in (1, 2):
        obs.append(env.step(full_ahead(env.agents)).observations["vector"][0])
        newest, older = obs[-1][:, 0:2] * half, obs[-1][:, 6:8] * half
        np.testing.assert_allclose(newest, start + facing * path[decision * period], atol=1e-4)
        np.testing.assert_allclose(older, start + facing * path[(decision - 1) * period], atol=1e-4)
        np.testing.assert_array_equal(obs[-1][:, 6:12], obs[-2][:, 0:6])  # the whole frame, bit for bit


@pytest.mark.parametrize("period", [5, 1])
def test_a_drone_s_older_stack_is_its_height_at_the_previous_decision(period):
    env = env_of(DBR, period)
    p = env.compiled.params
    metres = p.height_bound_m / p.vector_observation_gain  # per unit of an observed height (height / bound, gained)
    first = env.reset(seed=0)["vector"][0]
    start = first[:, 3] * metres  # height above sea level
    assert np.all(start + 2 * period * p.climb_speed_m < p.height_bound_m)  # no drone reaches the bound
    obs = [first]
    for decision in (1, 2):
        obs.append(env.step(climb(env.agents)).observations["vector"][0])
        rise = p.climb_speed_m * period
        np.testing.assert_allclose(obs[-1][:, 3] * metres, start + decision * rise, atol=1e-4)
        np.testing.assert_allclose(obs[-1][:, 13] * metres, start + (decision - 1) * rise, atol=1e-4)
        np.testing.assert_array_equal(obs[-1][:, 10:20], obs[-2][:, 0:10])


def test_a_camera_s_older_stack_is_what_it_saw_at_the_previous_decision():
    env = env_of(OPC, 5)
    before = env.reset(seed=1)["visual"]
    rng = np.random.default_rng(2)
    for _ in range(3):
        after = env.step(rng.integers(0, [2, 3], (1, env.agents, 2))).observations["visual"]
        np.testing.assert_array_equal(after[..., 1], before[..., 0])
        before = after


@pytest.mark.parametrize("env_id", [OPC, DBR])
def test_the_global_state_shows_the_stacks_the_agents_observe(env_id):
    env = hivex_dsl.parallel_env(hivex_dsl.compile(f"{env_id}/main"))
    gs = env.global_state
    env.reset(seed=0)
    for agent in env.possible_agents:
        env.action_space(agent).seed(0)
    for _ in range(2):
        obs, *_ = env.step({agent: env.action_space(agent).sample() for agent in env.agents})
    part = env.state()[gs.slices[AGENT_OBSERVATIONS]].reshape(len(env.possible_agents), -1)
    for i, agent in enumerate(env.possible_agents):
        np.testing.assert_array_equal(part[i], obs[agent]["vector"])


@pytest.mark.parametrize("env_id", [OPC, DBR])
def test_an_episode_s_first_observation_is_as_at_a_period_of_one(env_id):
    """The older stacks start as zeros (ML-Agents' StackingSensor starts and resets its buffer so), in both
    environments that stack: at any period, and after a restart at the end of a decision too."""
    five, one = env_of(env_id, 5), env_of(env_id, 1)
    first = five.reset(seed=4)
    for key, value in one.reset(seed=4).items():
        np.testing.assert_array_equal(first[key], value)
    vector, size = first["vector"], first["vector"].shape[-1] // 2
    assert vector[..., :size].any(axis=-1).all()  # a real frame is never all zeros (a drone's heading is a unit)
    np.testing.assert_array_equal(vector[..., size:], np.zeros_like(vector[..., size:]))
    actions = full_ahead(five.agents) if env_id == OPC else climb(five.agents)
    restarted = five.step(actions, restart=np.ones(1, bool)).observations["vector"]
    np.testing.assert_array_equal(restarted[..., size:], np.zeros_like(restarted[..., size:]))


def test_a_respawned_vessel_s_older_stacks_are_zeros_then_its_first_frame():
    env = env_of(OPC, 5, params={"crash_outcome": "end"})
    env.reset(seed=3)
    env.step(full_ahead(env.agents))
    mask = np.array([[True] + [False] * (env.agents - 1)])
    kept = env.observe()
    env.respawn_agents(mask)
    respawned = env.observe()
    assert not respawned["vector"][0, 0, 6:].any() and not respawned["visual"][0, 0, ..., 1].any()
    np.testing.assert_array_equal(respawned["vector"][0, 1:], kept["vector"][0, 1:])  # the others untouched
    after = env.step(full_ahead(env.agents)).observations
    np.testing.assert_array_equal(after["vector"][0, 0, 6:], respawned["vector"][0, 0, :6])
    np.testing.assert_array_equal(after["visual"][0, 0, ..., 1], respawned["visual"][0, 0, ..., 0])


def test_a_respawned_drone_s_older_stack_is_zeros_then_the_next_decision_shifts_its_first_frame_there():
    env = env_of(DBR, 5)
    env.reset(seed=3)
    env.step(climb(env.agents))
    env.step(climb(env.agents))
    env.respawn_agents(np.array([[True] + [False] * (env.agents - 1)]))
    observed = env.observe()["vector"][0]
    frames = observed[0]
    assert not frames[10:].any() and frames[:10].any()
    assert observed[1:, 10:].any(axis=-1).all()  # the others keep their older stacks
    after = env.step(climb(env.agents)).observations["vector"][0, 0]
    np.testing.assert_array_equal(after[10:], frames[:10])
    assert after[3] > frames[3]  # it climbed for a decision since
