"""Ocean Plastic Collection observations: the paper's spaces, the camera's layout and the stacks."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest
from gymnasium import spaces

import hivex_dsl
from hivex_dsl.envs.ocean_plastic_collection.camera import build_field

ENV = "ocean_plastic_collection"
NOOP = [0, 0]


def simulator(agents: int = 1, **params):
    """The pebble camera (params.camera_source 'pebbles') unless ``params`` say otherwise: these tests place
    pebbles in it; tests/envs/test_opc_camera_sources.py works the others."""
    params = {"camera_source": "pebbles", **params}
    sc = hivex_dsl.compile({"hivex": 1, "environment": ENV, "agents": agents, "params": params})
    return sc.entry.make_simulator(sc)


def observe_after_noop(sim, vessels, headings_deg, pebbles):
    """Observations after one do-nothing step of vessels at rest (they neither move nor turn)."""
    state = sim.reset(np.random.default_rng(0), 1)
    state = replace(state, position=np.array([vessels], float), heading=np.radians([headings_deg]).astype(float),
                    speed=np.zeros((1, len(vessels))),
                    pebbles=build_field(np.array([pebbles], float).reshape(1, -1, 2), sim.geometry))
    new, _ = sim.step(state, np.array([[NOOP] * len(vessels)]), np.random.default_rng(1))
    return new, sim.observe(new)


def test_spaces_follow_the_paper_specification_table():
    sim = simulator(3)
    assert sim.observation_space == spaces.Dict({
        "vector": spaces.Box(-1.0, 1.0, (12,), np.float32),  # 6 values x 2 stacks
        "visual": spaces.Box(0.0, 1.0, (25, 25, 2), np.float32),  # 25 x 25 x 1 trash density x 2 stacks
    })
    assert sim.action_space == spaces.MultiDiscrete([2, 3])
    assert len(sim.observation_labels) * sim.observation_stacks == 12


def offset(heading_deg: float, forward: float, left: float) -> np.ndarray:
    """World offset of a point ``forward`` ahead and ``left`` to the left of a vessel with this heading."""
    h = np.radians(heading_deg)
    return forward * np.array([np.cos(h), np.sin(h)]) + left * np.array([-np.sin(h), np.cos(h)])


@pytest.mark.parametrize("heading", [0.0, 30.0, 90.0, -135.0])
@pytest.mark.parametrize("forward, left, row, col", [
    (4.0, 0.0, 10, 12),     # 4 m straight ahead: two 2 m cells above the centre cell (12, 12)
    (0.0, 4.0, 12, 10),     # 4 m to the left
    (0.0, -4.0, 12, 14),    # 4 m to the right
    (-4.0, 0.0, 14, 12),    # 4 m behind
    (23.5, 23.5, 0, 0),     # the far-left corner ahead
    (-23.5, -23.5, 24, 24),  # the near-right corner behind
    (-0.5, -0.5, 12, 12),   # in the centre cell (behind the collector, which would take it)
])
def test_a_pebble_lands_in_the_camera_cell_of_its_place_relative_to_the_vessel(heading, forward, left, row, col):
    vessel = np.array([20.0, -30.0])
    # the 4 m pebble ahead is beyond the collector's 3 m reach, so a vessel at rest leaves it floating
    _, obs = observe_after_noop(simulator(), [vessel], [heading], [vessel + offset(heading, forward, left)])
    camera = obs["visual"][0, 0, :, :, 0]
    assert camera[row, col] == 0.5  # one pebble of camera_full_count = 2
    assert np.count_nonzero(camera) == 1


def test_pebbles_outside_the_50_m_square_are_not_seen():
    vessel = np.array([0.0, 0.0])
    outside = [offset(0, 25.5, 0), offset(0, 0, -25.5), offset(0, -25.5, 10)]
    _, obs = observe_after_noop(simulator(), [vessel], [0], outside)
    assert not obs["visual"][..., 0].any()


def test_density_is_the_count_over_camera_full_count_capped_at_1():
    vessel = np.array([0.0, 0.0])
    pebbles = [offset(0, 10.2, 0.3), offset(0, 10.8, 0.7),                         # two in one cell -> 1
               offset(0, -8.5, 6.5), offset(0, -8.7, 6.1), offset(0, -8.9, 6.9),  # three -> capped at 1
               offset(0, 15.5, -15.5)]                                            # one -> 0.5
    _, obs = observe_after_noop(simulator(), [vessel], [0], pebbles)
    camera = obs["visual"][0, 0, :, :, 0]
    assert camera[7, 12] == 1.0 and camera[16, 9] == 1.0 and camera[4, 20] == 0.5
    _, obs = observe_after_noop(simulator(camera_full_count=4), [vessel], [0], pebbles)
    assert obs["visual"][0, 0, 16, 9, 0] == 0.75


def brute_force_camera(vessel, heading_deg, pebbles):
    """The camera cell counts by a plain Python loop over pebbles (the definition, independent of the code)."""
    counts = np.zeros((25, 25))
    h = np.radians(heading_deg)
    for p in pebbles:
        d = p - vessel
        forward = d[0] * np.cos(h) + d[1] * np.sin(h)
        left = -d[0] * np.sin(h) + d[1] * np.cos(h)
        row, col = int(np.floor((25 - forward) / 2)), int(np.floor((25 - left) / 2))
        if 0 <= row < 25 and 0 <= col < 25:
            counts[row, col] += 1
    return counts


@pytest.mark.parametrize("half, radius", [(200.0, 25.0), (300.0, 60.0)])
def test_the_binned_camera_and_nearby_count_match_a_loop_over_every_pebble(half, radius):
    """Vessels anywhere (also at the border, where the pebble grid is clipped) see what a loop sees."""
    rng = np.random.default_rng(11)
    vessels = np.array([[0.0, 0.0], [half - 5, -half + 1], [-half + 12, 150.0], [60.0, 60.0]])
    headings = rng.uniform(-180, 180, 4)
    near_vessels = np.concatenate([v + rng.uniform(-70, 70, (150, 2)) for v in vessels])
    pebbles = np.clip(np.concatenate([near_vessels, rng.uniform(-half, half, (400, 2))]), -half, half)
    sc = hivex_dsl.compile({"hivex": 1, "environment": ENV, "agents": 4,
                            "params": {"collision_distance_m": 0.1, "nearby_radius_m": radius,
                                       "camera_source": "pebbles"},
                            "generators": {"pollution": {"half_extent_m": half}, "spawn": {"half_extent_m": half}}})
    new, obs = observe_after_noop(sc.entry.make_simulator(sc), vessels, headings, pebbles)
    left = new.pebbles.positions[0][new.pebbles.alive[0]]  # some may have been swept at rest
    for a in range(4):
        expected = np.minimum(brute_force_camera(vessels[a], headings[a], left), 2) / 2
        np.testing.assert_array_equal(obs["visual"][0, a, :, :, 0], expected)
        nearby = int(np.sum(np.hypot(*(left - vessels[a]).T) < radius))
        assert new.nearby[0, a] == nearby


def test_vector_holds_position_direction_and_closest_vessel_normalised_by_200_m():
    vessels = [(100.0, -50.0), (120.0, -40.0), (-150.0, 150.0)]
    _, obs = observe_after_noop(simulator(3), vessels, [90.0, 180.0, -45.0], [(0.0, 0.0)])
    frame = obs["vector"][0, :, :6]
    np.testing.assert_allclose(frame[0], [0.5, -0.25, 0.0, 1.0, 0.6, -0.2], atol=1e-7)
    np.testing.assert_allclose(frame[1], [0.6, -0.2, -1.0, 0.0, 0.5, -0.25], atol=1e-7)
    np.testing.assert_allclose(frame[2], [-0.75, 0.75, np.sqrt(0.5), -np.sqrt(0.5), 0.5, -0.25], atol=1e-7)


def test_a_lone_vessel_sees_no_neighbour():
    _, obs = observe_after_noop(simulator(1), [(10.0, 10.0)], [0.0], [(0.0, 0.0)])
    assert obs["vector"][0, 0, 4:6].tolist() == [0.0, 0.0]


def test_stack_0_is_this_step_and_stack_1_the_previous_one_starting_from_zeros():
    sim = simulator(3)
    rng = np.random.default_rng(2)
    state = sim.reset(rng, 2)
    first = sim.observe(state)
    assert not first["vector"][..., 6:].any() and not first["visual"][..., 1].any()
    actions = np.ones((2, 3, 2), np.int64)
    new, _ = sim.step(state, actions, rng)
    second = sim.observe(new)
    np.testing.assert_array_equal(second["vector"][..., 6:], first["vector"][..., :6])
    np.testing.assert_array_equal(second["visual"][..., 1], first["visual"][..., 0])
    assert not np.array_equal(second["vector"][..., :6], first["vector"][..., :6])
