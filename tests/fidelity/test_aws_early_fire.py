"""benchmarks/aws_early_fire.py: the fire's course over the first summary points, ours against the original's."""

from __future__ import annotations

import json

import numpy as np
import pytest

from hivex_dsl.evaluation.original.compare import CompareError, RunCurve

from ..benchmark_scripts import benchmark_script

script = benchmark_script("aws_early_fire")


def test_pooling_weighs_each_point_by_its_episodes_and_stops_at_the_budget():
    curve = RunCurve(steps=np.array([1_000.0, 50_000.0, 100_000.0]), episodes=np.array([1.0, 3.0, 2.0]),
                     panels={"Fire Out": np.array([1.0, 0.0, 1.0]), "Episode Length": np.array([100.0, 200.0, 300.0])})
    # (1 x 1 + 0 x 3) / (100 x 1 + 200 x 3): the point at 100,000 lies beyond the 90,000 pooled
    assert script.pooled(curve, "Fire Out", 90_000) == pytest.approx(1 / 700)
    assert script.pooled(curve, "Fire Out", 200_000) == pytest.approx(3 / 1300)


def test_the_grid_record_reads_as_measured_by_hand():
    """The grid record (re-trained in sessions 93 and 94 under the release's weather) measured by hand from its JSON:
    Fire too Close to City times episodes over Episode Length times episodes, the points up to 90,000 agent-steps,
    0.36, 1.46, 0.74, 1.48, 0.36, 2.50, 2.13, 2.75, 3.22 and 2.21 x 1e-4 a plane-decision at levels 1-10, against the
    original's 1.25, 2.10, 2.69, 3.13, 2.88, 4.85, 3.73, 3.11, 2.83 and 2.01 (its ten first points' means summed
    likewise): ratios 0.29, 0.69, 0.28, 0.47, 0.12, 0.51, 0.57, 0.88, 1.14 and 1.10, median 0.54; this script agrees.
    A plane-decision counts the planes' survival (the test below compares at equal survival). The grid of sessions
    91-92 (the release's cadence under this toolkit's weather) read a median of 0.67, the one of sessions 89-90 (the
    release's start and queue at a fire step every 17 steps) 0.46, the one of session 86 (the fire before, every 22
    steps) 0.48, the one of session 64 0.26, the one before that (the value loss clipped, a point every episode) 0.34,
    then (drops landing over the island's forest grid alone) 0.40, (the mask open to flying planes alone) 0.50, the
    per-step cast's of session 44 0.26, the lone planes' grid, which fire_step_interval 22 was fitted to, 1.01 (the
    reward table's note 22)."""
    lines = script.report("grid record", script.grid_curves(), 90_000)
    pairs = lines[1].split(": ", 1)[1].split(";")[0].split(", ")
    ours = [float(pair.split()[-1].split("/")[0]) for pair in pairs]
    assert ours == [0.36, 1.46, 0.74, 1.48, 0.36, 2.50, 2.13, 2.75, 3.22, 2.21]
    median = float(lines[1].rsplit("median ratio ", 1)[1])
    assert median == pytest.approx(0.54, abs=0.005)


def test_a_folder_without_runs_is_a_clear_error(tmp_path, capsys):
    with pytest.raises(CompareError, match="no run of `hivex train`"):
        script.run_curves(tmp_path)
    assert script.main([str(tmp_path)]) == 2
    assert "no summary.json" in capsys.readouterr().err


def test_summary_points_pool_each_interval_weighted_by_its_episodes():
    curve = RunCurve(steps=np.array([2_000.0, 9_000.0, 12_000.0, 30_000.0]), episodes=np.array([1.0, 3.0, 2.0, 1.0]),
                     panels={"Episode Length": np.array([100.0, 300.0, 500.0, 700.0])})
    points = script.summary_points(curve)
    # (0, 9,000] holds the first two, (9,000, 18,000] the third, (27,000, 36,000] the fourth
    assert points.steps.tolist() == [9_000.0, 18_000.0, 36_000.0]
    assert points.episodes.tolist() == [4.0, 2.0, 1.0]
    assert points.panels["Episode Length"].tolist() == pytest.approx([(100 + 900) / 4, 500.0, 700.0])


