"""params.drop_ground: over what ground a drop lands, past the island's 600 m too.

The release's HivexAgent.DropWater tests its action, that the plane holds water, and that its last cast hit the
terrain (layer 8) at y 10 or more; nothing bounds it to the island. PickupWater fills a plane without water wherever
|x| or |z| exceeds 600 m. So over a headland of the generator's terrain that runs on past 600 m above the sea a
plane refills at one decision and drops at the next, for as long as its cast reads the headland ('terrain'); this
toolkit's drop read only the island's forest grid ('island'). Worked by hand on a world whose whole terrain map
stands at 20 m east of x = 620 m and at 0 m elsewhere (the forest grid, which ends at 600 m, is sea), one plane
flying 5 m a step along the x axis, its cast read every step (terrain_cast 'step').
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest

import hivex_dsl
from hivex_dsl.envs.aerial_wildfire_suppression.simulator import AerialWildfireSimulator
from hivex_dsl.envs.island import SEA
from hivex_dsl.sim.grids import terrain_grid

HEADLAND_FROM_M = 620.0


def headland(drop_ground: str, x: float, water: bool):
    """The simulator and a one-plane state at (x, 0), over a headland east of HEADLAND_FROM_M past the island."""
    compiled = hivex_dsl.compile({"hivex": 1, "environment": "aerial_wildfire_suppression", "agents": 1,
                                  "params": {"drop_ground": drop_ground, "terrain_cast": "step"}})
    sim = AerialWildfireSimulator(compiled)
    state = sim.reset(np.random.default_rng(0), 1)
    grid = terrain_grid(sim.island.terrain)
    node_x = grid.origin + np.arange(grid.n) * grid.cell  # columns follow x
    terrain = np.where(node_x >= HEADLAND_FROM_M, 20.0, 0.0)[None, None, :].repeat(grid.n, axis=1)
    cells = sim.forest_spec.cells
    maps = replace(state.maps, terrain=terrain.astype(np.float32), height=np.zeros((1, cells, cells), np.float32),
                   ground=np.full((1, cells, cells), SEA, np.uint8))
    state = replace(state, maps=maps, position=np.array([[[x, 0.0]]]), heading=np.zeros((1, 1)),
                    water=np.full((1, 1), water), flying=np.ones((1, 1), bool), cast_at=np.array([[[x, 0.0]]]))
    return sim, sim.derive(state)


def drop(sim, state):
    act = {"continuous": np.zeros((1, 1, 1), np.float32), "discrete": np.ones((1, 1, 1), np.int64)}
    return sim.step(state, act, np.random.default_rng(1))


@pytest.mark.parametrize("drop_ground, lands", [("terrain", True), ("island", False)])
def test_a_drop_over_a_headland_past_the_island_lands_as_the_release_s_dropwater_reads_it(drop_ground, lands):
    sim, state = headland(drop_ground, 640.0, water=True)  # to 645 m, over 20 m of terrain
    assert sim.action_mask(state)[0, 0].tolist() == [True, True]  # the release's mask: terrain of 0.02 m or more
    new, outcome = drop(sim, state)
    assert outcome.events["dropped_water"][0, 0] == lands and new.water[0, 0] != lands
    assert new.prepared[0, 0] == 0 and new.extinguished[0, 0] == 0  # no forest past the grid within reach


def test_over_the_sea_past_the_island_no_drop_lands_under_either_rule():
    for drop_ground in ("terrain", "island"):
        sim, state = headland(drop_ground, 603.0, water=True)  # to 608 m: terrain 0 m, below the sea level
        new, outcome = drop(sim, state)
        assert not outcome.events["dropped_water"][0, 0] and new.water[0, 0]


def test_over_a_headland_a_plane_refills_and_drops_every_other_decision():
    """Six decisions asking to drop from 640 m, without water: pick-up, drop, pick-up, drop, ..., as the release's
    PickupWater and DropWater take turns there; each drop counts though it wets nothing."""
    sim, state = headland("terrain", 640.0, water=False)
    picks, drops = [], []
    for _ in range(6):
        state, outcome = drop(sim, state)
        picks.append(bool(outcome.events["picked_up_water"][0, 0]))
        drops.append(bool(outcome.events["dropped_water"][0, 0]))
    assert picks == [True, False] * 3 and drops == [False, True] * 3
    assert (state.position[0, 0, 0] - 640.0) == pytest.approx(6 * sim.params.plane_speed_m)  # still over it


def test_the_land_past_the_island_grows_with_the_terrain_level():
    """A level scales the same seed's heights (its height multiplier), so on the same test worlds land above the sea
    past the island's square only grows with the level: rare at level 1, where the original's late planes dropped
    least (benchmarks/aws_drops.py --headlands)."""
    from ..benchmark_scripts import benchmark_script

    script = benchmark_script("aws_drops")
    (share_1, area_1), (share_10, area_10) = script.headlands(1, worlds=8), script.headlands(10, worlds=8)
    assert share_1 <= share_10 and 0 < area_1 < area_10 / 5
