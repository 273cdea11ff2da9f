"""hivex_dsl.testing: its strategies draw what they promise, and the README shows the example that runs."""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np
import pytest
from gymnasium import spaces
from hypothesis import given, settings, strategies as st

import hivex_dsl
from hivex_dsl.compiler.registry import environments
from hivex_dsl.testing import actions, compiled_scenarios, scenarios, term_inputs

ROOT = Path(__file__).resolve().parents[1]


@pytest.mark.parametrize("env_id", list(environments()))
@settings(max_examples=15, deadline=None)
@given(data=st.data())
def test_drawn_scenarios_compile_within_the_environment_bounds(env_id, data):
    drawn = data.draw(scenarios(env_id, weights=True))
    compiled = hivex_dsl.compile(drawn)
    info = environments()[env_id].info
    assert info.min_agents <= compiled.agents <= info.max_agents
    assert compiled.seeds.train != compiled.seeds.test
    for term, weight in drawn.get("weights", {}).items():
        assert compiled.weights[term] == weight


SPACES = [spaces.Discrete(3), spaces.Discrete(4, start=-1), spaces.MultiDiscrete([2, 3]),
          spaces.Box(-1.0, 1.0, (3,), np.float32), spaces.Box(np.array([0.0, -2.0]), np.array([1.0, 2.0]), dtype=np.float64),
          spaces.Dict({"continuous": spaces.Box(-1.0, 1.0, (1,), np.float32), "discrete": spaces.MultiDiscrete([2])})]


@pytest.mark.parametrize("space", SPACES, ids=str)
@settings(max_examples=25, deadline=None)
@given(data=st.data())
def test_actions_lie_in_the_space_for_every_agent(space, data):
    drawn = data.draw(actions(space, (2, 3)))
    parts = drawn.items() if isinstance(space, spaces.Dict) else [(None, drawn)]
    for key, part in parts:
        sub = space[key] if key else space
        assert part.shape == (2, 3) + sub.shape
        assert all(sub.contains(np.asarray(a, sub.dtype)) for a in part.reshape((6,) + sub.shape))


@settings(max_examples=5, deadline=None)
@given(inputs=term_inputs("wind_farm_control", steps=st.integers(0, 5), batch=2))
def test_term_inputs_are_one_step_of_the_drawn_scenario(inputs):
    compiled = inputs.compiled
    assert inputs.actions.shape == (2, compiled.agents) and inputs.params is compiled.params
    sim = compiled.entry.make_simulator(compiled)
    # the simulator turns each turbine by the drawn action: headings differ exactly where the action rotates
    turned = ~np.isclose(np.angle(np.exp(1j * (inputs.state.heading - inputs.prev.heading))), 0.0)
    np.testing.assert_array_equal(turned, inputs.actions != 0)
    assert sim.observation_space.contains(sim.observe(inputs.state)[0, 0])


@settings(max_examples=3, deadline=None)
@given(compiled=compiled_scenarios("ocean_plastic_collection", tasks=["group_up"]))
def test_compiled_scenarios_respect_the_task_choice(compiled):
    assert compiled.task_name == "group_up"


def test_the_readme_shows_the_example_test_verbatim():
    example = (ROOT / "tests" / "test_testing_example.py").read_text()
    body = re.search(r"# --- example start ---\n(.*?)# --- example end ---", example, flags=re.S).group(1)
    readme = (ROOT / "README.md").read_text()
    assert f"```py\n{body}```" in readme
