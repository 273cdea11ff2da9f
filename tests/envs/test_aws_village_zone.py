"""params.village_zone: where a burning tree counts as too close to the village.

The release's CityGenerator.FindClosestTrees, called once a new island's forest stands and before its fire starts,
keeps every standing tree within 50 forest cells (150 m) of the village's cell in x and in y
(ForestDataGenerator.GetLocationsOfClosestTrees(50, village): a 101 x 101 block of cells); CheckCloseTreeBurning
sets the flag once any of them burns. So the release's zone is a square of half side 150 m ('square'); the paper's
'within 150 m' read as a circle ('circle') misses a fire coming at the square's corners, up to 212 m away. Worked
by hand: one burning tree set at a chosen offset from the village, everything else bare ground.
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest

import hivex_dsl
from hivex_dsl.envs.aerial_wildfire_suppression.simulator import AerialWildfireSimulator
from hivex_dsl.sim.fire import FireState, TreeState


def one_tree_burning(zone: str, offset_m: tuple[float, float]):
    """The simulator, its one-world state and the village threat with a lone burning tree whose cell centre lies
    ``offset_m`` (x, y) from the village centre (the village moved onto a cell centre so offsets are exact)."""
    compiled = hivex_dsl.compile({"hivex": 1, "environment": "aerial_wildfire_suppression", "agents": 1,
                                  "params": {"village_zone": zone}})
    sim = AerialWildfireSimulator(compiled)
    state = sim.reset(np.random.default_rng(0), 1)
    cells, cell_m, half = sim.forest_spec.cells, sim.forest_spec.spacing_m, compiled.params.island_half_extent_m
    centre_col = centre_row = cells // 2  # the cell whose centre is at (+cell_m / 2, +cell_m / 2)
    village = np.array([[-half + (centre_col + 0.5) * cell_m, -half + (centre_row + 0.5) * cell_m]])
    col = centre_col + int(round(offset_m[0] / cell_m))
    row = centre_row + int(round(offset_m[1] / cell_m))
    trees = np.zeros((1, cells, cells), np.uint8)
    trees[0, row, col] = TreeState.BURNING
    fire = FireState(trees=trees, burning=np.array([row * cells + col]), age=np.zeros(1, np.int32),
                     quiet=np.zeros(1, np.int32), out=np.zeros(1, bool), ignited=np.zeros(1, np.int64),
                     burnt_out=np.zeros(1, np.int64))
    far_away = np.array([[[-half + 10.0, -half + 10.0]]])  # the plane sees nothing near the village
    sighting = sim._sight_of(fire, village, far_away, np.ones((1, 1), bool))
    return bool(sighting.village_threat[0])


@pytest.mark.parametrize("offset_m, square, circle", [
    ((0.0, 147.0), True, True),      # straight north, 147 m: inside both
    ((147.0, 0.0), True, True),      # straight east
    ((153.0, 0.0), False, False),    # just past 150 m along an axis: outside both
    ((141.0, 141.0), True, False),   # at a corner, 199 m away: only the release's square
    ((-111.0, 111.0), True, False),  # sqrt(2) x 111 = 157 m: the circle misses it too
    ((-102.0, -102.0), True, True),  # 144 m on the diagonal: both
    ((150.0, 153.0), False, False),  # past the square's north edge
])
def test_the_release_flags_a_burning_tree_in_the_square_the_paper_s_circle_only_within_150_m(offset_m, square, circle):
    assert one_tree_burning("square", offset_m) is square
    assert one_tree_burning("circle", offset_m) is circle

