"""The two bundled tasks written only in YAML: guard the village (AWS) and steady yaw (WFC)."""

from __future__ import annotations

import math

import numpy as np
import pytest

import hivex_dsl
from hivex_dsl.evaluation.policies import make_policy
from hivex_dsl.runtime import BatchedEnv

GUARD = "scenarios/aerial_wildfire_suppression/guard_the_village.yaml"
STEADY = "scenarios/wind_farm_control/steady_yaw.yaml"


def _term(compiled, name):
    return next(t for t in compiled.expressions.terms if t.contract.name == name)


def _between(plane, fire, village):
    """The guard bonus by hand for one plane that sees the fire at ``fire``."""
    d_pf, d_pv, d_fv = math.dist(plane, fire), math.dist(plane, village), math.dist(fire, village)
    if not d_pv < d_fv:
        return 0.0
    return 1.0 - min(max((d_pf + d_pv - d_fv) / 200.0, 0.0), 1.0)


@pytest.mark.parametrize("plane, fire, village", [
    ((0.0, 0.0), (100.0, 0.0), (-300.0, 0.0)),  # on the line, nearer the village than the fire: 1
    ((0.0, 60.0), (100.0, 0.0), (-300.0, 0.0)),  # off the line: less
    ((120.0, 0.0), (100.0, 0.0), (-300.0, 0.0)),  # behind the fire: 0
    ((0.0, 140.0), (100.0, 0.0), (-300.0, 0.0)),  # far off the line: clipped to 0
])
def test_guard_pays_what_the_geometry_says(plane, fire, village):
    compiled = hivex_dsl.compile(GUARD)
    expression = _term(compiled, "between_fire_and_village").expression
    d_pf, d_pv, d_fv = math.dist(plane, fire), math.dist(plane, village), math.dist(fire, village)
    now = {"sees_fire": np.array([[True, False]]), "distance_to_fire_m": np.array([[d_pf, 0.0]]),
           "distance_to_village_m": np.array([[d_pv, 10.0]]), "fire_to_village_m": np.array([[d_fv, 0.0]])}
    value = expression.evaluate(now, now)
    assert value[0, 0] == pytest.approx(_between(plane, fire, village), abs=1e-12)
    assert value[0, 1] == 0.0  # sees no fire


def test_guard_term_and_shaping_follow_the_state_over_a_rollout():
    compiled = hivex_dsl.compile(GUARD)
    env = BatchedEnv(compiled, batch=1)
    policy = make_policy("scripted", compiled, env.sim.action_space, env.shape)
    observations = env.reset(seed=5)
    seen = 0
    for _ in range(700):  # planes fly 3 m a step (issue 52): 700 steps cover the 2 km that 400 did at 5 m
        before = env.state
        transition = env.step(policy(observations))
        observations = transition.observations
        s, village = env.state, env.state.maps.village[0]
        for a in range(compiled.agents):
            plane = s.position[0, a]
            expected = _between(plane, s.sighting.plane_xy[0, a], village) if s.sighting.plane_found[0, a] else 0.0
            assert transition.terms["between_fire_and_village"][0, a] == pytest.approx(expected, abs=1e-9)
            seen += bool(s.sighting.plane_found[0, a])
            phi = lambda st: -math.dist(st.position[0, a], village) / 1000 if st.water[0, a] else 0.0  # noqa: E731
            assert transition.terms["toward_village_with_water"][0, a] == pytest.approx(
                0.99 * phi(s) - phi(before), abs=1e-12)
        if transition.ended.all():
            break
    assert seen, "the scripted planes find the fire within 700 steps"


def test_guard_contract_is_inferred_from_the_vocabulary():
    contracts = {c.name: c for c in hivex_dsl.compile(GUARD).term_contracts}
    guard = contracts["between_fire_and_village"]
    assert (guard.low, guard.high, guard.sign, guard.scope) == (0.0, 1.0, "bonus", "agent")
    shaping = contracts["toward_village_with_water"]
    assert shaping.sign == "mixed" and shaping.low < 0 < shaping.high


def test_steady_yaw_costs_each_turn_once_the_schedule_has_run():
    compiled = hivex_dsl.compile(STEADY)
    env = BatchedEnv(compiled, batch=2)
    env.reset(seed=3)
    rng = np.random.default_rng(0)
    env.env_steps = 1_000_000  # resumed training: the curriculum is over
    for _ in range(40):
        actions = rng.integers(0, 3, env.shape)
        transition = env.step(actions)
        turned = (actions != 0).astype(float)
        np.testing.assert_array_equal(transition.terms["yaw_change"], turned)
        np.testing.assert_allclose(transition.rewards, transition.terms["generate_energy"] - 0.2 * turned, atol=1e-12)


def test_steady_yaw_weight_ramps_with_the_env_step_clock():
    compiled = hivex_dsl.compile(STEADY)
    env = BatchedEnv(compiled, batch=4)
    env.reset(seed=3)
    actions = np.ones(env.shape, int)  # every turbine turns every step
    first = env.step(actions)
    np.testing.assert_allclose(first.rewards, first.terms["generate_energy"], atol=0)  # weight 0 at step 0
    assert env.env_steps == 4  # one step of four worlds
    env.env_steps = 250_000
    quarter = env.step(actions)
    np.testing.assert_allclose(quarter.rewards, quarter.terms["generate_energy"] - 0.05, atol=1e-12)
    assert env.env_steps == 250_004
    assert compiled.to_lock()["scenario"]["weights"]["yaw_change"] == {
        "from": 0.0, "to": -0.2, "over_steps": 1_000_000, "kind": "linear"}
