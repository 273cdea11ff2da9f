"""Wind Farm Control's turbine and wind dynamics against facts computed by hand from the defaults."""

from __future__ import annotations

import math

import numpy as np
import pytest

import hivex_dsl
from hivex_dsl.envs.wind_farm_control.params import WindFarmControlParams
from hivex_dsl.sim.procgen.wind import wind_reset, wind_step, wrap_angle

DEFAULTS = WindFarmControlParams()


def simulator(agents: int = 8, **params):
    sc = hivex_dsl.compile({"hivex": 1, "environment": "wind_farm_control", "agents": agents, "params": params})
    return sc.entry.make_simulator(sc)


def test_the_turbines_of_a_farm_start_facing_one_way_and_farms_differ():
    state = simulator().reset(np.random.default_rng(0), 64)
    assert np.ptp(state.heading, axis=1).max() == 0.0  # spread 0: one heading per world
    # the worlds' headings are uniform on the circle: mean resultant length about 1/sqrt(64)
    assert abs(np.exp(1j * state.heading[:, 0]).mean()) < 0.35


def test_a_full_spread_draws_every_turbine_on_its_own():
    heading = simulator(initial_heading_spread_deg=360.0).reset(np.random.default_rng(0), 256).heading
    # shared + uniform(-pi, pi) is uniform on the circle and independent between turbines of a farm
    assert abs(np.exp(1j * heading).mean()) < 0.05
    diff = wrap_angle(heading[:, 0] - heading[:, 1])
    assert abs(np.exp(1j * diff).mean()) < 0.15


def test_a_new_episode_continues_the_world_and_restarts_the_performance():
    sim = simulator()
    rng = np.random.default_rng(1)
    state = sim.reset(rng, 4)
    for _ in range(20):
        state, _ = sim.step(state, np.ones((4, 8), int), rng)
    mask = np.array([True, False, True, False])
    again = sim.reset_where(state, mask, rng)
    np.testing.assert_array_equal(again.heading, state.heading)
    np.testing.assert_array_equal(again.wind.main, state.wind.main)
    np.testing.assert_array_equal(again.local_wind, state.local_wind)
    assert np.all(again.performance[mask] == 0.0)
    np.testing.assert_array_equal(again.performance[~mask], state.performance[~mask])


def test_episodes_that_do_not_continue_draw_a_new_world():
    sim = simulator(episodes_continue=0)
    rng = np.random.default_rng(1)
    state = sim.reset(rng, 4)
    again = sim.reset_where(state, np.array([True, False, True, False]), rng)
    assert np.all(again.heading[[0, 2]] != state.heading[[0, 2]])
    np.testing.assert_array_equal(again.heading[[1, 3]], state.heading[[1, 3]])


def test_the_main_wind_reaches_its_target_after_the_hand_computed_number_of_steps():
    """From the target shift s, the remaining angle after n steps is s (1 - e)^n; reached below the tolerance."""
    spec = DEFAULTS.wind_spec()
    expected = math.ceil(math.log(spec.retarget_tolerance_deg / spec.target_shift_deg) / math.log(1 - spec.ease_rate))
    state = wind_reset(np.random.default_rng(2), 3, spec)
    first_target = state.target.copy()
    rng = np.random.default_rng(3)
    for step in range(1, expected + 1):
        state = wind_step(state, rng, spec)
        retargeted = np.abs(wrap_angle(state.target - first_target)) > 1e-9
        assert retargeted.all() == (step == expected)
    # the default pace: about one shift of the main wind per 5,000-step episode
    assert 4_000 <= expected <= 6_000


def test_random_play_turns_a_turbine_as_a_random_walk_of_the_rotation_speed():
    """A uniform choice of {0, +r, -r} has variance 2 r^2 / 3 per step, so after n steps the heading has moved
    by a standard deviation of r sqrt(2 n / 3): 0.1 degrees x sqrt(2000 / 3) = 2.58 degrees after 1,000."""
    sim = simulator()
    rng, actions = np.random.default_rng(4), np.random.default_rng(5)
    state = sim.reset(rng, 64)
    start = state.heading.copy()
    steps = 1000
    for _ in range(steps):
        state, _ = sim.step(state, actions.integers(0, 3, (64, 8)), rng)
    moved = np.degrees(wrap_angle(state.heading - start))
    expected = DEFAULTS.rotation_speed_deg * math.sqrt(2 * steps / 3)
    assert moved.std() == pytest.approx(expected, rel=0.1)


def test_all_zeros_earns_the_same_on_every_turbine_of_a_farm_in_a_uniform_wind():
    """Same heading, same wind (no local deviation), same P recursion: every turbine earns the same; and a farm
    held 45 degrees off a wind that stays put earns W = 0.5 from P = 0: sum over t of 0.5 (1 - 0.9^t)."""
    sim = simulator(wind_deviation_max_deg=0.0, wind_target_shift_deg=0.0)
    rng = np.random.default_rng(6)
    state = sim.reset(rng, 2)
    upwind = state.wind.main[:, None] + np.pi
    heading = np.broadcast_to(upwind + np.radians([[45.0], [0.0]]), (2, 8)).copy()
    state = type(state)(positions=state.positions, heading=heading, performance=state.performance,
                        local_wind=state.local_wind, wind=state.wind, wind_probe=None)
    total = np.zeros((2, 8))
    steps = 200
    for _ in range(steps):
        state, _ = sim.step(state, np.zeros((2, 8), int), rng)
        total += np.clip(state.performance, 0.0, 1.0)
    by_hand = sum(1 - 0.9 ** t for t in range(1, steps + 1))
    np.testing.assert_allclose(total, [[0.5 * by_hand] * 8, [by_hand] * 8], rtol=1e-9)
