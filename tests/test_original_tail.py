"""The end of training pooled (hivex_dsl/evaluation/original/tail.py): by hand, on the original's WFC cell against
its event files, and as `hivex curves` and the pages print it."""

from __future__ import annotations

import json

import numpy as np
import pytest

from hivex_dsl.cli import main
from hivex_dsl.evaluation.original import compare
from hivex_dsl.evaluation.original.curves import Curve, OriginalCell, OriginalPanel, original_curves
from hivex_dsl.evaluation.original.digitise import VALUE_RESOLUTION_PT
from hivex_dsl.evaluation.original.tail import tail, tail_seeds, tail_table


def _panel(title: str, steps: np.ndarray, mean: np.ndarray) -> OriginalPanel:
    return OriginalPanel(title, None, 2, 1.0, 1.0, Curve(steps, mean, steps, mean - 5.0, mean + 5.0), None)


@pytest.fixture
def cell() -> OriginalCell:
    """A page of budget 1,000 with a summary point every 50: the return's mean step / 10, Episode Length 200 until
    900 and 300 from 950 on, and a statistic our runs do not log."""
    steps = np.arange(0, 1001, 50).astype(float)
    panels = {"Cumulative Reward": _panel("Cumulative Reward", steps, steps / 10),
              "Episode Length": _panel("Episode Length", steps, np.where(steps > 900, 300.0, 200.0)),
              "Water Pickup": _panel("Water Pickup", steps, np.ones(len(steps)))}
    return OriginalCell("aerial_wildfire_suppression", 0, 1, "made_up.pdf", "A made-up page", panels)


def _run(points, label="this toolkit"):
    return compare.from_points([{"agent_steps": s, "return": r, "episodes": e, "length": n} for s, r, e, n in points],
                               label)


def test_the_last_tenth_pools_ours_by_episodes_and_the_original_s_points_by_hand(cell):
    """Budget 1,000: the last tenth is past 900, where the original's points are 950 and 1,000 (means 95 and 100);
    ours at 950 (one episode, 90) and 1,000 (three, 110) pool to 105, the point at 900 before it and the one at
    1,050 beyond the original's budget left out."""
    run = _run([(900, 1_000.0, 5, 1.0), (950, 90.0, 1, 251.0), (1_000, 110.0, 3, 301.0), (1_050, -1_000.0, 9, 1.0)])
    end = tail(run, cell)
    assert (end.panel, end.ours, end.theirs, end.start) == ("Cumulative Reward", 105.0, 97.5, 900)
    assert end.ratio == pytest.approx(105.0 / 97.5)
    # Episode Length as ML-Agents logged it, a decision less: (250 x 1 + 300 x 3) / 4 = 287.5 against 300
    length = tail(run, cell, "Episode Length")
    assert (length.ours, length.theirs) == (287.5, 300.0) and length.ratio == pytest.approx(287.5 / 300)
    # a fifth of the budget: past 800, where the original's points are 850-1,000 (85, 90, 95, 100), and ours at 900
    wider = tail(run, cell, share=0.2)
    assert wider.start == 800 and wider.theirs == 92.5
    assert wider.ours == pytest.approx((1_000 * 5 + 90 + 110 * 3) / 9)


def test_a_run_without_a_point_there_pools_none(cell):
    early = _run([(500, 40.0, 1, 100.0), (900, 95.0, 1, 100.0)])  # its last point is at 900, not past it
    end = tail(early, cell)
    assert end.ours is None and end.ratio is None and end.theirs == 97.5
    no_lengths = compare.from_points([{"agent_steps": 1_000, "return": 1.0}])
    assert tail(no_lengths, cell, "Episode Length").ours is None  # a panel the run does not log


def test_what_cannot_be_pooled_is_refused(cell):
    run = _run([(1_000, 1.0, 1, 1.0)])
    with pytest.raises(compare.CompareError, match="draws no training band of Fire Extinguished"):
        tail(run, cell, "Fire Extinguished")
    for share in (0.0, 1.5):
        with pytest.raises(compare.CompareError, match=r"share of the original's budget in \(0, 1\]"):
            tail(run, cell, share=share)
    with pytest.raises(compare.CompareError, match="no training seed"):
        tail_seeds([], cell)


