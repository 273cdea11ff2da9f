"""The global state for centralised critics (hivex_dsl.runtime.global_state) on every environment, through PettingZoo's
``state()`` / ``state_space`` and the vector env's ``state()``: its layout, its bounds (PettingZoo's own state_test
and a property test over random rollouts), the agents' part against their observations, one world fact per
environment against a value computed by hand from the simulator state, determinism, dead agents and the decision
period."""

from __future__ import annotations

import importlib
import pickle

import numpy as np
import pytest
from gymnasium import spaces
from hypothesis import given, settings
from hypothesis import strategies as st
from pettingzoo.test import state_test

import hivex_dsl
from hivex_dsl.compiler import registry
from hivex_dsl.base.errors import ResetNeeded
from hivex_dsl.runtime.global_state import AGENT_OBSERVATIONS, EPISODE_PROGRESS, vector_space

from .crashes import first_agent_crashes_on

ENV_IDS = list(registry.environments())
CYCLES = 30


def scenario(env_id: str, **fields) -> dict:
    """Decision period 1 unless given (OPC and DBR default to 5): a step is a physics step, which the counts below
    assume; test_the_state_is_taken_at_the_decision covers a longer period."""
    return {"hivex": 1, "environment": env_id, "episode_length": CYCLES, "decision_period": 1,
            "seeds": {"train": 1, "test": 2}, **fields}


def vectors_of(obs) -> np.ndarray:
    """The vector part of one observation or of a batch of them."""
    return obs["vector"] if isinstance(obs, dict) else obs


def agent_part(env, state: np.ndarray) -> np.ndarray:
    """(..., A, D) agents' part of (..., K) states."""
    part = state[..., env.global_state.slices[AGENT_OBSERVATIONS]]
    return part.reshape(state.shape[:-1] + (env.global_state.agents, -1))


def random_actions(env, rng: np.random.Generator) -> dict:
    space = env.action_space(env.possible_agents[0])
    space.seed(int(rng.integers(2**31)))
    return {a: space.sample() for a in env.agents}


@pytest.mark.parametrize("env_id", ENV_IDS)
def test_state_space_is_a_flat_float32_box_laid_out_as_its_named_components(env_id):
    env = hivex_dsl.parallel_env(scenario(env_id))
    gs, space = env.global_state, env.state_space
    assert isinstance(space, spaces.Box) and space.dtype == np.float32 and space.shape == (gs.size,)
    assert np.all(space.low < space.high) and np.isfinite(space.low).all() and np.isfinite(space.high).all()
    names = [c.name for c in gs.components]
    assert names[0] == AGENT_OBSERVATIONS and names[-1] == EPISODE_PROGRESS and len(set(names)) == len(names)
    starts = [gs.slices[n].start for n in names]
    stops = [gs.slices[n].stop for n in names]
    assert starts[0] == 0 and stops[-1] == gs.size and starts[1:] == stops[:-1]  # contiguous, in order
    agents, vector = len(env.possible_agents), vector_space(env.observation_space(env.possible_agents[0]))
    assert gs.slices[AGENT_OBSERVATIONS].stop == agents * vector.shape[0]  # the vector parts only: no images
    for c in gs.components:
        assert gs.slices[c.name].stop - gs.slices[c.name].start == c.size * (agents if c.per_agent else 1)
        np.testing.assert_array_equal(space.low[gs.slices[c.name]], np.float32(c.low))
        np.testing.assert_array_equal(space.high[gs.slices[c.name]], np.float32(c.high))
    assert gs.size < 200 + 20 * agents  # moderate: images are left out
    with pytest.raises(ResetNeeded):
        env.state()
    env.reset(seed=0)
    state = env.state()
    assert state.dtype == np.float32 and state.shape == space.shape and space.contains(state)


@pytest.mark.parametrize("env_id", ENV_IDS)
def test_the_agents_part_is_every_agents_vector_observation_in_agent_order(env_id):
    env = hivex_dsl.parallel_env(scenario(env_id))
    rng = np.random.default_rng(0)
    obs, _ = env.reset(seed=4)
    for _ in range(5):
        part = agent_part(env, env.state())
        for i, agent in enumerate(env.possible_agents):
            np.testing.assert_array_equal(part[i], vectors_of(obs[agent]))
        obs, *_ = env.step(random_actions(env, rng))
    assert env.state()[-1] == np.float32(5 / CYCLES)  # episode progress: 5 of the episode's steps


def acting_on(env_id: str, env, rng: np.random.Generator) -> dict:
    """Random actions; DBR's drones fly ahead, climbing, and drop their seeds (they plant on the first steps)."""
    if env_id == "drone_based_reforestation":
        return {a: {"continuous": np.array([1.0, 0.0, 0.2], np.float32), "discrete": np.array([1])}
                for a in env.agents}
    return random_actions(env, rng)


