"""benchmarks/wrm_untrained_shares.py: how the original's untrained towers shared their resources, and ours.

Facts read from the digitised pages (every cell, levels 1-10 x tasks 0-2) and measured on this toolkit's untrained
networks; the reward table's note 'The untrained towers' says what they mean:

- the original's untrained towers (the first training point, one network on the same fires in all three tasks)
  kept 0.15-0.43 of their Individual Performance and gave 0.51-1.00 of it, at every level and in every task;
- its main task learned to give about three times its Individual Performance and to keep almost nothing;
- this toolkit's untrained networks give more than twice what the original's gave and keep less than it: the
  gap the note leaves open (this test fails once the allocation mechanics meet the original's).
"""

from __future__ import annotations

import numpy as np
import pytest

from ..benchmark_scripts import benchmark_script

script = benchmark_script("wrm_untrained_shares")
CELLS = [(task, level) for task in script.TASK_WEIGHTS for level in range(1, 11)]


def test_each_paid_statistic_is_divided_by_its_task_s_weight():
    """Keep All pays keeping x10, Distribute All giving x10: 20 and 30 over an Individual Performance of 10."""
    assert script.shares(20.0, 30.0, 10.0, task=0) == (2.0, 3.0)
    assert script.shares(20.0, 30.0, 10.0, task=1) == pytest.approx((0.2, 3.0))
    assert script.shares(20.0, 30.0, 10.0, task=2) == pytest.approx((2.0, 0.3))


def test_the_original_s_untrained_towers_kept_much_and_gave_little_everywhere():
    first = {cell: script.original_first_point(*cell) for cell in CELLS}
    keeping = np.array([first[cell][0] for cell in CELLS])
    giving = np.array([first[cell][1] for cell in CELLS])
    assert keeping.min() > 0.15 and keeping.max() < 0.45
    assert giving.min() > 0.5 and giving.max() < 1.01
    for level in range(1, 11):  # one untrained network on the same fires: the three tasks' first points agree
        at_level = np.array([first[(task, level)][:2] for task in script.TASK_WEIGHTS])
        assert np.ptp(at_level[:, 0]) < 0.12 and np.ptp(at_level[:, 1]) < 0.2


def test_the_original_s_main_task_learned_to_give():
    cell = script.original_curves(script.ENVIRONMENT, 0, 1)
    steps = cell.panel(script.SELF).training.band_steps
    last = steps[steps >= 0.9 * steps.max()]

    def mean(panel: str) -> float:
        return float(cell.panel(panel).training.mean_at(last).mean())

    keeping, giving = script.shares(mean(script.SELF), mean(script.NEIGHBOURS), mean(script.INDIVIDUAL))
    assert keeping < 0.03 and 2.5 < giving < 3.5


def test_this_toolkit_s_untrained_towers_give_far_more_than_the_original_s():
    pytest.importorskip("torch")
    lowest_original_keep = min(script.original_first_point(task, 1)[0] for task in script.TASK_WEIGHTS)
    highest_original_give = max(script.original_first_point(task, 1)[1] for task in script.TASK_WEIGHTS)
    for seed in (0, 1):
        keeping, giving = script.untrained_shares(1, seed, worlds=4, decisions=400)
        assert giving > 2 * highest_original_give
        assert keeping < lowest_original_keep


def test_bad_counts_are_refused_with_exit_2(capsys):
    assert script.main(["--inits", "0"]) == 2
    assert "must be at least 1" in capsys.readouterr().err
