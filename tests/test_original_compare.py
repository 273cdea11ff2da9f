"""Our learning curves beside the original's: the measure at fractions of its budget, by hand and on a real cell."""

from __future__ import annotations

import json

import numpy as np
import pytest

from hivex_dsl.cli import main
from hivex_dsl.evaluation.original import compare
from hivex_dsl.evaluation.original.curves import Curve, OriginalCell, OriginalPanel, original_curves


def _line(steps, mean, half_width) -> Curve:
    steps, mean = np.asarray(steps, dtype=float), np.asarray(mean, dtype=float)
    return Curve(steps, mean, steps, mean - half_width, mean + half_width)


def _panel(title, curve) -> OriginalPanel:
    return OriginalPanel(title, None, 2, 1.0, 1.0, curve, None)


@pytest.fixture
def cell() -> OriginalCell:
    """A page of budget 1,000 with a summary point every 50: the return's mean step / 10 with a band of +-5,
    Episode Length flat at 200 +- 20, and a statistic our run does not log."""
    steps = np.arange(0, 1001, 50)
    panels = {"Cumulative Reward": _panel("Cumulative Reward", _line(steps, steps / 10, 5.0)),
              "Episode Length": _panel("Episode Length", _line(steps, np.full(len(steps), 200.0), 20.0)),
              "Water Pickup": _panel("Water Pickup", _line(steps, np.ones(len(steps)), 0.5))}
    return OriginalCell("aerial_wildfire_suppression", 0, 1, "made_up.pdf", "A made-up page", panels)


@pytest.fixture
def run() -> compare.RunCurve:
    """Points at 90 and 110 (one and three episodes), 240 and 260, 500, and 900: within half the original's summary
    interval (25) of 100, 250 and 500, and 100 from 1,000."""
    returns = {90: (12.0, 1), 110: (20.0, 3), 240: (22.0, 2), 260: (24.0, 2), 500: (40.0, 1), 900: (95.0, 1)}
    points = [{"agent_steps": s, "return": r, "episodes": e, "length": 210.0, "statistics": {"Not Logged There": 1.0}}
              for s, (r, e) in returns.items()]
    return compare.from_points(points)


def test_the_measure_by_hand(cell, run):
    rows = {(r.panel, r.fraction): r for r in compare.measure(run, cell)}
    at_10 = rows["Cumulative Reward", 0.1]
    assert (at_10.step, at_10.mean, at_10.lower, at_10.upper) == (100, 10.0, 5.0, 15.0)
    assert at_10.ours == compare.Ours((12 * 1 + 20 * 3) / 4, 90, 110) and at_10.verdict == "above"  # 18 > 15
    assert rows["Cumulative Reward", 0.25].ours.value == 23.0 and rows["Cumulative Reward", 0.25].verdict == "within"
    assert rows["Cumulative Reward", 0.5].ours.value == 40.0 and rows["Cumulative Reward", 0.5].verdict == "below"
    # 900 is 100 from 1,000: more than 25 (half the summary interval) and than 50 (5% of the budget)
    last = rows["Cumulative Reward", 1.0]
    assert last.ours == compare.Ours(None) and last.verdict == "no point"
    lengths = [rows["Episode Length", f].verdict for f in compare.FRACTIONS]
    assert lengths == ["within", "within", "within", "no point"]  # 210 in 180-220; none near 1,000


def test_only_the_panels_both_log_are_compared(cell, run):
    assert compare.shared_panels(run, cell) == ["Cumulative Reward", "Episode Length"]


def test_the_nearest_point_within_5_percent_of_the_budget_stands_in(cell):
    run = compare.from_points([{"agent_steps": 960, "return": 99.0, "episodes": 1}])
    last = [r for r in compare.measure(run, cell) if r.fraction == 1.0][0]
    assert last.ours == compare.Ours(99.0, 960, 960) and last.verdict == "within"  # 40 from 1,000: within 50


def test_a_run_that_logs_no_shared_panel_is_refused(cell):
    run = compare.RunCurve(np.array([100.0]), np.array([1.0]), {"Something Else": np.array([1.0])})
    with pytest.raises(compare.CompareError, match="none of the panels"):
        compare.measure(run, cell)


