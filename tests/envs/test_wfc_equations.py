"""Wind Farm Control physics and reward terms against values computed by hand from the paper."""

from __future__ import annotations

import numpy as np
import pytest

import hivex_dsl
from hivex_dsl.envs.wind_farm_control.simulator import alignment, next_performance, wind_force
from hivex_dsl.envs.wind_farm_control.terms import avoid_damage, generate_energy
from hivex_dsl.envs.wind_farm_control.types import WindFarmState

DEG = np.pi / 180


def state_with(heading_deg, wind_deg, performance):
    heading = np.radians(np.atleast_2d(heading_deg).astype(float))
    return WindFarmState(positions=np.zeros(heading.shape + (2,)), heading=heading,
                         performance=np.broadcast_to(np.asarray(performance, float), heading.shape).copy(),
                         local_wind=np.radians(np.atleast_2d(wind_deg).astype(float)), wind=None)


@pytest.mark.parametrize("heading, wind, expected", [
    (180.0, 0.0, 1.0),    # wind blows to +x, rotor faces -x: straight into it
    (0.0, 0.0, 0.0),      # facing downwind
    (90.0, 0.0, 0.5),     # across the wind
    (135.0, 0.0, 0.75),   # 45 degrees off upwind: 1 - 45/180
    (-150.0, 0.0, 1 - 30 / 180),
    (10.0, 190.0, 1.0),   # wrap-around: upwind of 190 is 10
])
def test_alignment_is_linear_in_the_angle_to_upwind(heading, wind, expected):
    assert alignment(np.radians(heading), np.radians(wind)) == pytest.approx(expected)


@pytest.mark.parametrize("theta, expected", [(0.0, 0.0), (0.3, 0.0), (0.5, 0.0), (0.75, 0.5), (0.9, 0.8), (1.0, 1.0)])
def test_wind_force_is_zero_below_half_then_linear(theta, expected):
    assert wind_force(np.array(theta), 0.5) == pytest.approx(expected)


def test_performance_update_by_hand():
    # P = 0: P' = 0 - 0.1*0 + 0.8*0.1 = 0.08; then 0.08 - 0.008 + 0.08 = 0.152
    p1 = next_performance(np.array(0.0), np.array(0.8), 0.1, 0.1)
    p2 = next_performance(p1, np.array(0.8), 0.1, 0.1)
    assert p1 == pytest.approx(0.08)
    assert p2 == pytest.approx(0.152)


def test_performance_converges_to_the_wind_force():
    # the fixed point of P <- 0.9 P + 0.1 W is P = W
    p = np.array(0.0)
    for _ in range(400):
        p = next_performance(p, np.array(0.6), 0.1, 0.1)
    assert p == pytest.approx(0.6, abs=1e-9)


def test_generate_energy_is_the_clamped_performance():
    state = state_with([[0.0, 0.0, 0.0]], [[0.0, 0.0, 0.0]], [[-0.2, 0.37, 1.4]])
    assert generate_energy(None, state, None, None) == pytest.approx(np.array([[0.0, 0.37, 1.0]]))


@pytest.mark.parametrize("angle, expected", [(0, 0.0), (45, 0.5), (90, 1.0), (135, 0.5), (180, 0.0), (-60, 60 / 90),
                                             (300, 60 / 90), (120, 2 - 120 / 90)])
def test_avoid_damage_by_hand(angle, expected):
    state = state_with([[30.0 + angle]], [[30.0]], 0.0)
    assert avoid_damage(None, state, None, None)[0, 0] == pytest.approx(expected)


def test_one_simulated_step_follows_the_paper_equation():
    """Run the real simulator one step and recompute the reward from its state by hand."""
    sc = hivex_dsl.compile({"hivex": 1, "environment": "wind_farm_control", "agents": 4})
    sim = sc.entry.make_simulator(sc)
    rng = np.random.default_rng(3)
    state = sim.reset(rng, 2)
    new, _ = sim.step(state, np.array([[0, 1, 2, 1], [2, 2, 0, 0]]), rng)
    turn = np.radians(sc.params.rotation_speed_deg)
    expected_heading = state.heading + turn * np.array([[0, 1, -1, 1], [-1, -1, 0, 0]])
    np.testing.assert_allclose(np.cos(new.heading), np.cos(expected_heading), atol=1e-12)
    upwind_angle = np.abs((new.heading - (new.local_wind + np.pi) + np.pi) % (2 * np.pi) - np.pi)
    theta = 1 - upwind_angle / np.pi
    force = np.clip((theta - 0.5) / 0.5, 0, 1)
    np.testing.assert_allclose(new.performance, 0.0 - 0.1 * 0.0 + 0.1 * force)


def test_observation_layout_and_normalisation():
    sc = hivex_dsl.compile({"hivex": 1, "environment": "wind_farm_control", "pattern": "chain", "agents": 16})
    sim = sc.entry.make_simulator(sc)
    state = sim.reset(np.random.default_rng(0), 1)
    obs = sim.observe(state)
    assert obs.shape == (1, 16, 6) and obs.dtype == np.float32
    np.testing.assert_allclose(obs[0, :, :2], state.positions[0] / 600.0, rtol=1e-6)
    np.testing.assert_allclose(np.hypot(obs[..., 2], obs[..., 3]), 1.0, rtol=1e-6)
    np.testing.assert_allclose(np.hypot(obs[..., 4], obs[..., 5]), 1.0, rtol=1e-6)
    assert np.all(np.abs(obs) <= 1.0)
