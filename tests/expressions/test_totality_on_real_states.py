"""Any expression that compiles over an environment's vocabulary is finite and inside its inferred range
on the states the simulator really produces (random expressions, real rollouts)."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from hivex_dsl.lang.expr import ExpressionError, compile_expression

from .rollouts import recorded

ENVIRONMENTS = ("wind_farm_control", "ocean_plastic_collection", "drone_based_reforestation")


RECORDED = {env_id: recorded(env_id, {"agents": 3, "episode_length": 100}, 25, seed=2) for env_id in ENVIRONMENTS}
UNARY = ("abs({})", "sqrt({})", "log({})", "exp({})", "-{}", "prev({})", "delta({})", "team_mean({})",
         "team_max({})", "team_sum({})")
BINARY = ("{} + {}", "{} - {}", "{} * {}", "{} / {}", "min({}, {})", "max({}, {})", "clip({}, {}, 1)",
          "where({} > {}, 1, 0)")


def _expressions(names: list[str]):
    leaf = st.one_of(st.sampled_from(names), st.sampled_from(["0.5", "2", "1e-3", "100"]))
    return st.recursive(leaf, lambda inner: st.one_of(
        st.tuples(st.sampled_from(UNARY), inner).map(lambda t: t[0].format(t[1])),
        st.tuples(st.sampled_from(BINARY), inner, inner).map(lambda t: t[0].format(f"({t[1]})", f"({t[2]})"))),
        max_leaves=6)


@pytest.mark.parametrize("env_id", ENVIRONMENTS)
@settings(max_examples=40, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(data=st.data())
def test_what_compiles_stays_finite_and_in_range_on_real_states(env_id, data):
    quantities, pairs = RECORDED[env_id]
    numbers = [n for n, q in quantities.items() if q.kind == "number"]
    source = data.draw(_expressions(numbers))
    try:
        expression = compile_expression(source, quantities, agents=3)
    except ExpressionError:
        return
    for now, before in pairs:
        value = expression.evaluate(now, before)
        assert np.all(np.isfinite(value)), source
        assert np.all((expression.low <= value) & (value <= expression.high)), (source, value.min(), value.max())
