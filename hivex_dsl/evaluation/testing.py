"""Hypothesis strategies for property-testing reward terms (public API; needs ``hypothesis``).

A researcher who writes a task (a reward table column, a term, a weight override) tests it in their
own pytest with these strategies::

    from hypothesis import given, settings
    from hivex_dsl.testing import term_inputs

    @settings(max_examples=20, deadline=None)
    @given(term_inputs("ocean_plastic_collection"))
    def test_collecting_pays_what_was_collected(inputs):
        term = inputs.compiled.entry.terms["collect_trash"]
        assert (term(*inputs.args) == inputs.state.collected).all()

- :func:`scenarios` draws valid scenario dicts of an environment (task, level, agents, episode
  length, seeds and optionally weight overrides); every dict drawn compiles;
- :func:`compiled_scenarios` draws them compiled;
- :func:`actions` draws batched actions ``(batch, agents, ...)`` of an action space;
- :func:`term_inputs` draws a :class:`TermInputs`: a state reached by a rollout of random actions from
  a drawn scenario and seed, and one more step taken with drawn actions, i.e. exactly what a reward
  term receives (``prev, state, actions, params``).
"""

from __future__ import annotations

from typing import Any, NamedTuple, Optional

import numpy as np

try:
    from hypothesis import strategies as st
    from hypothesis.extra import numpy as hnp
except ImportError as exc:  # pragma: no cover - depends on the installation
    raise ImportError("hivex_dsl.testing needs hypothesis: pip install 'hivex-dsl[testing]'") from exc
from gymnasium import spaces

from ..base.errors import ScenarioError
from ..compiler import registry
from ..compiler import CompiledScenario, compile as compile_scenario
from ..runtime.batched import BatchedEnv
from ..sim.spaces import check_actions
from .policies import random_policy

MAX_SEED = 2**32 - 1
SMALL_AGENTS = 4  # default upper bound of drawn agent counts: rollouts stay cheap


def _compiles(data: dict[str, Any]) -> bool:
    try:
        compile_scenario(data)
    except ScenarioError:
        return False
    return True


