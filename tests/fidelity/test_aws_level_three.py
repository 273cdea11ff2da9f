"""Why Aerial Wildfire Suppression's main task at terrain level 3 tests far below the published cell here.

The published cell is the best of the original's three runs, and at level 3 that run stands further above the other
two than at any other level (2.2 times the three runs' mean, 1.4-1.8 elsewhere); the three runs' mean is as
ordinary as its neighbours'. Our one seed tests between the original's worst and best level-3 runs. Our level-3
world is levels 2 and 4's island at an intermediate height. (The reward table's notes give the figures.)
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

import hivex_dsl
from hivex_dsl.envs.island import IslandSpecs, draw_maps
from hivex_dsl.evaluation.original.compare import seed_curves
from hivex_dsl.evaluation.original.curves import original_curves
from hivex_dsl.evaluation.original.evidence import best_of_three
from hivex_dsl.evaluation.original.tail import tail
from hivex_dsl.sim.procgen.terrain import height_multiplier_for_level

AWS = "aerial_wildfire_suppression"
LEVELS = range(1, 11)
GRID = Path(__file__).resolve().parents[2] / "benchmarks" / "baselines" / "grids" / f"{AWS}.json"


def test_best_of_three_reads_wfc_s_event_files(wfc_event_runs):
    """Wind Farm Control pattern 0's three test runs from its event files: the published cell is the highest run's
    mean over its points, and the digitised band's edges are the runs' lowest and highest at every point."""
    runs = np.array([[value for _, value in wfc_event_runs[f"test_run_{i}"]["Environment/Cumulative Reward"]]
                     for i in range(3)])  # (3 runs, 200 points)
    means = np.sort(runs.mean(axis=1))
    read = best_of_three("wind_farm_control", 0, 0)
    tolerance = 2 * original_curves("wind_farm_control", 0, 0).panel("Cumulative Reward").y_per_pt
    assert read.published == pytest.approx(means[-1], abs=0.01)
    assert read.mean == pytest.approx(runs.mean(), abs=tolerance)
    assert read.lowest == pytest.approx(runs.min(axis=0).mean(), abs=tolerance)
    assert read.highest == pytest.approx(runs.max(axis=0).mean(), abs=tolerance)
    assert read.other_two == pytest.approx(means[:2].mean(), abs=2 * tolerance)


def test_every_aws_main_task_cell_publishes_a_run_above_the_three_runs_mean():
    for level in LEVELS:
        read = best_of_three(AWS, 0, level)
        assert read.mean < read.published <= read.highest, level
        assert read.other_two >= read.lowest, level


def test_level_3_s_best_run_stands_furthest_above_its_other_two_and_its_runs_are_ordinary():
    read = {level: best_of_three(AWS, 0, level) for level in LEVELS}
    ratios = {level: r.best_over_mean for level, r in read.items()}
    assert max(ratios, key=ratios.get) == 3
    assert ratios[3] == pytest.approx(1321.47 / 594.2, abs=0.01)
    assert max(ratio for level, ratio in ratios.items() if level != 3) < 1.85
    # the other two level-3 runs test at about 231, the second lowest of the ten levels (level 1: 179)
    assert read[3].other_two == pytest.approx(230.6, abs=1.0)
    # the three runs' mean at level 3 lies between its neighbours' (477 and 627): an ordinary level
    assert read[2].mean < read[3].mean < read[4].mean


def test_our_level_3_point_tests_within_the_original_s_three_runs():
    """Between the original's worst and best level-3 runs (the grid of sessions 93-94, under the release's weather:
    399.6, a run that learned to crash, above the other two runs' mean of 231 and below the published 1,321.5; of
    sessions 91-92: 622.4; of session 89, 728.6; of session 86, 555.6; of session 64,
    645.3; the grid of session 48, 259.7; of session 44, 161.2, below the other two runs' mean as most of that
    grid's points lie below the published; the grid before, 1,032.3)."""
    point = next(p for p in json.loads(GRID.read_text())["points"] if p["level"] == 3)
    ours, read = point["return"]["mean"], best_of_three(AWS, 0, 3)
    assert ours < read.published
    assert read.lowest < ours < read.highest


