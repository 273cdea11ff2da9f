"""params.max_speed_m and drag 0: a vessel that holds its speed up to a cap (issue 52, the reward table's note
'Early lives'). Worked by hand with the simulator's physics steps: speed' = min(cap, speed (1 - drag) + 0.2
throttle), then the vessel advances by its new speed along its heading."""

from __future__ import annotations

import numpy as np
import pytest

import hivex_dsl
from hivex_dsl.base.errors import HivexError
from hivex_dsl.envs.ocean_plastic_collection.params import OceanPlasticCollectionParams

from .test_opc_mechanics import GO, NOOP, hand_built, simulator, step

ENV = "ocean_plastic_collection"
HOLD = {"drag": 0.0, "max_speed_m": 1.0}


def speeds_and_x(sim, actions: list) -> tuple[list[float], list[float]]:
    """One vessel from rest at the centre heading +x, far from pebbles: its speed and x after each step."""
    state = hand_built(sim, [(0, 0)], [0], [(150, 150)])
    speeds, xs = [], []
    for action in actions:
        state, _ = step(sim, state, [action])
        speeds.append(float(state.speed[0, 0]))
        xs.append(float(state.position[0, 0, 0]))
    return speeds, xs


def test_without_drag_a_vessel_reaches_the_cap_and_holds_it_when_it_stops_throttling():
    """0.2, 0.4, 0.6, 0.8, 1.0 over five throttled steps, then capped at 1.0, and 1.0 held over three idle steps;
    x sums the speeds: 0.2, 0.6, 1.2, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0."""
    speeds, xs = speeds_and_x(simulator(1, **HOLD), [GO] * 6 + [NOOP] * 3)
    np.testing.assert_allclose(speeds, [0.2, 0.4, 0.6, 0.8, 1.0, 1.0, 1.0, 1.0, 1.0])
    np.testing.assert_allclose(xs, [0.2, 0.6, 1.2, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0])


def test_the_default_has_no_cap_and_drag_slows_an_idle_vessel():
    """speed' = 0.9 speed + 0.2: 0.2, 0.38, 0.542 throttled, then 0.4878 idle."""
    speeds, _ = speeds_and_x(simulator(1), [GO] * 3 + [NOOP])
    np.testing.assert_allclose(speeds, [0.2, 0.38, 0.542, 0.4878])


def test_a_cap_above_the_drag_limit_changes_nothing():
    """Under the default drag the speed tends to 0.2 / 0.1 = 2 m a step, which a 3 m cap never reaches."""
    capped, _ = speeds_and_x(simulator(1, max_speed_m=3.0), [GO] * 40)
    free, _ = speeds_and_x(simulator(1), [GO] * 40)
    assert capped == free


@pytest.mark.parametrize("params, top", [({}, 2.0), (HOLD, 1.0), ({"max_speed_m": 1.5}, 1.5),
                                         ({"max_speed_m": 3.0}, 2.0)])
def test_top_speed_is_the_drag_limit_or_the_cap_whichever_is_lower(params, top):
    assert OceanPlasticCollectionParams(**params).top_speed_m == pytest.approx(top)


def test_drag_0_without_a_cap_is_a_clear_error():
    with pytest.raises(HivexError) as error:
        hivex_dsl.compile({"hivex": 1, "environment": ENV, "agents": 3, "params": {"drag": 0.0}})
    assert "max_speed_m" in str(error.value) and "drag" in str(error.value)


def test_a_scenario_that_does_not_cap_keeps_its_fingerprint():
    """max_speed_m null (None) is what every scenario did before the param came (ADDED_FIELDS): records stay matched."""
    plain = hivex_dsl.compile({"hivex": 1, "environment": ENV, "agents": 3})
    written = hivex_dsl.compile({"hivex": 1, "environment": ENV, "agents": 3, "params": {"max_speed_m": None}})
    capped = hivex_dsl.compile({"hivex": 1, "environment": ENV, "agents": 3, "params": {"max_speed_m": 1.0}})
    assert plain.fingerprint == written.fingerprint != capped.fingerprint
