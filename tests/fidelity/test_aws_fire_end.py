"""benchmarks/aws_fire_end.py: how much of the island the fire has burnt when it goes out."""

from __future__ import annotations

import numpy as np
import pytest

from ..benchmark_scripts import benchmark_script

script = benchmark_script("aws_fire_end")


def test_shares_count_every_tree_and_no_empty_cell():
    # states: 0 none, 1 existing, 2 burning, 3 burnt, 4 wet; six trees, three of them burnt
    trees = np.array([[0, 1, 2], [3, 4, 3], [3, 0, 0]], dtype=np.uint8)
    assert script.shares(trees) == (pytest.approx(3 / 6), pytest.approx(1 / 6), pytest.approx(1 / 6),
                                     pytest.approx(1 / 6))


def test_a_fire_that_cannot_spread_goes_out_on_its_own_island_and_is_read_before_the_reset():
    """No try ignites (spread chance 0), a fire step every step and the fire out after one quiet step: the start's
    trees burn and the fire is out within a few steps; the shares read then are of that island, nearly all its trees
    standing and some burning, and sum to one."""
    params = {"spread_chance_per_factor": 0.0, "fire_cadence": "interval", "fire_step_interval": 1,
              "quiet_steps_out": 1}
    ends = script.play(1, 1, params, policy="random", episode_length=200)
    (end,) = ends
    assert end.went_out and 0 < end.out_step <= 5
    assert end.burnt + end.wet + end.standing + end.burning == pytest.approx(1.0)
    assert end.standing > 0.99 and end.burning > 0


def test_the_report_ranges_the_shares_of_the_episodes_out_and_the_others():
    ends = [script.FireEnd(900, 0.85, 0.1, 0.02, 0.0), script.FireEnd(-1, 0.5, 0.1, 0.3, 0.1),
            script.FireEnd(1500, 0.95, 0.04, 0.01, 0.0)]
    lines = script.report(6, ends)
    assert lines[0] == "L6 episode 0: out at step 900, burnt 0.85, wet 0.10, standing 0.02"
    assert lines[1].startswith("L6 episode 1: not out")
    assert lines[-1] == ("L6: out in 2 of 3 episodes, with 85%-95% burnt and 1%-2% standing; the others end with "
                         "50%-50% burnt and 30%-30% standing")


def test_a_grid_without_the_level_is_a_clear_error(tmp_path, capsys):
    assert script.main(["--grid", str(tmp_path), "--levels", "3", "--episodes", "1"]) == 2
    assert "expected one run of terrain level 3" in capsys.readouterr().err
