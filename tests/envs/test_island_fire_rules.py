"""The release's spread rules (hivex_dsl.sim.fire's options) as both island environments' params read them.

The engine's hand cases are in tests/fire/test_fire_release_rules.py; here, that each simulator passes what the
option asks for: with the wind's noise field at no deviation the local wind is the main wind, so 'local' must
burn exactly the fire 'main' burns, and with the field's +/-90 degrees it must not.
"""

from __future__ import annotations

import numpy as np
import pytest

import hivex_dsl

WORLDS = 4
# the rules off (Wildfire Resource Management's defaults; Aerial Wildfire Suppression's are the release's)
PLAIN = {"spread_weather_at": "burning", "spread_max_distance_m": 0.0, "spread_wind": "main"}


def burnt_after(environment: str, steps: int, params: dict) -> np.ndarray:
    """(B, C, C) trees of WORLDS test-seed worlds after ``steps`` steps of idle agents."""
    compiled = hivex_dsl.compile({"hivex": 1, "environment": environment, "terrain_level": 5, "params": params})
    sim = compiled.entry.make_simulator(compiled)
    rng = np.random.default_rng(compiled.seeds.test)
    state = sim.reset(rng, WORLDS)
    shape = (WORLDS, compiled.agents, 1)
    if environment == "aerial_wildfire_suppression":
        idle = {"continuous": np.ones(shape, np.float32), "discrete": np.zeros(shape, np.int64)}
    else:
        idle = np.zeros((WORLDS, compiled.agents, 4), np.int64)
    for _ in range(steps):
        state, _ = sim.step(state, idle, rng)
    return state.fire.trees.copy()


@pytest.mark.parametrize(("environment", "steps"), [("aerial_wildfire_suppression", 450),
                                                    ("wildfire_resource_management", 40)])
def test_the_local_wind_reaches_the_fire(environment, steps):
    still = {**PLAIN, "wind_deviation_max_deg": 0.0}
    main = burnt_after(environment, steps, still)
    np.testing.assert_array_equal(burnt_after(environment, steps, {**still, "spread_wind": "local"}), main)
    assert np.count_nonzero(main >= 2) > 20 * WORLDS  # the fire spread: the comparison compared something
    assert not np.array_equal(burnt_after(environment, steps, {**PLAIN, "spread_wind": "local"}),
                              burnt_after(environment, steps, PLAIN))


@pytest.mark.parametrize(("environment", "steps"), [("aerial_wildfire_suppression", 450),
                                                    ("wildfire_resource_management", 40)])
def test_the_three_d_reach_and_the_neighbours_weather_reach_the_fire(environment, steps):
    plain = burnt_after(environment, steps, PLAIN)
    # a reach beyond the block changes nothing (the same draws); one of 6 m cuts the diagonal neighbours off
    np.testing.assert_array_equal(burnt_after(environment, steps, {**PLAIN, "spread_max_distance_m": 100.0}), plain)
    assert np.count_nonzero(burnt_after(environment, steps, {**PLAIN, "spread_max_distance_m": 6.0}) >= 2) < \
        np.count_nonzero(plain >= 2)
    assert not np.array_equal(burnt_after(environment, steps, {**PLAIN, "spread_weather_at": "neighbour"}), plain)
