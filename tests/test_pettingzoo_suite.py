"""PettingZoo's whole test suite, unmodified, on every environment through the module convention
(``hivex_dsl.zoo.<env>_v0``: ``env()``, ``parallel_env()``, ``raw_env``, ``max_cycles``)."""

from __future__ import annotations

import importlib
import os
import sys
from functools import partial

import numpy as np
import pytest
from gymnasium import spaces
from pettingzoo.test import (api_test, max_cycles_test, parallel_api_test, parallel_seed_test, render_test,
                             seed_test)

from hivex_dsl import ActionError
from hivex_dsl.compiler import registry
from hivex_dsl.sim.spaces import describe_space

ENV_IDS = list(registry.environments())
CYCLES = 40  # steps per episode in these tests: enough for every agent to act, small enough for CI


def module(env_id: str):
    return importlib.import_module(f"hivex_dsl.zoo.{env_id}_v0")


@pytest.mark.ecosystem("pettingzoo")
@pytest.mark.parametrize("env_id", ENV_IDS)
def test_api_test(env_id):
    api_test(module(env_id).env(max_cycles=CYCLES), num_cycles=CYCLES + 10)


@pytest.mark.ecosystem("pettingzoo")
@pytest.mark.parametrize("env_id", ENV_IDS)
def test_parallel_api_test(env_id):
    parallel_api_test(module(env_id).parallel_env(max_cycles=CYCLES), num_cycles=CYCLES + 10)


@pytest.mark.ecosystem("pettingzoo")
@pytest.mark.parametrize("env_id", ENV_IDS)
def test_seed_test(env_id):
    seed_test(partial(module(env_id).env, max_cycles=CYCLES), num_cycles=CYCLES)


@pytest.mark.ecosystem("pettingzoo")
@pytest.mark.parametrize("env_id", ENV_IDS)
def test_parallel_seed_test(env_id):
    parallel_seed_test(partial(module(env_id).parallel_env, max_cycles=CYCLES), num_cycles=CYCLES)


@pytest.mark.ecosystem("pettingzoo")
@pytest.mark.parametrize("env_id", ENV_IDS)
def test_max_cycles_test(env_id):
    max_cycles_test(module(env_id))


@pytest.mark.ecosystem("pettingzoo")
@pytest.mark.parametrize("env_id", ENV_IDS)
def test_render_test(env_id, monkeypatch):
    pytest.importorskip("pygame", reason='render_mode="human" needs the window extra (pygame)')
    monkeypatch.setenv("SDL_VIDEODRIVER", os.environ.get("SDL_VIDEODRIVER", "dummy"))
    render_test(partial(module(env_id).env, max_cycles=CYCLES))


@pytest.mark.parametrize("env_id", ENV_IDS)
def test_raw_env_is_the_aec_class(env_id):
    mod = module(env_id)
    aec = mod.raw_env(max_cycles=5)
    aec.reset(seed=0)
    assert isinstance(aec, mod.raw_env) and aec.unwrapped.possible_agents == aec.possible_agents


@pytest.mark.parametrize("env_id", ENV_IDS)
def test_without_pygame_human_is_not_advertised_and_asking_for_it_says_what_to_install(env_id, monkeypatch):
    """Every listed render mode works on the install: without the window extra the metadata lists rgb_array
    alone (it listed "human", which then raised). PettingZoo's render_test builds a "human" env before it reads
    the metadata, so it needs the window extra whatever the metadata says."""
    import importlib.util

    real = importlib.util.find_spec
    monkeypatch.setattr(importlib.util, "find_spec", lambda name, *a: None if name == "pygame" else real(name, *a))
    monkeypatch.setitem(sys.modules, "pygame", None)  # `import pygame` fails as on an install without it
    env = module(env_id).parallel_env(max_cycles=CYCLES, render_mode="rgb_array")
    assert env.metadata["render_modes"] == ["rgb_array"]
    env.reset(seed=0)
    assert env.render().ndim == 3
    with pytest.raises(ImportError, match=r'render_mode="human" needs pygame: pip install "hivex-dsl\[window\]"'):
        module(env_id).parallel_env(max_cycles=CYCLES, render_mode="human")


def _outside(space):
    """An action just outside ``space`` (every entry one past its largest value)."""
    if isinstance(space, spaces.Dict):
        return {key: _outside(part) for key, part in space.spaces.items()}
    if isinstance(space, spaces.Discrete):
        return int(space.start + space.n)
    if isinstance(space, spaces.MultiDiscrete):
        return np.asarray(space.nvec, np.int64)
    return np.asarray(space.high, space.dtype) + 1


@pytest.mark.parametrize("env_id", ENV_IDS)
def test_the_aec_env_refuses_a_bad_action_at_once_for_the_agent_that_gave_it(env_id):
    # issue 54 item 10: the bad action was kept and raised only at the cycle's last agent, on every retry
    aec = module(env_id).env(max_cycles=5)
    aec.reset(seed=0)
    agents = list(aec.agents)
    for turn, agent in enumerate(agents):
        assert aec.agent_selection == agent
        space = aec.action_space(agent)
        with pytest.raises(ActionError, match=agent) as refused:
            aec.step(_outside(space))
        assert describe_space(space) in str(refused.value)
        assert aec.agent_selection == agent and aec.unwrapped.core.clock.max() == 0  # nothing changed
        aec.step(space.sample())  # the same agent then plays a good action, and the cycle goes on
    # one decision taken: the clock counts its decision_period physics steps
    assert aec.unwrapped.core.clock.max() == aec.unwrapped.core.period and aec.agent_selection == agents[0]