def by_hand(env_id: str, env) -> dict:
    """Some world facts of world 0, computed from the simulator's state by the environment's own hook (its entry's
    ``state_facts``), independently of its ``world_state``."""
    core = env.core
    return core.compiled.entry.state_facts(core.sim, core.state, core.compiled.params)


@pytest.mark.parametrize("env_id", [env_id for env_id, entry in registry.environments().items() if entry.state_facts])
def test_world_facts_match_values_computed_by_hand_from_the_simulator_state(env_id):
    env = hivex_dsl.parallel_env(scenario(env_id))
    rng = np.random.default_rng(1)
    env.reset(seed=2)
    env.step(acting_on(env_id, env, rng))
    env.step(acting_on(env_id, env, rng))
    for step in range(12):
        if step % 4 == 0:
            state = env.state()
            for name, value in by_hand(env_id, env).items():
                np.testing.assert_allclose(state[env.global_state.slices[name]], np.asarray(value, np.float64),
                                           rtol=1e-6, atol=1e-6, err_msg=f"{env_id} {name} at step {step}")
        env.step(acting_on(env_id, env, rng))


@pytest.mark.parametrize("env_id", ENV_IDS)
def test_the_state_is_deterministic_with_the_seed(env_id):
    def states(seed: int) -> list[np.ndarray]:
        env = hivex_dsl.parallel_env(scenario(env_id))
        rng = np.random.default_rng(7)
        env.reset(seed=seed)
        out = [env.state()]
        for _ in range(6):
            env.step(random_actions(env, rng))
            out.append(env.state())
        return out

    first, again, other = states(11), states(11), states(12)
    for a, b in zip(first, again):
        np.testing.assert_array_equal(a, b)
    assert any(not np.array_equal(a, b) for a, b in zip(first, other))


@pytest.mark.parametrize("env_id", ENV_IDS)
def test_pettingzoo_state_test(env_id):
    module = importlib.import_module(f"hivex_dsl.zoo.{env_id}_v0")
    state_test(module.env(max_cycles=CYCLES), module.parallel_env(max_cycles=CYCLES), num_cycles=CYCLES + 5)


def world_values_within_bounds(venv) -> None:
    """The simulator's raw world facts (float64, before the float32 cast) lie within their components' bounds."""
    gs = venv.global_state
    _, world = venv.core.sim.world_state(venv.core.state)
    start = gs.slices[AGENT_OBSERVATIONS].stop
    low, high = gs.space.low[start:-1], gs.space.high[start:-1]
    assert np.isfinite(world).all()
    assert np.all(world >= low) and np.all(world <= high), (world, low, high)


@pytest.mark.parametrize("env_id", ENV_IDS)
@settings(max_examples=6, deadline=None)
@given(seed=st.integers(0, 2**16), steps=st.integers(1, 40), mode=st.sampled_from(["next_step", "same_step"]))
def test_random_rollouts_stay_in_the_state_space_and_match_the_returned_observations(env_id, seed, steps, mode):
    """Over random play with restarts (episodes of 12 decisions), every world's state lies in the state space,
    the raw world facts within their bounds, and the agents' part equals the observations just returned (NEXT_STEP:
    an ended slot's last one; SAME_STEP: the new first one)."""
    venv = hivex_dsl.vector_env(scenario(env_id, episode_length=12), num_worlds=2, autoreset_mode=mode)
    venv.action_space.seed(seed)
    obs, _ = venv.reset(seed=seed)
    for _ in range(steps + 1):
        states = venv.state()
        assert states.shape == (2,) + venv.single_state_space.shape and states.dtype == np.float32
        assert venv.state_space.contains(states)
        world_values_within_bounds(venv)
        np.testing.assert_array_equal(agent_part(venv, states).reshape(venv.num_envs, -1), vectors_of(obs))
        np.testing.assert_array_equal(venv.state(per_slot=True), np.repeat(states, venv.agents_per_world, axis=0))
        obs, *_ = venv.step(venv.action_space.sample())


