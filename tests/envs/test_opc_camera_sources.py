"""params.camera_source 'heat_map': the visual observation shows the pollution heat map, not the pebbles; 'blank'
shows nothing.

Worked by hand on a 200 m world whose 64 x 64 heat map (6.25 m cells, centres at -196.875 + 6.25 j metres) rises
by one unit a column along x: between two cell centres the camera reads the straight line through them, over the
world's densest cell (column 63), so a camera cell centred at x reads ((x + 200) / 6.25 - 0.5) / 63.
"""

from __future__ import annotations

import numpy as np
import pytest

from hivex_dsl.envs.ocean_plastic_collection.camera import CAMERA_CELLS, heat_camera

from .test_opc_mechanics import GO, hand_built, simulator, step

HALF = 200.0
RAMP = np.broadcast_to(np.arange(64.0), (64, 64))[None] / (64 * 63 * 64 / 2)  # column j holds j, summing to 1


def expected(x: float) -> float:
    return ((x + HALF) / 6.25 - 0.5) / 63


def test_a_vessel_facing_east_sees_the_ramp_rise_ahead_and_not_across():
    """Heading +x: row 0 is the farthest ahead (forward 24 m), column 0 the farthest left (+y)."""
    picture = heat_camera(RAMP, np.array([[[10.0, -30.0]]]), np.exp(1j * np.zeros((1, 1))), np.ones((1, 1), bool),
                          HALF)[0, 0]
    forward = 24.0 - 2.0 * np.arange(CAMERA_CELLS)  # row r's centre lies this far ahead
    np.testing.assert_allclose(picture[:, 7], [expected(10.0 + f) for f in forward], rtol=1e-6)
    np.testing.assert_allclose(picture, picture[:, :1].repeat(CAMERA_CELLS, axis=1), rtol=1e-6)  # flat across


def test_a_vessel_facing_north_sees_the_ramp_rise_to_its_right():
    """Heading +y: column 0 is the farthest left, which is -x, so the picture rises from left to right."""
    picture = heat_camera(RAMP, np.zeros((1, 1, 2)), np.exp(1j * np.full((1, 1), np.pi / 2)), np.ones((1, 1), bool),
                          HALF)[0, 0]
    left = 24.0 - 2.0 * np.arange(CAMERA_CELLS)
    np.testing.assert_allclose(picture[3], [expected(-l) for l in left], rtol=1e-6, atol=1e-7)


def test_beyond_the_border_and_for_inactive_vessels_the_picture_is_dark():
    """A vessel 10 m inside the east border at heading +x sees 14 m and more ahead beyond it: rows whose centre
    lies past x = 200 read 0; past the last cell centre (196.875 m) up to the border the map reads its densest
    column, 1; an inactive vessel sees nothing."""
    position = np.array([[[190.0, 0.0], [0.0, 0.0]]])
    picture = heat_camera(RAMP, position, np.ones((1, 2), complex), np.array([[True, False]]), HALF)[0]
    beyond = 190.0 + 24.0 - 2.0 * np.arange(CAMERA_CELLS) > HALF
    assert beyond.sum() == 7 and (picture[0][beyond] == 0).all()
    inside_rows = picture[0][~beyond][:, 0]
    np.testing.assert_allclose(inside_rows[:2], 1.0)  # x 200 (on the border) and 198 lie past the last centre
    np.testing.assert_allclose(inside_rows[2:], [expected(x) for x in 196.0 - 2.0 * np.arange(16)], rtol=1e-6)
    assert not picture[1].any()


def test_the_simulator_shows_the_heat_map_and_not_what_was_swept():
    """Under 'heat_map' the newest stack is heat_camera's picture of the world's own map at the vessel's new pose,
    whatever it swept up (the older stack the reset's picture)."""
    by_heat = simulator(1, camera_source="heat_map")
    state = hand_built(by_heat, [(0, 0)], [0], [(x, 0.0) for x in np.arange(0.5, 12.0, 0.5)], speeds=[2.0])
    new, _ = step(by_heat, state, [GO])
    assert new.collected[0, 0] > 0
    picture = heat_camera(new.heat, new.position, np.exp(1j * new.heading), new.active, HALF)
    np.testing.assert_array_equal(new.visual[..., 0], picture)
    np.testing.assert_array_equal(new.visual[..., 1], state.visual[..., 0])


@pytest.mark.parametrize("source", ["pebbles", "heat_map"])  # (blank: below)
def test_the_picture_is_a_density_in_the_unit_interval(source):
    sim = simulator(3, camera_source=source)
    state = sim.reset(np.random.default_rng(3), 4)
    assert state.visual.dtype == np.float32 and 0.0 <= state.visual.min() and state.visual.max() <= 1.0
    assert state.visual[..., 0].any()


def test_a_blank_camera_shows_nothing_in_either_stack():
    sim = simulator(3, camera_source="blank")
    state = sim.reset(np.random.default_rng(3), 2)
    for _ in range(3):
        state, _ = sim.step(state, np.ones((2, 3, 2), np.int64), np.random.default_rng(4))
    assert state.visual.shape == (2, 3, CAMERA_CELLS, CAMERA_CELLS, 2) and not state.visual.any()
    assert state.nearby.sum() > 0  # pebbles lie within 25 m, unseen
