"""Per-agent action stacking and batched action checks: the right arrays, and errors that name the agent."""

from __future__ import annotations

import numpy as np
import pytest
from gymnasium import spaces

from hivex_dsl.errors import ActionError
from hivex_dsl.spaces import check_actions, stack_agent_actions

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
