"""params.terrain_cast: where a plane reads the ground for the drop's mask and for whether its drop lands.

The release's HivexAgent.AutoAdjustHeight casts the ray down in Update, once a rendered frame (16.7 academy steps
under mlagents-learn's defaults), and WriteDiscreteActionMask and DropWater both read its last hit ('frame', the
default since issue 52's session 46); 'step' reads the ground under the plane every step, as this toolkit did
before. Worked by hand on a world whose land (20 m) ends at x = 100 m, the sea (0 m) beyond it, one plane holding
water flying 5 m a step along the x axis.
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest

import hivex_dsl
from hivex_dsl.envs.aerial_wildfire_suppression.simulator import AerialWildfireSimulator, frame_ends
from hivex_dsl.envs.island import SEA

HALF, CELL = 600.0, 3.0
SHORE_M = 100.0


def coast(terrain_cast: str, x: float, heading_deg: float, tick: int, cast_x: float | None = None, water: bool = True):
    """The simulator and a one-plane state at (x, 0) over the coast, its last cast at (cast_x, 0)."""
    compiled = hivex_dsl.compile({"hivex": 1, "environment": "aerial_wildfire_suppression", "agents": 1,
                                  "params": {"terrain_cast": terrain_cast}})
    sim = AerialWildfireSimulator(compiled)
    state = sim.reset(np.random.default_rng(0), 1)
    east = (np.arange(400) + 0.5) * CELL - HALF >= SHORE_M  # forest-grid columns beyond the shore
    height = np.where(east[None, None, :], 0.0, 20.0).repeat(400, axis=1).astype(np.float32)
    ground = np.where(east[None, None, :], SEA, 10).repeat(400, axis=1).astype(np.uint8)
    position = np.array([[[x, 0.0]]])
    state = replace(state, maps=replace(state.maps, height=height, ground=ground), tick=tick, position=position,
                    heading=np.radians(np.array([[heading_deg]])), water=np.full((1, 1), water),
                    flying=np.ones((1, 1), bool), cast_at=np.array([[[x if cast_x is None else cast_x, 0.0]]]))
    return sim, sim.derive(state)


def drop(sim, state):
    act = {"continuous": np.zeros((1, 1, 1), np.float32), "discrete": np.ones((1, 1, 1), np.int64)}
    return sim.step(state, act, np.random.default_rng(1))


def test_frames_end_every_16_or_17_steps():
    assert [t for t in range(60) if frame_ends(t, 50.0 / 3.0)] == [16, 33, 49]


def test_flying_out_over_the_sea_a_frame_cast_still_drops_and_keeps_the_mask_open():
    sim, state = coast("frame", 98.0, 0.0, tick=0)  # to 103 m: over the sea, the last cast on land
    new, outcome = drop(sim, state)
    assert outcome.events["dropped_water"][0, 0] and not new.water[0, 0]  # dropped into the sea, water lost
    assert new.cast_at[0, 0].tolist() == [98.0, 0.0]  # no frame ended: the cast stays where it was
    kept = replace(new, water=np.ones((1, 1), bool))
    assert sim.action_mask(kept)[0, 0].tolist() == [True, True]  # over the sea, the branch still open


def test_flying_out_over_the_sea_a_step_cast_neither_drops_nor_opens_the_mask():
    sim, state = coast("step", 98.0, 0.0, tick=0)
    new, outcome = drop(sim, state)
    assert not outcome.events["dropped_water"][0, 0] and new.water[0, 0]
    assert sim.action_mask(new)[0, 0].tolist() == [True, False]


def test_a_frame_that_ends_casts_the_plane_s_new_place():
    sim, state = coast("frame", 98.0, 0.0, tick=16)  # the step from tick 16 ends a frame
    new, outcome = drop(sim, state)
    assert outcome.events["dropped_water"][0, 0]  # the drop still read the cast from before the move
    assert new.cast_at[0, 0].tolist() == pytest.approx([103.0, 0.0])
    kept = replace(new, water=np.ones((1, 1), bool))
    assert sim.action_mask(kept)[0, 0].tolist() == [True, False]


@pytest.mark.parametrize("terrain_cast, lands", [("frame", False), ("step", True)])
def test_flying_in_over_land_a_frame_cast_waits_for_the_next_frame(terrain_cast, lands):
    sim, state = coast(terrain_cast, 103.0, 180.0, tick=0)  # to 98 m: over land, the last cast at sea
    new, outcome = drop(sim, state)
    assert outcome.events["dropped_water"][0, 0] == lands and new.water[0, 0] != lands


def test_a_respawned_plane_reads_the_ground_at_its_spawn():
    sim, state = coast("frame", 98.0, 0.0, tick=0, cast_x=-50.0)
    again = sim.respawn_where(state, np.ones((1, 1), bool), np.random.default_rng(3))
    assert np.array_equal(again.cast_at, again.position) and not np.array_equal(again.position, state.position)


def test_a_plane_drops_no_water_it_picked_up_that_step_but_drops_it_the_next():
    """The release's mask is written when the plane decides: without water, the drop is closed, though
    OnActionReceived then fills the plane (PickupWater, past 600 m) before DropWater reads the action. So a plane
    flying out over the water ring with its cast still on land picks up at one decision and drops (into the ring,
    wetting nothing) at the next, every other decision until the next frame (the reward table's note 'The frame's
    terrain cast, and the main task's untrained drop branch'); and a Pick Up Water plane, which ends at its pick-up,
    never drops (the original logs no drop in that task at any level, untrained included)."""
    sim, state = coast("frame", 598.0, 0.0, tick=0, cast_x=90.0, water=False)  # to 603 m: over the ring
    assert sim.action_mask(state)[0, 0].tolist() == [True, False]  # no water when it decides: closed
    new, outcome = drop(sim, state)
    assert outcome.events["picked_up_water"][0, 0] and not outcome.events["dropped_water"][0, 0]
    assert new.water[0, 0] and sim.action_mask(new)[0, 0].tolist() == [True, True]  # the cast still on land
    after, outcome = drop(sim, new)  # tick 1: no frame ends, the cast stays at 90 m
    assert outcome.events["dropped_water"][0, 0] and not after.water[0, 0]
    assert not outcome.events["picked_up_water"][0, 0]
    again, outcome = drop(sim, after)
    assert outcome.events["picked_up_water"][0, 0] and not outcome.events["dropped_water"][0, 0]
