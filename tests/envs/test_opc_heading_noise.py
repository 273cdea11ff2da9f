"""params.heading_noise_deg: a random turn the sea gives every vessel each physics step (issue 52's probe).

The original's trained worlds crash at a steady rate with policies sharper than ours (the reward table's ending
note), as a disturbance no policy foresees would make them. 0, the default, draws nothing, so the scenarios and the
records trained before the param keep their worlds; above 0 each active vessel's heading moves by a normal draw of
that standard deviation before its steering, from the step's generator.
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest

import hivex_dsl
from hivex_dsl import ScenarioError

from .test_opc_mechanics import NOOP, floating, hand_built, simulator

ENV = "ocean_plastic_collection"
RIGHT = [0, 1]  # no throttle, turn right 6 degrees


def test_without_noise_a_step_draws_nothing_from_the_generator():
    sim = simulator(3)
    state = hand_built(sim, [(0, 0), (50, 0), (-50, 0)], [0, 90, 0], [(150, 150)])
    rng = np.random.default_rng(7)
    sim.step(state, np.array([[NOOP, NOOP, NOOP]]), rng)
    assert rng.random() == np.random.default_rng(7).random()


def test_the_sea_turns_each_vessel_by_draws_of_the_given_spread():
    """1,000 worlds of three vessels at rest, one step: the turns are N(0, 3 degrees); a steered one adds its 6."""
    sim = simulator(3, heading_noise_deg=3.0)
    state = sim.reset(np.random.default_rng(0), 1000)
    state = replace(state, heading=np.zeros((1000, 3)), speed=np.zeros((1000, 3)))
    new, _ = sim.step(state, np.tile(np.array([NOOP, RIGHT, NOOP]), (1000, 1, 1)), np.random.default_rng(2))
    turns = np.degrees(new.heading)
    held = turns[:, [0, 2]].ravel()
    assert abs(held.mean()) < 0.2 and held.std() == pytest.approx(3.0, rel=0.05)
    assert turns[:, 1].mean() == pytest.approx(-6.0, abs=0.3)  # right is clockwise


def test_an_ended_vessel_is_not_turned_and_a_turned_one_at_rest_collects_nothing():
    sim = simulator(2, heading_noise_deg=10.0)
    state = hand_built(sim, [(0, 0), (60, 0)], [0, 0], [(1.0, 0.0), (61.0, 0.0)])
    state = replace(state, active=np.array([[True, False]]))
    new, _ = sim.step(state, np.array([[NOOP, NOOP]]), np.random.default_rng(3))
    assert new.heading[0, 0] != 0.0 and new.heading[0, 1] == 0.0
    assert floating(new) == {(1.0, 0.0), (61.0, 0.0)}  # the turned collector did not sweep its pebble


def test_the_same_generator_gives_the_same_worlds():
    sim = simulator(3, heading_noise_deg=3.0)
    runs = []
    for _ in range(2):
        state = sim.reset(np.random.default_rng(4), 4)
        rng = np.random.default_rng(5)
        for _ in range(20):
            state, _ = sim.step(state, np.tile(np.array([[1, 0], [1, 1], [1, 2]]), (4, 1, 1)), rng)
        runs.append(state.position)
    np.testing.assert_array_equal(*runs)


def test_the_default_keeps_the_main_scenarios_fingerprint():
    """A scenario that says 0 does what one written before the param did, so its fingerprint is theirs."""
    main = {"hivex": 1, "environment": ENV, "task": 0, "agents": 3}
    assert hivex_dsl.compile({**main, "params": {"heading_noise_deg": 0.0}}).fingerprint == \
        hivex_dsl.compile(main).fingerprint


@pytest.mark.parametrize("bad", [-1.0, 31.0])
def test_a_spread_out_of_bounds_is_refused(bad):
    with pytest.raises(ScenarioError, match="heading_noise_deg"):
        hivex_dsl.compile({"hivex": 1, "environment": ENV, "agents": 3, "params": {"heading_noise_deg": bad}})
