"""Every registered reward term keeps its contract on states the real simulators produce."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings, strategies as st

from hivex_dsl.compiler.registry import environments
from hivex_dsl.testing import term_inputs

TERMS = [(env_id, term.name) for env_id, entry in environments().items() for term in entry.terms]


@pytest.mark.parametrize("env_id", list(environments()))
@settings(max_examples=25, deadline=None)
@given(data=st.data())
def test_terms_are_finite_in_range_shaped_and_deterministic(env_id, data):
    """One rollout per example serves every term of the environment (resets dominate the cost)."""
    inputs = data.draw(term_inputs(env_id))
    count = inputs.compiled.agents
    for term in environments()[env_id].terms:
        value = np.asarray(term(*inputs.args))
        assert value.shape == (3, count), term.name
        assert np.all(np.isfinite(value)), term.name
        assert np.all(value >= term.contract.low) and np.all(value <= term.contract.high), term.name
        np.testing.assert_array_equal(value, term(*inputs.args))


@pytest.mark.parametrize("env_id, term_name", TERMS)
def test_contract_is_documented(env_id, term_name):
    contract = environments()[env_id].terms[term_name].contract
    assert contract.title and contract.description and contract.equation
    assert contract.timing in ("dense", "event", "terminal") and contract.scope in ("agent", "team", "global")


def test_every_term_has_a_row_in_its_reward_table():
    for entry in environments().values():
        assert list(entry.reward_table.matrix) == list(entry.terms.names)