def test_the_mean_of_runs_weighs_each_run_once_at_the_points_they_share():
    one = RunCurve(steps=np.array([9_000.0, 18_000.0]), episodes=np.array([1.0, 5.0]),
                   panels={"Episode Length": np.array([300.0, 900.0])})
    two = RunCurve(steps=np.array([9_000.0, 18_000.0, 27_000.0]), episodes=np.array([4.0, 1.0, 2.0]),
                   panels={"Episode Length": np.array([100.0, 300.0, 500.0])})
    mean = script.mean_of_runs([one, two])
    assert mean.steps.tolist() == [9_000.0, 18_000.0]
    assert mean.panels["Episode Length"].tolist() == [200.0, 600.0]  # not weighted by the runs' episodes
    assert mean.episodes.tolist() == [1.0, 1.0]


def test_at_equal_survival_the_grids_fire_reaches_the_village_as_the_originals_does():
    """Measured by hand (an independent script: the grid's points re-pooled into 9,000-agent-step windows, binned by
    their Episode Length, the original's mean points alike) over the first 300,000 agent-steps of the ten levels (the
    grid of sessions 93-94, under the release's weather): Fire too Close to City a plane-episode 0.014, 0.077, 0.209,
    0.379, 0.505, 0.800 and 0.882 in the bins from 0 to 3,000 decisions (30, 86, 69, 55, 42, 15 and 17 points),
    against the original's 0.020, 0.075, 0.198, 0.350, 0.569, 0.757 and 0.762. From 300 to 2,600 decisions, where the
    original's points lie thickest, the two agree within 15% (1.02, 1.06, 1.08, 0.89 and 1.06 of it); below 300 ours
    is 0.72 of it and at 2,600 up 1.16 (the original's 7 points there); one ratio, the bins' geometric mean weighted by
    the original's points, 0.98 (benchmarks/aws_early_fire.py --record --by-length --steps 300000). The grid of
    sessions 91-92 (this toolkit's weather) read 1.03 as one ratio and 0.75 at 300-500 decisions, the one of sessions
    89-90 (a fire step every 17 steps) 1.07 and 1.20 at 300-800 decisions and within 11% from 800 up, the grid of
    session 86, under the fire before at 22 steps, 0.57 and 0.65 at 300-800, the ones before 0.67-0.75 at 800-1,200
    and the per-step cast's grid of session 44 0.299: the release's cadence and weather keep the early fire at the
    original's pace."""
    rows = script.by_length(script.grid_curves(), 300_000)
    assert [row[:2] for row in rows] == list(zip(script.LENGTH_EDGES[:-1], script.LENGTH_EDGES[1:]))
    assert [round(row[2], 3) for row in rows] == [0.014, 0.077, 0.209, 0.379, 0.505, 0.800, 0.882]
    assert [round(row[4], 3) for row in rows] == [0.020, 0.075, 0.198, 0.350, 0.569, 0.757, 0.762]
    assert [row[3] for row in rows] == [30, 86, 69, 55, 42, 15, 17]
    for row in rows[1:6]:
        assert row[2] == pytest.approx(row[4], rel=0.15)
    assert rows[0][2] / rows[0][4] == pytest.approx(0.72, abs=0.02)
    assert script.length_ratio(rows) == pytest.approx(0.98, abs=0.005)


