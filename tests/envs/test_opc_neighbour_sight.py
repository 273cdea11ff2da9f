"""params.neighbour_sight_m: how far a vessel's vector observation sees its closest neighbour (issue 52's probe).

The vector's third pair is the closest active vessel's position over the half extent H, (0, 0) without one. Null,
the default, sends it at any distance; a number r sends it only while that vessel is at most r metres away, (0, 0)
past it; 0 blinds every vessel to the others. Worked by hand on one world of three vessels at rest (H = 200 m, so
the closest vessel's position reads x / 200, y / 200).
"""

from __future__ import annotations

import numpy as np
import pytest

import hivex_dsl
from hivex_dsl import ScenarioError

from .test_opc_mechanics import NOOP, hand_built, simulator

ENV = "ocean_plastic_collection"
VESSELS = [(10.0, 10.0), (40.0, 50.0), (-110.0, 10.0)]  # 0-1: 50 m apart, 0-2: 120 m, 1-2: 155.2 m


def neighbour_seen(**params) -> np.ndarray:
    """(3, 2): each vessel's closest-neighbour pair after one step of three vessels at rest."""
    sim = simulator(3, **params)
    state = hand_built(sim, VESSELS, [0, 0, 0], [(150.0, 150.0)])
    new, _ = sim.step(state, np.array([[NOOP, NOOP, NOOP]]), np.random.default_rng(1))
    return new.vector[0, :, 4:6]


def test_by_default_each_vessel_sees_its_closest_neighbour_at_any_distance():
    np.testing.assert_allclose(neighbour_seen(), [[0.2, 0.25], [0.05, 0.05], [0.05, 0.05]], atol=1e-7)
    # vessel 1's closest is vessel 0 (50 m), vessel 2's is vessel 0 too (120 m against 155.2 m)


def test_a_neighbour_past_the_sight_reads_as_no_neighbour():
    """Sight 100 m: vessel 2's closest (vessel 0, 120 m off) is not sent, (0, 0), while 0 and 1 (50 m) see each
    other; its further vessel (1, 155.2 m) is not sent in its place."""
    seen = neighbour_seen(neighbour_sight_m=100.0)
    np.testing.assert_allclose(seen, [[0.2, 0.25], [0.05, 0.05], [0.0, 0.0]], atol=1e-7)
    far = neighbour_seen(neighbour_sight_m=40.0)
    np.testing.assert_array_equal(far, np.zeros((3, 2)))


def test_the_sight_is_inclusive_and_zero_blinds_every_vessel():
    np.testing.assert_allclose(neighbour_seen(neighbour_sight_m=50.0)[:2], [[0.2, 0.25], [0.05, 0.05]], atol=1e-7)
    np.testing.assert_array_equal(neighbour_seen(neighbour_sight_m=0.0), np.zeros((3, 2)))


def test_blind_vessels_still_collide_and_see_themselves():
    """The sight changes what is observed, nothing else: two blind vessels 8 m apart collide (10 m) and pay."""
    sim = simulator(2, neighbour_sight_m=0.0)
    state = hand_built(sim, [(0.0, 0.0), (8.0, 0.0)], [0, 180], [(150.0, 150.0)])
    new, outcome = sim.step(state, np.array([[NOOP, NOOP]]), np.random.default_rng(1))
    assert outcome.events["collided_with_other_vessel"].all()
    np.testing.assert_allclose(new.vector[0, 1, 0:2], [0.04, 0.0], atol=1e-7)  # its own position, 8 / 200


def test_the_default_keeps_the_main_scenarios_fingerprint_and_a_sight_changes_it():
    main = {"hivex": 1, "environment": ENV, "task": 0, "agents": 3}
    default = hivex_dsl.compile(main).fingerprint
    assert hivex_dsl.compile({**main, "params": {"neighbour_sight_m": None}}).fingerprint == default
    assert hivex_dsl.compile({**main, "params": {"neighbour_sight_m": 0.0}}).fingerprint != default


@pytest.mark.parametrize("bad", [-1.0, 1001.0])
def test_a_sight_out_of_bounds_is_refused(bad):
    with pytest.raises(ScenarioError, match="neighbour_sight_m"):
        hivex_dsl.compile({"hivex": 1, "environment": ENV, "agents": 3, "params": {"neighbour_sight_m": bad}})
