"""Bad actions on every environment and adapter (issue 34, item 5).

The fuzzer draws actions with a seeded NumPy Generator, each valid or invalid by construction: NaN, inf,
out of range, fractions for discrete spaces, wrong dtypes and shapes, booleans (alone, in arrays,
hidden in Python lists), strings, None, dicts where arrays belong and arrays where dicts belong,
ragged and nested garbage, objects whose conversion raises, missing and extra agents, slot counts, and
torch tensors with and without grad or on another device. A valid action must be accepted; an invalid
one must raise ActionError naming the space (and the agent, or the slot's agent and world, at fault),
never another exception and never a silent acceptance.

``HIVEX_FUZZ_LONG=1`` raises the count from 25 to 1,000 cases per environment and adapter: from 1,000 to
40,000 in all, half of them with torch tensors among the forms (about a minute).
"""

from __future__ import annotations

import os
from typing import Any, Callable, Optional

import numpy as np
import pytest
from gymnasium import spaces

import hivex_dsl
from hivex_dsl import ActionError
from hivex_dsl.compiler import registry
from hivex_dsl.adapters.flat import FlatParallelEnv, flat_vector_env
from hivex_dsl.sim.spaces import describe_space

from .action_fuzz_cases import Case, bad_leaf, parallel_case, vector_case

ENVIRONMENTS = list(registry.environments())
ADAPTERS = ["parallel", "vector", "flat_parallel", "flat_vector"]
CASES = 1000 if os.environ.get("HIVEX_FUZZ_LONG") else 25
WORLDS = 2


def scenario(environment: str) -> hivex_dsl.CompiledScenario:
    return hivex_dsl.compile({"hivex": 1, "environment": environment, "episode_length": 20})


def make(environment: str, adapter: str, worlds: int = WORLDS):
    """(env, per-agent action space) of one adapter, reset."""
    compiled = scenario(environment)
    if adapter.endswith("parallel"):
        env = hivex_dsl.parallel_env(compiled)
        env = FlatParallelEnv(env) if adapter == "flat_parallel" else env
        env.reset(seed=0)
        return env, env.action_space(env.possible_agents[0])
    env = hivex_dsl.vector_env(compiled, num_worlds=worlds)
    env = flat_vector_env(env) if adapter == "flat_vector" else env
    env.reset(seed=0)
    return env, env.single_action_space


def draw_case(env, adapter: str, space: spaces.Space, rng: np.random.Generator, torch: Any) -> Case:
    if adapter.endswith("parallel"):
        return parallel_case(space, list(env.agents), rng, torch)
    core = env.unwrapped
    return vector_case(space, core.core.shape, list(core.compiled.agent_names), rng, torch)


def play(env, adapter: str, space: spaces.Space, case: Case) -> None:
    """Step with the case's actions: accepted if valid, an ActionError naming the culprit if not."""
    if not case.valid:
        with pytest.raises(ActionError) as caught:
            env.step(case.actions)
        message = str(caught.value)
        assert describe_space(space) in message or not case.names_space, (case.label, message)
        assert case.culprit is None or f"action for {case.culprit} " in message, (case.label, message)
        return
    env.step(case.actions)
    if adapter.endswith("parallel") and not env.agents:
        env.reset()


def fuzz(environment: str, adapter: str, seed: int, torch: Any = None) -> None:
    rng = np.random.default_rng(seed)
    env, space = make(environment, adapter)
    for _ in range(CASES):
        case = draw_case(env, adapter, space, rng, torch)
        try:
            play(env, adapter, space, case)
        except Exception as exc:
            raise AssertionError(f"{environment}/{adapter}: {case.label} ({case.valid=}): {exc!r}") from exc


@pytest.mark.parametrize("adapter", ADAPTERS)
@pytest.mark.parametrize("environment", ENVIRONMENTS)
def test_fuzzed_actions_are_accepted_when_valid_and_refused_with_an_action_error_when_not(environment, adapter):
    fuzz(environment, adapter, seed=ENVIRONMENTS.index(environment) * 10 + ADAPTERS.index(adapter))


@pytest.mark.parametrize("adapter", ADAPTERS)
@pytest.mark.parametrize("environment", ENVIRONMENTS)
def test_fuzzed_actions_with_torch_tensors(environment, adapter):
    torch = pytest.importorskip("torch")
    fuzz(environment, adapter, seed=1000 + ENVIRONMENTS.index(environment) * 10 + ADAPTERS.index(adapter), torch=torch)


# --- the reproducers, on every environment and both adapters -------------------------------------