def test_a_real_cell_wind_farm_control_pattern_0():
    """The original's WFC main task, pattern 0 (ORIGINAL-DATA.md: the untrained policy earns about 840, the runs
    reach 4,160-4,350 at 2.44M agent-steps and about 4,600 by 5.6M; the budget is 8M, a summary every 40,000)."""
    cell = original_curves("wind_farm_control", 0, 0)
    steps = np.arange(40_000, 8_000_001, 40_000, dtype=float)
    for value, verdict in ((840.0, "below"), (5_000.0, "above")):
        run = compare.RunCurve(steps, np.ones_like(steps), {"Cumulative Reward": np.full(len(steps), value)})
        rows = compare.measure(run, cell)
        assert [(r.fraction, r.step) for r in rows] == [(0.1, 800_000), (0.25, 2_000_000), (0.5, 4_000_000),
                                                        (1.0, 8_000_000)]
        assert {r.verdict for r in rows} == {verdict}
        assert all(r.ours.first == r.ours.last == r.step for r in rows)  # one of our points a summary period


def _run_dir(tmp_path, points):
    run = tmp_path / "run"
    run.mkdir()
    (run / "curve.json").write_text(json.dumps(points))
    (run / "summary.json").write_text(json.dumps({"environment": "wind_farm_control", "task_index": 0, "level": 0,
                                                  "seed": 0, "agent_steps": 8_000_000}))
    return run


def test_hivex_curves_prints_the_table_and_draws_the_figure(tmp_path, capsys):
    pytest.importorskip("matplotlib")
    run = _run_dir(tmp_path, [{"agent_steps": s, "return": 5_000.0, "episodes": 8, "length": 4_999.0}
                              for s in range(40_000, 8_000_001, 40_000)])
    assert main(["curves", str(run), "-o", str(tmp_path / "curves.png")]) == 0
    out = capsys.readouterr().out
    assert "WindFarmControl_results_pattern_0_task_0.pdf" in out
    assert "| Cumulative Reward | 100% | 8,000,000 | 5,000 (8,000,000) |" in out
    assert "| Episode Length | 100% | 8,000,000 | 4,999 (8,000,000) |" in out
    assert (tmp_path / "curves.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_hivex_curves_refuses_what_is_no_run(tmp_path, capsys):
    assert main(["curves", str(tmp_path / "nowhere")]) == 2
    assert "no such run directory or baseline record" in capsys.readouterr().err
    run = _run_dir(tmp_path, [])
    assert main(["curves", str(run)]) == 2
    assert "no episode ended" in capsys.readouterr().err


def test_an_unsettled_drone_based_reforestation_page_is_asked_for():
    with pytest.raises(compare.CompareError, match="page's task index"):
        compare.original_cell("drone_based_reforestation", 3, 1)
    assert compare.original_cell("drone_based_reforestation", 3, 1, page_task=2).file.endswith("_task_2.pdf")


def test_a_record_s_other_seeds_with_curves_are_measured_too(tmp_path, capsys):
    """A record of seed 0 whose seed 1 kept its curve and whose seed 2 (added before curves were kept) did not."""
    rows = [[s, 0.0, 5_000.0] for s in range(40_000, 8_000_001, 40_000)]
    low = [[s, 0.0, 840.0] for s in range(40_000, 8_000_001, 40_000)]
    record = {"environment": "wind_farm_control", "task_index": 0, "level": 0, "seed": 0, "curve": rows,
              "other_seeds": [{"seed": 1, "curve": low}, {"seed": 2}]}
    curves = compare.seed_curves(record)
    assert [c.label for c in curves] == ["this toolkit, seed 0", "this toolkit, seed 1"]
    path = tmp_path / "wind_farm_control.json"
    path.write_text(json.dumps(record))
    assert main(["curves", str(path)]) == 0
    out = capsys.readouterr().out
    mine, seed_1 = out.split("this toolkit, seed 1:")
    assert "| Cumulative Reward | 100% | 8,000,000 | 5,000 (8,000,000) | 4,583 | 4,559 - 4,597 | above |" in mine
    assert "| Cumulative Reward | 100% | 8,000,000 | 840 (8,000,000) | 4,583 | 4,559 - 4,597 | below |" in seed_1
