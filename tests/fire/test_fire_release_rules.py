"""The release's spread rules as options of ``hivex_dsl.sim.fire`` (issue 52), on hand-drawn grids.

The release's ForestDataGenerator.BurnNNeighbourIndexes reads hot, dry and overcast at the neighbour it tries,
tries only neighbours within 10 m in 3-D, and reads the wind at the burning tree (Wind.GetWindAtLocation). Each
option is forced to an outcome known by hand: a chance of 1 a factor and one factor that can hold.
"""

from __future__ import annotations

import numpy as np
import pytest

from hivex_dsl.sim.fire import FactorGrid, FireSpec, TreeState, fire_step, grid_cell_table
from hivex_dsl.sim.procgen.wind import WindParams, local_wind, wind_reader, wind_reset

from .test_fire_engine import BLOCK, FULL_7, MILD, NO_WIND_CONE, WIND_10, around, cells, level, reset, step

ONE_FACTOR = {"spread_chance_per_factor": 1.0, **NO_WIND_CONE}


def hot_from_column_2(calls=None):
    """Conditions hot where col >= 2 (no other factor anywhere), recording each call's cells."""
    def conditions(world, row, col):
        if calls is not None:
            calls.append(sorted(zip(row.tolist(), col.tolist())))
        return np.where(col >= 2, 1.0, 0.0), np.ones(len(row)), np.ones(len(row))
    return conditions


def test_weather_at_the_neighbour_counts_the_targets_own_weather():
    # the burning tree (3, 3) stands where it is hot; its block spans columns 1-5, of which 2-5 are hot
    at_burning = step(reset(FULL_7), FireSpec(**ONE_FACTOR), WIND_10, level(1, 7), hot_from_column_2())
    assert cells(at_burning.trees[0], TreeState.BURNING) == around((3, 3), BLOCK) | {(3, 3)}
    calls = []
    spec = FireSpec(spread_weather_at="neighbour", **ONE_FACTOR)
    at_target = step(reset(FULL_7), spec, WIND_10, level(1, 7), hot_from_column_2(calls))
    hot_targets = [(dr, dc) for dr, dc in BLOCK if 3 + dc >= 2]
    assert len(hot_targets) == 19  # 5 rows x 4 columns, less the burning tree itself
    assert cells(at_target.trees[0], TreeState.BURNING) == around((3, 3), hot_targets) | {(3, 3)}
    assert calls == [sorted(around((3, 3), BLOCK))]  # asked once, for each of the 24 targets


def test_weather_at_the_neighbour_reads_a_factor_grid_at_the_target_cells():
    # a 7 x 7 weather grid on the 7 x 7 forest, one weather cell a forest cell: hot where col >= 2
    counts = np.tile((np.arange(7) >= 2).astype(np.int8), 7)[None]
    grid = FactorGrid(counts, grid_cell_table(np.arange(7), 7))
    spec = FireSpec(spread_weather_at="neighbour", **ONE_FACTOR)
    state = step(reset(FULL_7), spec, WIND_10, level(1, 7), grid)
    assert cells(state.trees[0], TreeState.BURNING) == around((3, 3), [(r, c) for r, c in BLOCK if c >= -1]) | {(3, 3)}


def test_three_d_reach_leaves_out_the_neighbours_beyond_it():
    spec = FireSpec(spread_chance_per_factor=1.0, downwind_cone_deg=180.0, spread_max_distance_m=10.0)
    flat = level(1, 7)
    # flat ground on 3 m cells: the farthest neighbour, (2, 2), lies 8.49 m off: the whole block
    state = fire_step(reset(FULL_7), np.random.default_rng(0), spec, np.zeros(1), flat, MILD, cell_m=3.0)
    assert cells(state.trees[0], TreeState.BURNING) == around((3, 3), BLOCK) | {(3, 3)}
    # 4 m cells: the corners lie 11.3 m off, (1, 2) 8.9 m and (2, 0) 8 m
    state = fire_step(reset(FULL_7), np.random.default_rng(0), spec, np.zeros(1), flat, MILD, cell_m=4.0)
    assert cells(state.trees[0], TreeState.BURNING) == around((3, 3), [o for o in BLOCK if o not in
                                                                      [(2, 2), (2, -2), (-2, 2), (-2, -2)]]) | {(3, 3)}
    # 3 m cells on ground rising 5 m a column: two columns off is 6 m across and 10 m up or down, 11.7 m; one
    # column off at most sqrt(6^2 + 3^2 + 5^2) = 8.4 m; the same column two rows off 6 m
    ramp = np.broadcast_to(5.0 * np.arange(7, dtype=np.float32), (1, 7, 7)).copy()
    state = fire_step(reset(FULL_7), np.random.default_rng(0), spec, np.zeros(1), ramp, MILD, cell_m=3.0)
    assert cells(state.trees[0], TreeState.BURNING) == around((3, 3), [o for o in BLOCK if abs(o[1]) < 2]) | {(3, 3)}


