"""params.village_zone: where a burning tree counts as too close to the village.

The release's CityGenerator.FindClosestTrees, called once a new island's forest stands and before its fire starts,
keeps every standing tree within 50 forest cells (150 m) of the village's cell in x and in y
(ForestDataGenerator.GetLocationsOfClosestTrees(50, village): a 101 x 101 block of cells); CheckCloseTreeBurning
sets the flag once any of them burns. So the release's zone is a square of half side 150 m ('square'); the paper's
'within 150 m' read as a circle ('circle') misses a fire coming at the square's corners, up to 212 m away. Worked
by hand: one burning tree set at a chosen offset from the village, everything else bare ground.

params.village_distance: how far a plane is from the village in Find Village. The release's FindVillageTask reads
Vector3.Distance(village, plane) < 150, and its AutoAdjustHeight keeps the plane 100 m above the terrain its last
frame's cast hit (over ground below 0, 100 m), descending past 500 m from the centre in x or y; so over the
village's level ground a plane finds it about 112 m away ('release'), where this toolkit read 150 m horizontally
('horizontal'). Worked by hand on flat terrain and on a cliff.
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest

import hivex_dsl
from hivex_dsl.envs.aerial_wildfire_suppression.simulator import AerialWildfireSimulator
from hivex_dsl.sim.fire import fire_reset
from hivex_dsl.sim.grids import terrain_grid


def one_tree_burning(zone: str, offset_m: tuple[float, float]) -> bool:
    """Whether the village is threatened by a lone burning tree whose cell centre lies ``offset_m`` (x, y) from the
    village centre (the village moved onto a cell centre so offsets are exact)."""
    compiled = hivex_dsl.compile({"hivex": 1, "environment": "aerial_wildfire_suppression", "agents": 1,
                                  "params": {"village_zone": zone}})
    sim = AerialWildfireSimulator(compiled)
    state = sim.reset(np.random.default_rng(0), 1)
    cells, cell_m, half = sim.forest_spec.cells, sim.forest_spec.spacing_m, compiled.params.island_half_extent_m
    centre_col = centre_row = cells // 2  # the cell whose centre is at (+cell_m / 2, +cell_m / 2)
    village = np.array([[-half + (centre_col + 0.5) * cell_m, -half + (centre_row + 0.5) * cell_m]])
    col = centre_col + int(round(offset_m[0] / cell_m))
    row = centre_row + int(round(offset_m[1] / cell_m))
    lone = np.zeros((1, cells, cells), bool)
    lone[0, row, col] = True
    fire = fire_reset(lone, lone)
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


def plane_near_village(distance: str, horizontal_m: float, cast_x_m: float | None = None, ground_m: float = 0.0,
                       cliff_m: float = 0.0):
    """Whether one plane ``horizontal_m`` east of the village (at the centre) finds it. The terrain stands at
    ``ground_m``, and at ``ground_m + cliff_m`` east of x = 90 m; the plane's last cast was at x ``cast_x_m`` (where
    it is, unless given)."""
    compiled = hivex_dsl.compile({"hivex": 1, "environment": "aerial_wildfire_suppression", "agents": 1,
                                  "params": {"village_distance": distance}})
    sim = AerialWildfireSimulator(compiled)
    state = sim.reset(np.random.default_rng(0), 1)
    grid = terrain_grid(sim.island.terrain)
    node_x = grid.origin + np.arange(grid.n) * grid.cell  # columns follow x
    terrain = ground_m + np.where(node_x >= 90.0, cliff_m, 0.0)[None, None, :].repeat(grid.n, axis=1)
    maps = replace(state.maps, terrain=terrain.astype(np.float32), village=np.zeros((1, 2)))
    position = np.array([[[horizontal_m, 0.0]]])
    cast_at = position if cast_x_m is None else np.array([[[cast_x_m, 0.0]]])
    return bool(sim._near_village(maps, position, cast_at, np.ones((1, 1), bool))[0, 0])


@pytest.mark.parametrize("horizontal_m, horizontal, release", [
    (80.0, True, True),     # 3-D: sqrt(80^2 + 100^2) = 128 m
    (111.0, True, True),    # 149.4 m
    (113.0, True, False),   # 150.7 m: the release's plane flies 100 m above the ground
    (149.0, True, False),
    (151.0, False, False),
])
def test_the_release_finds_the_village_in_3_d_from_100_m_above_the_ground(horizontal_m, horizontal, release):
    for ground_m in (0.0, 20.0):  # the village on the same ground as the plane: only the 100 m count
        assert plane_near_village("horizontal", horizontal_m, ground_m=ground_m) is horizontal
        assert plane_near_village("release", horizontal_m, ground_m=ground_m) is release


def test_the_plane_s_height_is_read_at_its_last_cast():
    # 80 m east of the village: cast over the village's ground, 100 m up, 128 m in 3-D; cast east of a 30 m cliff,
    # 130 m up, sqrt(80^2 + 130^2) = 152.6 m; 70 m east with that cast, 147.6 m
    assert plane_near_village("release", 80.0, cast_x_m=0.0, cliff_m=30.0)
    assert not plane_near_village("release", 80.0, cast_x_m=100.0, cliff_m=30.0)
    assert plane_near_village("release", 70.0, cast_x_m=100.0, cliff_m=30.0)
    assert plane_near_village("horizontal", 80.0, cast_x_m=100.0, cliff_m=30.0)


def test_past_500_m_the_release_s_plane_flies_lower():
    # its last cast 575 m out: d = 75 / 150 = 0.5, ((cos(pi / 2) + 1) / 2 + 0.1) x 100 = 60 m over the village's
    # ground at 0 m (not 100 m): 137 m east is sqrt(137^2 + 60^2) = 149.6 m in 3-D, 139 m east 151.4 m
    assert plane_near_village("release", 137.0, cast_x_m=575.0)
    assert not plane_near_village("release", 139.0, cast_x_m=575.0)
    assert not plane_near_village("release", 137.0, cast_x_m=137.0)  # cast where it is: 100 m up, 168.9 m
