"""The reward composer: linear in the weights, zero weights skipped, names checked first."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, strategies as st

from hivex_dsl.sim.reward import RewardComposer, TermRegistry

SHAPE = (2, 3)
weights = st.floats(-100, 100, allow_nan=False)


def registry() -> TermRegistry:
    reg = TermRegistry("test_env")

    @reg.term("ramp", title="Ramp", description="d", low=0, high=5, sign="bonus", timing="dense", scope="agent")
    def ramp(prev, state, actions, params):
        return state["x"]

    @reg.term("cost", title="Cost", description="d", low=-1, high=0, sign="penalty", timing="event", scope="global")
    def cost(prev, state, actions, params):
        return -np.ones(SHAPE) * (state["x"].mean() > 1)

    @reg.term("explodes", title="Boom", description="d", low=0, high=1, sign="bonus", timing="dense", scope="agent")
    def explodes(prev, state, actions, params):
        raise AssertionError("a zero-weight term must never be evaluated")

    return reg


STATE = {"x": np.arange(6.0).reshape(SHAPE) / 2}


def total(w_ramp: float, w_cost: float) -> np.ndarray:
    composer = RewardComposer(registry(), {"ramp": w_ramp, "cost": w_cost, "explodes": 0.0})
    return composer(None, STATE, None, None, SHAPE)[0]


@given(a=weights, b=weights, c=weights, d=weights)
def test_linear_in_the_weights(a, b, c, d):
    np.testing.assert_allclose(total(a + c, b + d), total(a, b) + total(c, d), atol=1e-9)


@given(a=weights, k=st.floats(-10, 10, allow_nan=False))
def test_homogeneous(a, k):
    np.testing.assert_allclose(total(k * a, 0.0), k * total(a, 0.0), atol=1e-9)


def test_weighted_sum_by_hand():
    # ramp = x = [[0, .5, 1], [1.5, 2, 2.5]]; mean 1.25 > 1 so cost = -1 everywhere
    expected = 2.0 * STATE["x"] + 3.0 * -1.0
    np.testing.assert_allclose(total(2.0, 3.0), expected)


def test_zero_weight_contributes_exactly_zero_and_is_not_reported():
    composer = RewardComposer(registry(), {"ramp": 0.0, "cost": 1.0, "explodes": 0.0})
    reward, terms = composer(None, STATE, None, None, SHAPE)
    assert composer.active == ("cost",)
    assert set(terms) == {"cost"}
    np.testing.assert_array_equal(reward, -np.ones(SHAPE))


def test_unweighted_values_are_reported():
    _, terms = RewardComposer(registry(), {"ramp": 7.0})(None, STATE, None, None, SHAPE)
    np.testing.assert_array_equal(terms["ramp"], STATE["x"])


def test_an_unpaid_term_is_evaluated_and_reported_but_adds_nothing():
    """By hand: ramp at weight 2 unpaid, cost at 3 paid; the reward is cost's 3 x -1 alone, ramp's value is reported
    for the statistics (which weigh it by its 2) and ``paid`` says what each term pays per unit."""
    composer = RewardComposer(registry(), {"ramp": 2.0, "cost": 3.0}, unpaid=frozenset({"ramp"}))
    reward, terms = composer(None, STATE, None, None, SHAPE)
    np.testing.assert_array_equal(reward, np.full(SHAPE, -3.0))
    np.testing.assert_array_equal(terms["ramp"], STATE["x"])
    assert composer.active == ("ramp", "cost") and composer.unpaid == {"ramp"}
    assert (composer.paid("ramp"), composer.paid("cost"), composer.weights["ramp"]) == (0.0, 3.0, 2.0)


def test_unknown_name_fails_even_with_zero_weight():
    with pytest.raises(KeyError, match="did you mean 'ramp'"):
        RewardComposer(registry(), {"rampp": 0.0})


def test_signature_and_contract_are_checked_at_registration():
    reg = TermRegistry("test_env")
    with pytest.raises(TypeError, match="must take"):
        reg.term("bad", title="t", description="d", low=0, high=1, sign="bonus", timing="dense",
                 scope="agent")(lambda state, prev, actions, params: 0)
    with pytest.raises(ValueError, match="bonus but its range starts below 0"):
        reg.term("neg", title="t", description="d", low=-1, high=1, sign="bonus", timing="dense",
                 scope="agent")(lambda prev, state, actions, params: 0)