def test_level_3_s_three_seeds_crash_as_the_original_s_runs_spread_and_none_finds_its_best():
    """Level 3 on three seeds under the release's weather (session 94): over the last tenth of the budget seeds 0
    and 1 crash 0.52 and 0.43 times a plane-episode and seed 2 0.03, as the original's band there spreads from 0.03
    to 0.49 on average (its lowest and highest run at each summary point): the crash-prone policy is one the
    original's runs learned too. The three test at 399.6, 267.9 and 420.0, each between the original's worst and
    best runs and below its best, the published 1,321.5."""
    point = next(p for p in json.loads(GRID.read_text())["points"] if p["level"] == 3)
    runs = [point, *point["other_seeds"]]
    assert [run.get("seed", point["seed"]) for run in runs] == [0, 1, 2]
    cell = original_curves(AWS, 0, 3)
    # Crash Count a plane-episode over the last tenth of the budget, each seed's points weighted by their episodes
    crashes = [tail(curve, cell, "Crash Count").ours for curve in seed_curves(point)]
    assert crashes == pytest.approx([0.515, 0.432, 0.026], abs=0.001)
    band = cell.panel("Crash Count").training
    late = band.band_steps > 1_620_000
    assert band.lower[late].mean() == pytest.approx(0.025, abs=0.005)
    assert band.upper[late].mean() == pytest.approx(0.489, abs=0.005)
    read = best_of_three(AWS, 0, 3)
    tests = [run["return"]["mean"] for run in runs]
    assert tests == pytest.approx([399.6, 267.9, 420.0], abs=0.05)
    assert all(read.lowest < ours < read.published for ours in tests)


def _islands(level: int, seed: int, count: int):
    compiled = hivex_dsl.compile({"hivex": 1, "environment": AWS, "task": "main", "terrain_level": level})
    return draw_maps(np.random.default_rng(seed), count, IslandSpecs.of(compiled))


def _trees_near_sea(maps, metres: float, cell_m: float) -> int:
    """Trees of every world within ``metres`` of a sea cell, stepping along the grid's rows and columns (cells of
    ``cell_m``)."""
    near = maps.height <= 0.0
    for _ in range(int(metres // cell_m)):
        padded = np.pad(near, ((0, 0), (1, 1), (1, 1)), constant_values=True)
        near = (padded[:, 1:-1, 1:-1] | padded[:, :-2, 1:-1] | padded[:, 2:, 1:-1] | padded[:, 1:-1, :-2]
                | padded[:, 1:-1, 2:])
    return int(np.count_nonzero(maps.exists & near))


def test_level_3_draws_levels_2_and_4_s_island_at_a_height_between_theirs():
    """A terrain level only sets the height multiplier: from one seed, levels 2, 3 and 4 draw the same land and
    village, heights in the ratio of their multipliers (13 / 10, 15 / 13), and a forest (trees grow at 10-100 m)
    that grows with the level, near the coast too, where our trained planes drop their water."""
    islands = {level: _islands(level, 6000, 2) for level in (2, 3, 4)}
    land = islands[3].height > 0
    for level in (2, 4):
        np.testing.assert_array_equal(islands[level].height > 0, land)
        np.testing.assert_array_equal(islands[level].village, islands[3].village)
        ratio = height_multiplier_for_level(3) / height_multiplier_for_level(level)
        np.testing.assert_allclose(islands[3].height[land], ratio * islands[level].height[land], rtol=1e-5)
    trees = [int(islands[level].exists.sum()) for level in (2, 3, 4)]
    coast = [_trees_near_sea(islands[level], 60.0, 3.0) for level in (2, 3, 4)]
    assert trees == sorted(trees) and len(set(trees)) == 3
    assert coast == sorted(coast) and len(set(coast)) == 3