def one_agent_action(space: spaces.Space, make_leaf: Callable[[spaces.Space], Any]) -> Any:
    """A valid action with ``make_leaf(space)`` as its value (its continuous part's, for a Dict space)."""
    if isinstance(space, spaces.Dict):
        return {"continuous": make_leaf(space["continuous"]), "discrete": np.zeros(space["discrete"].shape, np.int64)}
    return make_leaf(space)


def slot_actions(space: spaces.Space, slots: int, make_batch: Callable[[spaces.Space, int], Any]) -> Any:
    if isinstance(space, spaces.Dict):
        return {"continuous": make_batch(space["continuous"], slots),
                "discrete": np.zeros((slots,) + space["discrete"].shape, np.int64)}
    return make_batch(space, slots)


def refused(env, actions: Any) -> str:
    with pytest.raises(ActionError) as caught:
        env.step(actions)
    return str(caught.value)


@pytest.mark.parametrize("environment", ENVIRONMENTS)
def test_a_tensor_that_requires_grad_is_refused_by_the_parallel_env_with_a_hint_to_detach(environment):
    torch = pytest.importorskip("torch")
    env, space = make(environment, "parallel")
    actions = {a: one_agent_action(space, lambda s: np.zeros(s.shape, s.dtype)) for a in env.agents}
    first = env.agents[0]
    actions[first] = one_agent_action(space, lambda s: torch.zeros(s.shape, requires_grad=True))
    message = refused(env, actions)
    assert message.startswith(f"action for {first} is a tensor that requires grad; call .detach() on it first")
    assert describe_space(space) in message
    actions[first] = one_agent_action(space, lambda s: torch.zeros(s.shape).detach())  # detached: accepted
    env.step(actions)


@pytest.mark.parametrize("environment", ENVIRONMENTS)
def test_a_tensor_that_requires_grad_is_refused_by_the_vector_env_with_a_hint_to_detach(environment):
    torch = pytest.importorskip("torch")
    env, space = make(environment, "vector")
    grad = slot_actions(space, env.num_envs, lambda s, n: torch.zeros((n,) + s.shape, requires_grad=True))
    message = refused(env, grad)
    assert "actions are a tensor that requires grad; call .detach() on it first" in message
    assert describe_space(space) in message and f"{env.num_envs} slots" in message
    env.step(slot_actions(space, env.num_envs, lambda s, n: torch.zeros((n,) + s.shape)))  # no grad: accepted


@pytest.mark.parametrize("adapter", ["parallel", "vector"])
@pytest.mark.parametrize("environment", ENVIRONMENTS)
def test_a_tensor_on_another_device_is_an_action_error_saying_to_copy_it(environment, adapter):
    torch = pytest.importorskip("torch")
    env, space = make(environment, adapter)
    if adapter == "parallel":
        actions = {a: one_agent_action(space, lambda s: torch.zeros(s.shape, device="meta")) for a in env.agents}
    else:
        actions = slot_actions(space, env.num_envs, lambda s, n: torch.zeros((n,) + s.shape, device="meta"))
    message = refused(env, actions)
    assert "not readable as an array (TypeError: can't convert meta device type tensor" in message
    assert "Tensor.cpu()" in message and describe_space(space) in message


def test_a_boolean_in_a_python_list_is_refused_by_the_vector_env_as_by_the_parallel_env():
    vector, _ = make("wind_farm_control", "vector", worlds=1)
    parallel, _ = make("wind_farm_control", "parallel")
    assert vector.num_envs == 8
    from_vector = refused(vector, [True] + [0] * 7)
    from_parallel = refused(parallel, dict(zip(parallel.agents, [True] + [0] * 7)))
    assert from_vector == from_parallel == ("action for turbine_0 is True (a boolean); expected an action of "
                                            "Discrete(3) (a boolean is not read as 0 or 1)")


@pytest.mark.parametrize("environment", ENVIRONMENTS)
def test_a_boolean_hidden_in_an_agents_list_is_refused_by_both_adapters(environment):
    """[True, 0, ...] for a MultiDiscrete or Box agent: NumPy would read it as [1, 0, ...]."""
    parallel, space = make(environment, "parallel")
    vector, _ = make(environment, "vector", worlds=1)

    def hidden(s: spaces.Space) -> Any:
        return True if s.shape == () else [True] + [0] * (int(np.prod(s.shape)) - 1)

    actions = [one_agent_action(space, hidden)] + [one_agent_action(space, lambda s: np.zeros(s.shape, s.dtype))
                                                    for _ in parallel.agents[1:]]
    from_parallel = refused(parallel, dict(zip(parallel.agents, actions)))
    batched = actions if not isinstance(space, spaces.Dict) else {
        key: [action[key] for action in actions] for key in space.spaces}
    from_vector = refused(vector, batched)
    first = parallel.agents[0]
    assert from_parallel == from_vector and from_parallel.startswith(f"action for {first} is ")
    assert "(a boolean is not read as 0 or 1)" in from_parallel and describe_space(space) in from_parallel