@st.composite
def scenarios(draw, environment: str, agents: Optional[st.SearchStrategy[int]] = None,
              episode_length: st.SearchStrategy[int] = st.integers(1, 200), tasks: Optional[list[str]] = None,
              weights: bool = False) -> dict[str, Any]:
    """Valid scenario dicts of ``environment``: task (name or index), level, agents, episode length (the drawn
    length rounded up to whole decisions of the environment's default decision period), seeds.

    ``agents`` defaults to the environment's minimum up to 4 agents; ``tasks`` (names) limits the tasks;
    ``weights=True`` also overrides up to two terms' weights with values in [-10, 10].
    """
    entry = registry.get(environment)
    info, table = entry.info, entry.reward_table
    names = tasks or list(table.task_names)
    task = draw(st.sampled_from(names))
    data: dict[str, Any] = {"hivex": 1, "environment": environment,
                            "task": draw(st.sampled_from([task, table.task_names.index(task)]))}
    if info.level_field == "pattern":
        level = draw(st.integers(0, info.level_count - 1))
        data["pattern"] = draw(st.sampled_from([level, entry.level_names[level]]))
    elif info.level_field == "terrain_level":
        data["terrain_level"] = draw(st.integers(1, info.level_count))
    data["agents"] = draw(agents or st.integers(info.min_agents, max(info.min_agents, min(info.max_agents, SMALL_AGENTS))))
    period = info.default_decision_period  # an episode ends on a decision: whole decisions of the default period
    data["episode_length"] = -(-draw(episode_length) // period) * period
    train = draw(st.integers(0, MAX_SEED))
    data["seeds"] = {"train": train, "test": draw(st.integers(0, MAX_SEED).filter(lambda s: s != train))}
    if weights:
        chosen = draw(st.lists(st.sampled_from(entry.terms.names), unique=True, max_size=2))
        data["weights"] = {t: draw(st.floats(-10.0, 10.0, allow_nan=False)) for t in chosen}
    if not _compiles(data):  # an environment check refused the combination (e.g. a layout that cannot fit)
        from hypothesis import reject

        reject()
    return data


def compiled_scenarios(environment: str, **kwargs: Any) -> st.SearchStrategy[CompiledScenario]:
    """:func:`scenarios` compiled; the keyword arguments are :func:`scenarios`'."""
    return scenarios(environment, **kwargs).map(compile_scenario)


def actions(space: spaces.Space, shape: tuple[int, ...]) -> st.SearchStrategy[Any]:
    """Batched actions ``shape + space.shape`` valid for a Discrete, MultiDiscrete, Box or Dict space."""
    if isinstance(space, spaces.Dict):
        return st.fixed_dictionaries({key: actions(sub, shape) for key, sub in space.spaces.items()})
    if isinstance(space, spaces.Discrete):
        start = int(space.start)
        return hnp.arrays(np.int64, shape, elements=st.integers(start, start + int(space.n) - 1))
    if isinstance(space, spaces.MultiDiscrete):
        nvec = np.broadcast_to(space.nvec, space.shape)
        start = np.broadcast_to(space.start, space.shape)
        parts = [hnp.arrays(np.int64, shape, elements=st.integers(int(s), int(s + n - 1)))
                 for s, n in zip(start.ravel(), nvec.ravel())]
        return st.tuples(*parts).map(lambda cols: np.stack(cols, axis=-1).reshape(shape + space.shape))
    if isinstance(space, spaces.Box):
        low, high = float(np.min(space.low)), float(np.max(space.high))
        elements = st.floats(low, high, width=32, allow_nan=False, allow_infinity=False)
        return hnp.arrays(space.dtype, shape + space.shape, elements=elements).map(
            lambda a: np.clip(a, space.low, space.high).astype(space.dtype))
    raise TypeError(f"no action strategy for {space}")


class TermInputs(NamedTuple):
    """What a reward term receives for one step of ``batch`` worlds, and the scenario it came from."""

    prev: Any
    state: Any
    actions: Any
    params: Any
    compiled: CompiledScenario

    @property
    def args(self) -> tuple[Any, Any, Any, Any]:
        """``(prev, state, actions, params)``: call a term as ``term(*inputs.args)``."""
        return self.prev, self.state, self.actions, self.params


@st.composite
def term_inputs(draw, environment: str, steps: st.SearchStrategy[int] = st.integers(0, 60), batch: int = 3,
                scenario: Optional[st.SearchStrategy[dict[str, Any]]] = None) -> TermInputs:
    """A state reached by ``steps`` random-action steps of ``batch`` worlds of a drawn scenario, then one
    step with drawn actions: the inputs of a reward term on that step.

    ``scenario`` (a strategy of scenario dicts, default :func:`scenarios` with episodes long enough for
    the steps) replaces the drawn scenario. The rollout goes through the runtime, so agents whose episode
    ended act as the runtime makes them (the placeholder action).
    """
    count = draw(steps)
    data = draw(scenario or scenarios(environment, episode_length=st.integers(count + 1, count + 200)))
    compiled = compile_scenario(data)
    env = BatchedEnv(compiled, batch=batch)
    seed = draw(st.integers(0, MAX_SEED))
    env.reset(seed)
    space, names, meanings = env.sim.action_space, compiled.agent_names, env.sim.action_meanings
    act = random_policy(space, env.shape, np.random.default_rng(seed))
    for _ in range(count):
        env.step(check_actions(space, act(None), names, meanings))
    last = check_actions(space, draw(actions(space, env.shape)), names, meanings)
    prev = env.state
    env.step(last)
    return TermInputs(prev, env.state, last, compiled.params, compiled)


__all__ = ["TermInputs", "actions", "compiled_scenarios", "scenarios", "term_inputs"]
