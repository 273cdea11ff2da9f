"""Per-agent action stacking and batched action checks: the right arrays, and errors that name the agent."""

from __future__ import annotations

import numpy as np
import pytest
from gymnasium import spaces
from hypothesis import given, settings
from hypothesis import strategies as st

from hivex_dsl.base.errors import ActionError
from hivex_dsl.sim.spaces import check_actions, describe_space, stack_agent_actions

AGENTS = ["a", "b", "c"]
PLANE = spaces.Dict({"continuous": spaces.Box(-1.0, 1.0, (1,), np.float32), "discrete": spaces.MultiDiscrete([2])})


def test_dict_actions_stack_per_part_in_agent_order():
    actions = {a: {"continuous": np.array([0.1 * i], np.float32), "discrete": np.array([i % 2])}
               for i, a in enumerate(AGENTS)}
    stacked = stack_agent_actions(PLANE, actions, AGENTS)
    np.testing.assert_array_equal(stacked["continuous"], np.array([[[0.0], [0.1], [0.2]]], np.float32))
    np.testing.assert_array_equal(stacked["discrete"], [[[0], [1], [0]]])
    checked = check_actions(PLANE, stacked, AGENTS)
    assert checked["continuous"].dtype == np.float32 and checked["discrete"].dtype == PLANE["discrete"].dtype


@pytest.mark.parametrize("bad", [np.array([0.0, 1.0]), [0.0, 1], "left", {"continuous": np.array([0.0])}])
def test_a_dict_space_action_that_is_not_the_dict_names_the_agent(bad):
    actions = {"a": {"continuous": np.array([0.0]), "discrete": np.array([1])}, "b": bad,
               "c": {"continuous": np.array([0.0]), "discrete": np.array([0])}}
    with pytest.raises(ActionError, match=r"action for b must be a dict with keys \['continuous', 'discrete'\]"):
        stack_agent_actions(PLANE, actions, AGENTS)


@pytest.mark.parametrize("space, values, culprit", [
    (spaces.Discrete(3), [0, 2, 3], "c"),
    (spaces.Discrete(3), [-1, 0, 0], "a"),
    (spaces.Discrete(3), [0.0, 1.5, 2.0], "b"),
    (spaces.MultiDiscrete([4, 4]), [[0, 3], [4, 0], [0, 0]], "b"),
    (spaces.Box(-1.0, 1.0, (2,), np.float32), [[0.0, 0.0], [0.0, 0.0], [np.nan, 0.0]], "c"),
    (spaces.Box(-1.0, 1.0, (2,), np.float32), [[0.0, 1.5], [0.0, 0.0], [0.0, 0.0]], "a"),
    (spaces.Box(-np.inf, np.inf, (1,), np.float64), [[0.0], [np.inf], [0.0]], "b"),
])
def test_the_first_agent_outside_the_space_is_named(space, values, culprit):
    batched = np.asarray(values)[None]
    with pytest.raises(ActionError, match=rf"action for {culprit} is .*, not in "):
        check_actions(space, batched, AGENTS)


def test_valid_actions_pass_with_the_space_dtype():
    checked = check_actions(spaces.Discrete(3), np.array([[0.0, 1.0, 2.0]]), AGENTS)
    assert checked.dtype == np.int64 and checked.tolist() == [[0, 1, 2]]


def test_missing_and_extra_agents_are_named():
    with pytest.raises(ActionError, match="no action for b"):
        stack_agent_actions(spaces.Discrete(3), {"a": 0, "c": 1}, AGENTS)
    with pytest.raises(ActionError, match="action for 'd', which is not a live agent"):
        stack_agent_actions(spaces.Discrete(3), {"a": 0, "b": 0, "c": 1, "d": 2}, AGENTS)


# --- bad values are blamed on their own agent, named with the space -------------------------------------

DISCRETE = spaces.Discrete(3)


@pytest.mark.parametrize("value, message", [
    (None, "action for c is None; expected an action of Discrete(3)"),
    ("1", "action for c is '1' (a string); expected an action of Discrete(3)"),
    (np.str_("1"), "action for c is '1' (a string); expected an action of Discrete(3)"),
    (True, "action for c is True (a boolean); expected an action of Discrete(3) (a boolean is not read as 0 or 1)"),
    (np.bool_(False), "action for c is False (a boolean); expected an action of Discrete(3) "
                      "(a boolean is not read as 0 or 1)"),
    ([1], "action for c has shape (1,), but Discrete(3) takes shape ()"),
    (np.array([1, 2]), "action for c has shape (2,), but Discrete(3) takes shape ()"),
    (1.5, "action for c is 1.5, not in Discrete(3)"),
    (2 ** 70, f"action for c is {2 ** 70}, not in Discrete(3)"),
    (object, "action for c is <class 'object'> (holding object values); expected an action of Discrete(3)"),
])
def test_a_bad_discrete_action_names_its_own_agent(value, message):
    with pytest.raises(ActionError) as caught:
        stack_agent_actions(DISCRETE, {"a": 0, "b": 1, "c": value}, AGENTS)
    assert str(caught.value) == message