def test_a_string_among_numbers_is_blamed_on_its_own_slot():
    vector, _ = make("wind_farm_control", "vector")
    message = refused(vector, [0] * 11 + ["1"] + [0] * 4)
    assert message.startswith("action for turbine_3 in env 1 is '1' (a string); expected an action of Discrete(3)")


@pytest.mark.parametrize("bad", [np.zeros(8, np.int64), [0] * 8, None, "0"])
def test_actions_that_are_not_a_dict_are_refused_by_the_parallel_env_and_its_flat_view(bad):
    for adapter in ("parallel", "flat_parallel"):
        env, _ = make("drone_based_reforestation" if adapter == "flat_parallel" else "wind_farm_control", adapter)
        assert refused(env, bad) == f"actions must be a dict {{agent: action}}, got {type(bad).__name__}"


def test_a_fraction_is_refused_after_an_agent_left(restepped):
    """The placeholders of agents that left are of the space's dtype: a live agent's 1.5 was cast to 1."""
    def end_turbine_1(sim, state, actions, rng):
        new, outcome = sim.step(state, actions, rng)
        ended = np.zeros_like(np.asarray(outcome.terminated), bool)
        ended[..., 1] = True
        return new, outcome._replace(terminated=ended)

    compiled = hivex_dsl.compile({"hivex": 1, "environment": "wind_farm_control", "agents": 3, "episode_length": 10})
    env = hivex_dsl.parallel_env(restepped(compiled, end_turbine_1))
    env.reset(seed=0)
    env.step({a: 0 for a in env.agents})
    assert env.agents == ["turbine_0", "turbine_2"]
    for bad in (1.5, float("nan"), -0.5):
        message = refused(env, {"turbine_0": bad, "turbine_2": 0.0})  # both floats: NumPy reads them as one array
        assert message.startswith(f"action for turbine_0 is {bad}, not in Discrete(3)")


@pytest.mark.parametrize("adapter", ["flat_parallel", "flat_vector"])
@pytest.mark.parametrize("value", [1.5, -2.0, np.inf, np.nan])
def test_the_flat_views_refuse_values_outside_their_box(adapter, value):
    """They clipped 1.5 to 1 and read NaN as a discrete choice; their Box(-1, 1) refuses both."""
    env, space = make("aerial_wildfire_suppression", adapter)
    action = np.array([0.0, value], np.float32)
    actions = {a: action for a in env.agents} if adapter == "flat_parallel" else np.tile(action, (env.num_envs, 1))
    message = refused(env, actions)
    assert "not in Box(-1.0, 1.0, (2,), float32) (value 0: the continuous part; value 1: the discrete part " in message


def test_a_jax_array_is_read_as_numpy_reads_it():
    jnp = pytest.importorskip("jax.numpy")
    env, space = make("ocean_plastic_collection", "vector")
    env.step(jnp.zeros((env.num_envs,) + space.shape, jnp.int32))
    with pytest.raises(ActionError, match=r"action for vessel_0 in env 0 is \[False, False\] \(booleans\)"):
        env.step(jnp.zeros((env.num_envs,) + space.shape, bool))


def test_every_bad_leaf_kind_is_drawn():
    """The fuzzer's bad values cover each kind the issue lists, for every kind of space."""
    rng = np.random.default_rng(0)
    expected = {"nan", "inf", "out of range", "python bool", "bool array", "string", "None", "dict", "wrong shape",
                "ragged", "failing __array__", "complex", "big int", "object array", "datetime"}
    for space, more in [(spaces.Discrete(3), {"fraction"}), (spaces.MultiDiscrete([2, 3]), {"fraction", "hidden bool"}),
                        (spaces.Box(-1.0, 1.0, (2,), np.float32), {"hidden bool"})]:
        labels = {bad_leaf(space, rng, None)[0] for _ in range(1000)}
        assert expected | more <= labels, (space, expected | more - labels)


def test_every_bad_tensor_kind_is_drawn():
    torch = pytest.importorskip("torch")
    rng = np.random.default_rng(0)
    labels = {bad_leaf(spaces.MultiDiscrete([2, 3]), rng, torch)[0] for _ in range(1000)}
    assert {"grad tensor", "meta tensor", "bool tensor", "nan tensor"} <= labels