@pytest.mark.parametrize("env_id", ["ocean_plastic_collection", "wind_farm_control"])
@pytest.mark.parametrize("respawn", [False, True])
def test_an_ended_agent_shows_its_last_observation_then_zeros_or_its_respawn(restepped, env_id, respawn):
    """On the step an agent ends, its slot holds the observation that step returned; afterwards zeros in every
    per-agent component (PettingZoo: it left ``agents``), or its new first observation when it respawns."""
    compiled = restepped(hivex_dsl.compile(scenario(env_id)), first_agent_crashes_on(2))
    env = hivex_dsl.parallel_env(compiled, respawn=respawn)
    gs, rng = env.global_state, np.random.default_rng(3)
    first = env.possible_agents[0]
    env.reset(seed=0)
    env.step(random_actions(env, rng))
    obs, _, terminations, *_ = env.step(random_actions(env, rng))  # agent 0 ends here
    assert terminations[first]
    np.testing.assert_array_equal(agent_part(env, env.state())[0], vectors_of(obs[first]))
    obs, *_ = env.step(random_actions(env, rng))
    state = env.state()
    assert (first in env.agents) == respawn
    if respawn:
        np.testing.assert_array_equal(agent_part(env, state)[0], vectors_of(obs[first]))
    else:
        per_agent = [c for c in gs.components if c.per_agent]
        for c in per_agent:
            values = state[gs.slices[c.name]].reshape(gs.agents, c.size)
            assert not values[0].any(), c.name
        assert agent_part(env, state)[1:].any()  # the others play on
    for i, agent in enumerate(env.possible_agents[1:], start=1):
        np.testing.assert_array_equal(agent_part(env, state)[i], vectors_of(obs[agent]))
    assert env.state_space.contains(state)


def test_the_state_is_taken_at_the_decision():
    """With a decision period of 3, one step is 3 physics steps: the progress counts them and the agents' part is
    the observation the decision returned."""
    env = hivex_dsl.parallel_env(scenario("drone_based_reforestation", decision_period=3, episode_length=30))
    rng = np.random.default_rng(5)
    env.reset(seed=0)
    for decision in range(1, 4):
        obs, *_ = env.step(random_actions(env, rng))
        state = env.state()
        assert state[-1] == np.float32(3 * decision / 30)
        for i, agent in enumerate(env.possible_agents):
            np.testing.assert_array_equal(agent_part(env, state)[i], obs[agent]["vector"])


def test_torchrl_reads_the_state_through_the_flat_and_joint_views():
    """TorchRL's PettingZooWrapper(return_state=True) finds ``state_space`` and ``state()`` through the views that
    :func:`hivex_dsl.adapters.torchrl.marl_view` puts over the parallel env."""
    pytest.importorskip("torchrl")
    from torchrl.envs.libs.pettingzoo import PettingZooWrapper
    from torchrl.envs.utils import MarlGroupMapType

    from hivex_dsl.adapters.torchrl import marl_view

    env = hivex_dsl.parallel_env(scenario("ocean_plastic_collection"))
    wrapped = PettingZooWrapper(marl_view(env), group_map=MarlGroupMapType.ALL_IN_ONE_GROUP, use_mask=True,
                                done_on_any=False, categorical_actions=True, seed=0, return_state=True)
    rollout = wrapped.rollout(3)
    assert rollout["state"].shape == (3,) + env.state_space.shape
    np.testing.assert_array_equal(rollout["next", "state"][-1].numpy(), env.state())


# ---- Gymnasium wrappers on Dict observations (issue 36, item 5) -----------------------------------------------

def test_normalize_observation_on_dict_observations_names_the_flat_view():
    """NormalizeObservation builds on a Dict space without complaint; the first reset now raises an error that
    names the flat view (it raised NumPy's AxisError), and over the flat view it works."""
    import gymnasium
    from gymnasium.wrappers.vector import NormalizeObservation

    from hivex_dsl.adapters.flat import flat_vector_env
    from hivex_dsl.adapters.gymnasium import DictObservationError

    wrapped = NormalizeObservation(gymnasium.make_vec("hivex/OceanPlasticCollection-v0", num_envs=2))
    with pytest.raises(DictObservationError, match=r"hivex_dsl\.adapters\.flat\.flat_vector_env") as caught:
        wrapped.reset(seed=0)
    assert isinstance(caught.value, TypeError) and isinstance(caught.value, hivex_dsl.HivexError)

    flat = NormalizeObservation(flat_vector_env(gymnasium.make_vec("hivex/OceanPlasticCollection-v0", num_envs=2)))
    obs, _ = flat.reset(seed=0)
    obs, *_ = flat.step(flat.action_space.sample())
    assert obs.shape == flat.observation_space.shape and np.isfinite(obs).all()

    box = NormalizeObservation(gymnasium.make_vec("hivex/WindFarmControl-v0", num_envs=2))  # a Box: as before
    box.reset(seed=0)
    obs, *_ = box.step(box.action_space.sample())
    assert obs.shape == box.observation_space.shape


def test_dict_observations_stay_a_plain_dict_to_every_other_reader():
    venv = hivex_dsl.vector_env(scenario("ocean_plastic_collection"), num_worlds=2)
    obs, _ = venv.reset(seed=0)
    assert isinstance(obs, dict) and list(obs) == ["vector", "visual"] and venv.observation_space.contains(obs)
    again = pickle.loads(pickle.dumps(obs))
    assert type(again) is type(obs) and all(np.array_equal(again[k], obs[k]) for k in obs)
    with pytest.raises(TypeError, match="flat_vector_env"):
        np.asarray(obs)
