"""benchmarks/aws_fire_out.py: Fire Out at the end of training beside the crashes, ours against the original's."""

from __future__ import annotations

import json

import numpy as np
import pytest

from hivex_dsl.evaluation.original.compare import CompareError, RunCurve

from ..benchmark_scripts import benchmark_script

script = benchmark_script("aws_fire_out")


def _curve(steps, episodes, fire_out, crashes) -> RunCurve:
    return RunCurve(steps=np.array(steps, dtype=float), episodes=np.array(episodes, dtype=float),
                    panels={"Fire Out": np.array(fire_out, dtype=float), "Crash Count": np.array(crashes, dtype=float)})


def test_a_plane_that_crashed_logs_no_fire_out_so_the_rate_a_plane_up_divides_by_the_planes_up():
    # 0.3 fire-outs a plane-episode with a quarter of the planes frozen: 0.3 / 0.75 a plane still up
    assert script.End(1, 0.3, 0.25).per_plane_up == pytest.approx(0.4)
    assert np.isnan(script.End(1, 0.0, 1.0).per_plane_up)


def test_ours_pools_the_last_tenth_of_the_original_s_budget_weighted_by_episodes():
    # the original's level-1 budget is 1,800,000 agent-steps: the point at 1,000,000 lies before its last tenth;
    # (1 x 1 + 0 x 3) / 4 fire-outs and (0 x 1 + 1/3 x 3) / 4 crashes a plane-episode
    curve = _curve([1_000_000, 1_700_000, 1_750_000], [5, 1, 3], [1.0, 1.0, 0.0], [1.0, 0.0, 1 / 3])
    end = script.our_end(curve, 1)
    assert (end.fire_out, end.crashes) == (pytest.approx(0.25), pytest.approx(0.25))
    assert end.per_plane_up == pytest.approx(1 / 3)


def test_a_run_that_stopped_before_the_last_tenth_is_a_clear_error():
    with pytest.raises(CompareError, match="no point in the last tenth"):
        script.our_end(_curve([500_000], [3], [0.0], [0.0]), 1)


def test_the_original_s_fire_out_follows_its_crashes_over_its_ten_levels():
    """The original's own records (its pages, last tenth of the budget): level 1, the one level whose planes kept
    crashing (0.52 a plane-episode), logs the least Fire Out (0.11); over the ten levels Fire Out falls as Crash
    Count rises (correlation -0.73), as its drops do (the reward table's note on the drops)."""
    ends = script.original_ends()
    assert [end.level for end in ends] == list(range(1, 11))
    assert min(ends, key=lambda end: end.fire_out).level == 1
    assert max(ends, key=lambda end: end.crashes).level == 1
    intercept, slope, correlation = script.line(ends)
    assert slope < 0 and correlation < -0.6
    assert ends[0].fire_out == pytest.approx(0.111, abs=0.001) and ends[0].crashes == pytest.approx(0.52, abs=0.005)


def test_a_folder_without_runs_is_a_clear_error(tmp_path, capsys):
    assert script.main([str(tmp_path)]) == 2
    assert "no finished run" in capsys.readouterr().err


def test_the_line_through_levels_is_least_squares_fire_out_on_crashes():
    # three points on Fire Out = 0.4 - 0.5 x Crash Count, and a fourth off it that pulls the fit by hand's amount
    on_line = [script.End(level, 0.4 - 0.5 * crashes, crashes) for level, crashes in ((1, 0.0), (2, 0.2), (3, 0.4))]
    assert script.line(on_line) == (pytest.approx(0.4), pytest.approx(-0.5), pytest.approx(-1.0))
    # with (0.6, 0.2) added: means 0.3 and 0.275; Sxy = -0.0375 - 0.0025 - 0.0075 - 0.0225 = -0.07 over
    # Sxx = 0.09 + 0.01 + 0.01 + 0.09 = 0.2: slope -0.35, intercept 0.275 + 0.35 x 0.3 = 0.38
    intercept, slope, _ = script.line(on_line + [script.End(4, 0.2, 0.6)])
    assert (intercept, slope) == (pytest.approx(0.38), pytest.approx(-0.35))


def test_a_ratio_over_nothing_reads_as_a_dash():
    assert script._ratio(0.3, 0.2) == "1.50"
    for nothing in (0.0, -0.04, float("nan")):  # a line read past its zero, a level whose planes all crashed
        assert script._ratio(0.3, nothing) == "-"


def _run_dir(folder, environment: str, level: int):
    folder.mkdir(parents=True)
    summary = {"environment": environment, "task_index": 0, "level": level, "seed": 0}
    (folder / "summary.json").write_text(json.dumps(summary))
    points = [{"agent_steps": 1_700_000, "return": 1.0, "episodes": 4, "length": 2_000,
               "statistics": {"Fire Out": 0.5, "Crash Count": 0.5}}]
    (folder / "curve.json").write_text(json.dumps(points))


def test_a_sweep_folder_reads_every_point_and_refuses_another_environment(tmp_path, capsys):
    _run_dir(tmp_path / "grid" / "000-a", script.ENVIRONMENT, 1)
    _run_dir(tmp_path / "grid" / "001-b", script.ENVIRONMENT, 2)
    assert script.main([str(tmp_path / "grid")]) == 0
    out = capsys.readouterr().out
    # 0.5 fire-outs with half the planes frozen: 1.0 a plane still up
    assert "000-a: Fire Out 0.500, Crash Count 0.50" in out and "a plane up 1.000" in out and "001-b:" in out
    _run_dir(tmp_path / "other", "wind_farm_control", 1)
    assert script.main([str(tmp_path / "other")]) == 2
    assert "not a run of the main task of aerial_wildfire_suppression" in capsys.readouterr().err