def test_every_seed_and_their_unweighted_mean_by_hand(cell):
    """Seed 0 pools 110 (three episodes), seed 1 80 (one), seed 2 has no point there: the mean is of the two seeds
    that have one, (110 + 80) / 2 = 95, whatever their episodes; the original's 97.5."""
    seeds = [_run([(1_000, 110.0, 3, 301.0)], "seed 0"), _run([(960, 80.0, 1, 201.0)], "seed 1"),
             _run([(400, 5.0, 1, 101.0)], "seed 2")]
    rows = {r.panel: r for r in tail_seeds(seeds, cell)}
    assert list(rows) == ["Cumulative Reward", "Episode Length"]  # the shared panels, the return first
    ret = rows["Cumulative Reward"]
    assert [t.ours for t in ret.seeds] == [110.0, 80.0, None] and ret.value == 95.0
    assert ret.ratio == pytest.approx(95.0 / 97.5) and ret.start == 900
    assert rows["Episode Length"].value == 250.0  # (300 + 200) / 2 against 300
    table = tail_table(list(rows.values()), ["seed 0", "seed 1", "seed 2"])
    assert "| panel | from agent-step | seed 0 | seed 1 | seed 2 | mean of seeds | original |" in table
    assert "| Cumulative Reward | 900 | 110 (1.13) | 80.00 (0.82) | - | 95.00 (0.97) | 97.50 |" in table
    assert "| Episode Length | 900 | 300 (1.00) | 200 (0.67) | - | 250 (0.83) | 300 |" in table


def test_the_last_tenth_of_the_original_wfc_cell_is_its_event_files_mean(wfc_event_runs):
    """Wind Farm Control pattern 0: the three training runs' Cumulative Reward at their 20 summary points past 7.2M,
    averaged over the runs at each point and then over the points, from the event files (4,571.7). The digitised
    mean is exact to the tick labels' resolution at the line's kept vertices and within 1/9 pt (Curve.mean_at) at
    the two the PDF dropped there (7.36M and 7.68M), so the pool is within a twentieth of each one's bound."""
    by_step: dict[float, list[float]] = {}
    for i in range(3):
        for step, value in wfc_event_runs[f"train_run_{i}"]["Environment/Cumulative Reward"]:
            if step > 7_200_000:
                by_step.setdefault(step, []).append(value)
    assert len(by_step) == 20 and all(len(values) == 3 for values in by_step.values())
    expected = float(np.mean([np.mean(values) for values in by_step.values()]))
    cell = original_curves("wind_farm_control", 0, 0)
    end = tail(compare.from_points([{"agent_steps": 8_000_000, "return": 4_600.0, "episodes": 8}]), cell)
    training, per_pt = cell.panel("Cumulative Reward").training, cell.panel("Cumulative Reward").y_per_pt
    dropped = sum(step not in training.steps for step in by_step)
    assert dropped == 2
    tolerance = ((20 - dropped) * VALUE_RESOLUTION_PT * per_pt + dropped * per_pt / 9) / 20 + 0.05  # 0.05: rounding
    assert end.theirs == pytest.approx(expected, abs=tolerance) and end.ours == 4_600.0


def test_hivex_curves_prints_the_pool_of_every_seed(tmp_path, capsys):
    """Two seeds of WFC pattern 0 flat at 5,000 and 4,000 with 5,000-decision episodes: pooled 5,000 and 4,000
    against the original's 4,571.7 (its event files; 1.09 and 0.87), their mean 4,500 (0.98); Episode Length 4,999
    as logged there, the original's 4,999 at every point."""
    runs = []
    for seed, value in ((0, 5_000.0), (1, 4_000.0)):
        run = tmp_path / f"seed{seed}"
        run.mkdir()
        (run / "curve.json").write_text(json.dumps([{"agent_steps": s, "return": value, "episodes": 8,
                                                     "length": 5_000.0} for s in range(40_000, 8_000_001, 40_000)]))
        (run / "summary.json").write_text(json.dumps({"environment": "wind_farm_control", "task_index": 0,
                                                      "level": 0, "seed": seed, "agent_steps": 8_000_000}))
        runs.append(run)
    assert main(["curves", str(runs[0]), "--with", str(runs[1])]) == 0
    pooled = capsys.readouterr().out.split("pooled over the last tenth of the original's budget")[1]
    assert "(from 7,200,000 agent-steps)" in pooled
    assert "| Cumulative Reward | 7,200,000 | 5,000 (1.09) | 4,000 (0.87) | 4,500 (0.98) | 4,572 |" in pooled
    assert "| Episode Length | 7,200,000 | 4,999 (1.00) | 4,999 (1.00) | 4,999 (1.00) | 4,999 |" in pooled
