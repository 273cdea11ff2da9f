"""Every registered Wind Farm Control term, re-expressed in the expression language, pays bit-identical rewards."""

from __future__ import annotations

import numpy as np

import hivex_dsl
from hivex_dsl.compiler import registry
from hivex_dsl.runtime import BatchedEnv

# The paper's equations as wind_farm_control/terms.py implements them, written over the vocabulary
AS_EXPRESSIONS = {
    "generate_energy": "clip(performance, 0, 1)",
    "avoid_damage": "where(wind_angle_deg <= 90, wind_angle_deg / 90, 2 - wind_angle_deg / 90)",
}


def test_every_registered_term_is_re_expressed():
    assert set(AS_EXPRESSIONS) == set(registry.get("wind_farm_control").terms.names)


def test_expressions_and_registered_terms_agree_bit_for_bit_over_1000_random_steps():
    terms = {f"{name}_expr": {"expr": expr} for name, expr in AS_EXPRESSIONS.items()}
    weights = {name: 1.0 for name in AS_EXPRESSIONS} | {name: 1.0 for name in terms}
    compiled = hivex_dsl.compile({"hivex": 1, "environment": "wind_farm_control", "agents": 6, "pattern": "random",
                                  "episode_length": 300, "terms": terms, "weights": weights})
    env = BatchedEnv(compiled, batch=4)
    env.reset(seed=7)
    rng = np.random.default_rng(1)
    compared = 0
    for _ in range(1000):
        transition = env.step(rng.integers(0, 3, env.shape), restart=None)
        for name in AS_EXPRESSIONS:
            registered, expressed = transition.terms[name], transition.terms[f"{name}_expr"]
            assert registered.dtype == expressed.dtype == np.float64
            assert registered.tobytes() == expressed.tobytes(), name
            compared += registered.size
        ended = transition.ended.all(axis=1)
        if ended.any():
            env.reset_worlds(ended)
    assert compared == 1000 * 4 * 6 * len(AS_EXPRESSIONS)
    summary = env.episode_summary(0, 0)["reward_terms"]
    for name in AS_EXPRESSIONS:
        assert summary[name] == summary[f"{name}_expr"]


def test_the_inferred_contracts_hold_the_registered_ones():
    """Interval arithmetic may be wider than the truth (where() takes the hull of both branches), never narrower."""
    terms = {f"{name}_expr": {"expr": expr} for name, expr in AS_EXPRESSIONS.items()}
    compiled = hivex_dsl.compile({"hivex": 1, "environment": "wind_farm_control", "terms": terms})
    contracts = {c.name: c for c in compiled.term_contracts}
    for name in AS_EXPRESSIONS:
        registered, inferred = contracts[name], contracts[f"{name}_expr"]
        assert inferred.low <= registered.low and registered.high <= inferred.high
        assert (inferred.sign, inferred.scope) == (registered.sign, registered.scope)
    assert (contracts["generate_energy_expr"].low, contracts["generate_energy_expr"].high) == (0.0, 1.0)
