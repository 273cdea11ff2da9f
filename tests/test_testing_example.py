"""The README's example of property-testing reward terms with hivex_dsl.testing (the README shows this file's
example verbatim; tests/test_testing.py checks that it still does)."""

from __future__ import annotations

# --- example start ---
import numpy as np
from hypothesis import given, settings

from hivex_dsl.testing import term_inputs


@settings(max_examples=10, deadline=None)
@given(term_inputs("ocean_plastic_collection", batch=2))
def test_collect_trash_pays_one_per_pebble_collected(inputs):
    """On any state a rollout reaches, with any actions: the term pays exactly the pebbles collected."""
    collect_trash = inputs.compiled.entry.terms["collect_trash"]
    value = collect_trash(*inputs.args)  # (prev, state, actions, params)
    assert value.shape == (2, inputs.compiled.agents)
    np.testing.assert_array_equal(value, inputs.state.collected)
# --- example end ---