@pytest.mark.parametrize("value", [1.0, np.float32(2.0), np.int8(1), np.uint64(0)])
def test_integral_floats_and_every_integer_type_are_discrete_actions(value):
    stacked = stack_agent_actions(DISCRETE, {"a": 0, "b": 1, "c": value}, AGENTS)
    assert check_actions(DISCRETE, stacked, AGENTS).tolist() == [[0, 1, int(value)]]


def test_a_ragged_box_action_and_booleans_for_a_box_name_the_agent():
    box = spaces.Box(-1.0, 1.0, (2,), np.float32)
    good = np.zeros(2, np.float32)
    with pytest.raises(ActionError, match=r"^action for b has shape \(3,\), but Box\(-1.0, 1.0, \(2,\), float32\) "
                                          r"takes shape \(2,\)$"):
        stack_agent_actions(box, {"a": good, "b": [0.0, 0.0, 0.0], "c": good}, AGENTS)
    with pytest.raises(ActionError, match=r"^action for b is ragged \(\[\[0.0\], 0.0\]\)"):
        stack_agent_actions(box, {"a": good, "b": [[0.0], 0.0], "c": good}, AGENTS)
    with pytest.raises(ActionError, match=r"^action for a is \[True, False\] \(booleans\)"):
        stack_agent_actions(box, {"a": [True, False], "b": good, "c": good}, AGENTS)


def test_an_extra_key_in_a_dict_action_is_refused():
    good = {"continuous": np.array([0.0]), "discrete": np.array([1])}
    with pytest.raises(ActionError, match=r"^action for b has key 'speed', which Dict\(.*\) does not have; "
                                          r"expected exactly the keys \['continuous', 'discrete'\]"):
        stack_agent_actions(PLANE, {"a": good, "b": {**good, "speed": 1.0}, "c": good}, AGENTS)
    with pytest.raises(ActionError, match=r"exactly the keys \['continuous', 'discrete'\] .*, got "
                                          r"\['continuous', 'discrete', 'speed'\]"):
        check_actions(PLANE, {"continuous": np.zeros((1, 3, 1)), "discrete": np.zeros((1, 3, 1), int),
                              "speed": np.zeros((1, 3))}, AGENTS)


@pytest.mark.parametrize("batched, message", [
    (np.array([[0, 1, None]], dtype=object), "action for c is None; expected an action of Discrete(3)"),
    (np.array([[0, 1], [2, "x"]], dtype=object)[:, :, None].reshape(2, 2),
     None),  # shape (2, 2): wrong agent count, reported as a shape
    (np.array([[True, False, True]]), "action for a is True (a boolean)"),
    (np.array([["0", "1", "2"]]), "action for a is '0' (a string)"),
])
def test_batched_actions_that_are_not_numbers_name_the_first_agent(batched, message):
    with pytest.raises(ActionError) as caught:
        check_actions(DISCRETE, batched, AGENTS)
    if message:
        assert str(caught.value).startswith(message)
    else:
        assert str(caught.value).startswith("actions have shape (2, 2); expected (batch, 3)")


def test_batched_values_are_named_with_their_env():
    batched = np.array([[0, 1, 2], [0, None, 2]], dtype=object)
    with pytest.raises(ActionError, match=r"^action for b in env 1 is None"):
        check_actions(DISCRETE, batched, AGENTS)


ANY_VALUE = st.recursive(
    st.one_of(st.none(), st.booleans(), st.integers(), st.floats(), st.text(max_size=3), st.binary(max_size=2),
              st.sampled_from([np.bool_(True), np.float32(1.0), np.int8(2), np.str_("1"), object()])),
    lambda inner: st.one_of(st.lists(inner, max_size=3), st.dictionaries(st.sampled_from(["continuous", "discrete", "x"]),
                                                                          inner, max_size=3),
                            st.lists(st.floats(-2, 2), min_size=1, max_size=2).map(np.array)),
    max_leaves=6)


@settings(max_examples=int(__import__("os").environ.get("FUZZ_N", 150)), deadline=None)
@given(st.sampled_from([DISCRETE, spaces.MultiDiscrete([2, 3]), spaces.Box(-1.0, 1.0, (1,), np.float32), PLANE]),
       ANY_VALUE)
def test_any_value_for_one_agent_is_accepted_or_an_action_error_naming_that_agent(space, value):
    others = {a: space.sample() for a in ("a", "b")}
    try:
        stacked = stack_agent_actions(space, {**others, "c": value}, AGENTS)
        check_actions(space, stacked, AGENTS)
    except ActionError as exc:
        assert str(exc).startswith("action for c ") and describe_space(space) in str(exc), str(exc)


def test_valid_actions_never_look_for_a_culprit(monkeypatch):
    import hivex_dsl
    from hivex_dsl.sim import spaces as module

    monkeypatch.setattr(module, "culprit", lambda *args: pytest.fail("searched for a culprit on a valid step"))
    env = hivex_dsl.parallel_env({"hivex": 1, "environment": "wind_farm_control", "agents": 3})
    env.reset(seed=1)
    env.step({a: i % 3 for i, a in enumerate(env.agents)})
    venv = hivex_dsl.vector_env({"hivex": 1, "environment": "wind_farm_control", "agents": 3}, num_worlds=2)
    venv.reset(seed=1)
    venv.step(np.array([0, 1, 2, 2, 1, 0]))