def test_the_main_records_three_seeds_read_the_early_fire_as_measured_by_hand():
    """The main record's seeds (level 1, trained in session 93 under the release's weather, the default since session
    94) as the mean of their runs, as the original's page draws its three: Fire too Close to City 1.05 x 1e-4 a
    plane-decision over the first 90,000 agent-steps against the original's 1.25 (measured by hand from the record's
    JSON: each seed's points re-pooled into 9,000-agent-step windows, the nine windows all three seeds logged
    averaged, their sums divided), 0.84 of it. Those steps hold 3, 15 and 9 plane-events in 144, 231 and 261
    plane-episodes (1, 5 and 3 of the fire's arrivals, each ending a world's three plane-episodes), so one arrival
    moves the reading by about a third of the original's: the record of session 91 (this toolkit's weather) read 2.16
    (2, 6 and 5 arrivals), the one of session 89 (the release's start and queue at 17 steps) 1.13 (3, 4 and 1), the
    one of session 86 (the fire before, every 22 steps) 0.85 (1, 2 and 2), the one of session 59 0.72 (0, 2 and 1),
    the one trained with the value loss clipped 0.34 (0, 1 and 2), the one under the mask open to flying planes alone
    1.55 (6, 1 and 1) and the per-step cast's of session 43 1.00. The fire's pace is read from the ten levels (the
    tests above and the reward table's note on the release's fire start and queue), not from this one."""
    lines = script.report("main record", script.record_seeds(), 90_000)
    assert "L1 1.05/1.25" in lines[1]
    assert float(lines[1].rsplit("median ratio ", 1)[1]) == pytest.approx(0.84, abs=0.005)


def _write_run(folder, level: int, points: list[tuple[float, float, float]]) -> None:
    """A run of the main task at ``level`` whose curve holds (agent-steps, Episode Length, Fire too Close to City)
    points of 3 episodes each."""
    folder.mkdir(parents=True)
    (folder / "summary.json").write_text(json.dumps({"environment": script.ENVIRONMENT, "task_index": 0,
                                                     "level": level}))
    (folder / "curve.json").write_text(json.dumps([
        {"agent_steps": steps, "episodes": 3, "return": 1.0, "length": length,
         "statistics": {"Fire too Close to City": close}} for steps, length, close in points]))


def test_seeds_of_different_levels_are_a_clear_error(tmp_path, capsys):
    _write_run(tmp_path / "a", 1, [(9_000, 300.0, 0.0)])
    _write_run(tmp_path / "b", 2, [(9_000, 300.0, 0.0)])
    assert script.main(["--seeds", "--by-length", str(tmp_path / "a"), str(tmp_path / "b")]) == 2
    assert "levels [1]; levels [2]" in capsys.readouterr().err


def test_sweeps_as_seeds_average_each_level_over_its_runs(tmp_path):
    """Two seeds' sweeps of levels 1 and 2: each level's mean weighs each run once (level 1 at 9,000 agent-steps:
    Episode Length (300 + 700) / 2 = 500, Fire too Close to City (0 + 1) / 2), so the by-length table puts one
    level-1 point of 0.5 in the 500-800 bin where neither run lies."""
    for seed, (length, close) in enumerate(((300.0, 0.0), (700.0, 1.0))):
        sweep = tmp_path / f"s{seed}"
        _write_run(sweep / "000-level=1", 1, [(9_000, length, close)])
        _write_run(sweep / "001-level=2", 2, [(9_000, 100.0, 0.0)])
    means = script.seeds_by_level([tmp_path / "s0", tmp_path / "s1"])
    assert sorted(means) == [1, 2]
    assert means[1].panels["Episode Length"].tolist() == [500.0]
    assert means[1].panels["Fire too Close to City"].tolist() == [0.5]
    rows = {row[0]: row for row in script.by_length(means, 9_000)}
    assert rows[500.0][2:4] == (0.5, 1) and rows[0.0][2:4] == (0.0, 1)


def test_the_length_ratio_weighs_each_bin_by_the_original_s_points_and_leaves_out_empty_ones():
    """Bins of ratio 2 (the original's 3 points) and 1/2 (its 1 point): exp((3 ln 2 - ln 2) / 4) = 2 ** 0.5; a bin
    where ours logged no event, one where ours has no point and one where the original has none are left out."""
    rows = [(0.0, 300.0, 0.2, 5, 0.1, 3), (300.0, 500.0, 0.1, 4, 0.2, 1), (500.0, 800.0, 0.0, 2, 0.3, 9),
            (800.0, 1_200.0, float("nan"), 0, 0.4, 9), (1_200.0, 1_800.0, 0.5, 3, float("nan"), 0)]
    assert script.length_ratio(rows) == pytest.approx(2 ** 0.5)
    assert np.isnan(script.length_ratio(rows[2:]))