def test_three_d_reach_draws_what_the_block_draws_and_needs_the_cell_size():
    # a reach beyond the block leaves every try as it was: the same draws, the same fire, at chance 0.2
    trees = [FULL_7] * 8
    wide = FireSpec(downwind_cone_deg=180.0, spread_max_distance_m=100.0)
    reached = fire_step(reset(*trees), np.random.default_rng(3), wide, np.zeros(8), level(8, 7), MILD, cell_m=3.0)
    plain = fire_step(reset(*trees), np.random.default_rng(3), FireSpec(downwind_cone_deg=180.0), np.zeros(8),
                      level(8, 7), MILD)
    np.testing.assert_array_equal(reached.trees, plain.trees)
    assert 0 < np.count_nonzero(plain.trees == TreeState.BURNING) < 8 * 25  # the draws decided something
    with pytest.raises(ValueError, match="cell_m"):
        fire_step(reset(FULL_7), np.random.default_rng(0), wide, np.zeros(1), level(1, 7), MILD)


def test_winds_at_the_burning_trees_set_each_ones_downwind_cone():
    grid = ["TTTTTTTTT"] * 9
    grid[1], grid[7] = "TBTTTTTTT", "TTTTTTTBT"  # burning trees at (1, 1) and (7, 7): their blocks do not meet
    asked = []

    def winds(world, row, col):  # east at (1, 1), north (+row) at (7, 7)
        asked.append(sorted(zip(row.tolist(), col.tolist())))
        return np.where(row == 1, 0.0, np.pi / 2)

    spec = FireSpec(spread_chance_per_factor=1.0)  # the 45 degree cone; only downwind can hold
    state = fire_step(reset(grid), np.random.default_rng(0), spec, winds, level(1, 9), MILD)
    east = [(0, 1), (0, 2), (1, 1), (-1, 1), (1, 2), (-1, 2), (2, 2), (-2, 2)]
    north = [(1, 0), (2, 0), (1, 1), (1, -1), (2, 1), (2, -1), (2, 2), (2, -2)]
    on_grid = {(r, c) for r, c in around((1, 1), east) | around((7, 7), north) if 0 <= r < 9 and 0 <= c < 9}
    assert cells(state.trees[0], TreeState.BURNING) == on_grid | {(1, 1), (7, 7)}
    assert asked == [[(1, 1), (7, 7)]]  # once per burning tree


def test_the_wind_reader_reads_the_local_wind_at_cell_centres():
    params = WindParams(wind_noise_scale_m=300.0)
    spec = params.wind_spec()
    wind = wind_reset(np.random.default_rng(11), 3, spec)
    half, cell_m = 600.0, 3.0
    world = np.array([2, 0, 2, 1, 0])  # unsorted, uneven per world
    row, col = np.array([0, 17, 399, 200, 5]), np.array([3, 250, 0, 200, 399])
    read = wind_reader(wind, spec, half, cell_m)(world, row, col)
    for i in range(len(world)):
        point = np.zeros((3, 1, 2))
        point[world[i], 0] = ((col[i] + 0.5) * cell_m - half, (row[i] + 0.5) * cell_m - half)
        assert read[i] == pytest.approx(local_wind(wind, point, spec)[world[i], 0], abs=1e-12)
    assert len(wind_reader(wind, spec, half, cell_m)(*(np.zeros(0, np.int64),) * 3)) == 0
