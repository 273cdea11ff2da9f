"""Every registered reward term keeps its contract on states the real simulators produce."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import assume, given, settings, strategies as st

import hivex_dsl
from hivex_dsl.policies import random_policy
from hivex_dsl.registry import environments

TERMS = [(env_id, term.name) for env_id, entry in environments().items() for term in entry.terms]


def rollout_pairs(env_id: str, seed: int, steps: int, agents: int | None):
    """(prev, state, actions, params) after ``steps`` random steps of a batch of 3 worlds."""
    data = {"hivex": 1, "environment": env_id}
    if agents is not None:
        data["agents"] = agents
    sc = hivex_dsl.compile(data)
    sim = sc.entry.make_simulator(sc)
    rng = np.random.default_rng(seed)
    policy = random_policy(sim.action_space, (3, sc.agents), rng)
    state = sim.reset(rng, 3)
    prev, actions = state, policy(None)
    for _ in range(steps):
        actions = policy(None)
        prev, (state, _) = state, sim.step(state, actions, rng)
    return prev, state, actions, sc.params, sc.agents


@pytest.mark.parametrize("env_id", list(environments()))
@settings(max_examples=25, deadline=None)
@given(seed=st.integers(0, 2**32 - 1), steps=st.integers(1, 60), agents=st.sampled_from([None, 1, 3]))
def test_terms_are_finite_in_range_shaped_and_deterministic(env_id, seed, steps, agents):
    """One rollout per example serves every term of the environment (resets dominate the cost)."""
    info = environments()[env_id].info
    assume(agents is None or info.min_agents <= agents <= info.max_agents)
    prev, state, actions, params, count = rollout_pairs(env_id, seed, steps, agents)
    for term in environments()[env_id].terms:
        value = np.asarray(term(prev, state, actions, params))
        assert value.shape == (3, count), term.name
        assert np.all(np.isfinite(value)), term.name
        assert np.all(value >= term.contract.low) and np.all(value <= term.contract.high), term.name
        np.testing.assert_array_equal(value, term(prev, state, actions, params))


@pytest.mark.parametrize("env_id, term_name", TERMS)
def test_contract_is_documented(env_id, term_name):
    contract = environments()[env_id].terms[term_name].contract
    assert contract.title and contract.description and contract.equation
    assert contract.timing in ("dense", "event", "terminal") and contract.scope in ("agent", "team", "global")


def test_every_term_has_a_row_in_its_reward_table():
    for entry in environments().values():
        assert list(entry.reward_table.matrix) == list(entry.terms.names)
