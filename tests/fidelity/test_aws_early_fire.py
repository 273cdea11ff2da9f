"""benchmarks/aws_early_fire.py: the fire's course over the first summary points, ours against the original's."""

from __future__ import annotations

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
    """The grid record (re-trained in session 44 under the release's plane rules) measured by hand from its JSON:
    Fire too Close to City times episodes over Episode Length times episodes, the points up to 90,000 agent-steps,
    2.08, 0.00, 1.04, 0.00, 0.34, 0.34, 1.03, 2.03, 0.67 and 1.46 x 1e-4 a plane-decision at levels 1-10, against
    the original's 1.25, 2.10, 2.69, 3.13, 2.88, 4.85, 3.73, 3.11, 2.83 and 2.01 (its ten first points' means summed
    likewise, level 10's page drawing no point at 18,000, counted as 0 as the point before it): ratios 1.66, 0,
    0.39, 0, 0.12, 0.07, 0.28, 0.65, 0.24 and 0.73, median 0.26; this script agrees. The lone planes' grid, which
    fire_step_interval 22 was fitted to, read a median of 1.01 (the reward table's note 22)."""
    lines = script.report("grid record", script.grid_curves(), 90_000)
    pairs = lines[1].split(": ", 1)[1].split(";")[0].split(", ")
    ours = [float(pair.split()[-1].split("/")[0]) for pair in pairs]
    assert ours == [2.08, 0.00, 1.04, 0.00, 0.34, 0.34, 1.03, 2.03, 0.67, 1.46]
    median = float(lines[1].rsplit("median ratio ", 1)[1])
    assert median == pytest.approx(0.26, abs=0.005)


def test_a_folder_without_runs_is_a_clear_error(tmp_path, capsys):
    with pytest.raises(CompareError, match="no run of `hivex train`"):
        script.run_curves(tmp_path)
    assert script.main([str(tmp_path)]) == 2
    assert "no summary.json" in capsys.readouterr().err
