"""Our learning curves beside the original's: the measure at fractions of its budget, by hand and on a real cell."""

from __future__ import annotations

import json

import numpy as np
import pytest

from hivex_dsl.cli import main
from hivex_dsl.evaluation.original import compare
from hivex_dsl.evaluation.original.curves import Curve, OriginalCell, OriginalPanel, original_curves
from hivex_dsl.evaluation.original.digitise import VALUE_RESOLUTION_PT
from hivex_dsl.evaluation.original.runs import read_run
from hivex_dsl.evaluation.original.seeds import (among_seeds, among_tally, among_words, band_over_range,
                                                 exchangeable_shares, measure_seeds, seeds_table, shared_swings,
                                                 swings_words)


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


def test_our_episodes_are_measured_as_ml_agents_logged_them():
    """ML-Agents' AgentProcessor counts every experience but the terminal one toward Environment/Episode Length, so
    Wind Farm Control's episodes of 5,000 decisions log 4,999 at every point of the original's event files: ours of
    5,000 decisions measure within that collapsed band, where 5,000 set beside it raw lay above it."""
    steps = np.arange(0, 1001, 50)
    flat = lambda value: _panel("Episode Length", _line(steps, np.full(len(steps), value), 0.0))  # noqa: E731
    cell = OriginalCell("wind_farm_control", 0, 0, "made_up.pdf", "A made-up page",
                        {"Cumulative Reward": _panel("Cumulative Reward", _line(steps, steps / 10, 5.0)),
                         "Episode Length": flat(4_999.0)})
    run = compare.from_points([{"agent_steps": s, "return": 0.0, "length": 5_000.0} for s in steps])
    rows = [r for r in compare.measure(run, cell) if r.panel == "Episode Length"]
    assert [(r.ours.value, r.verdict) for r in rows] == [(4_999.0, "within")] * 4
    assert compare.as_logged_there("Water Pickup", np.array([3.0])) == 3.0  # sums are logged as they are


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


def _run_dir(tmp_path, points, seed=0):
    run = tmp_path / "run"
    run.mkdir(parents=True)
    (run / "curve.json").write_text(json.dumps(points))
    (run / "summary.json").write_text(json.dumps({"environment": "wind_farm_control", "task_index": 0, "level": 0,
                                                  "seed": seed, "agent_steps": 8_000_000}))
    return run


def test_hivex_curves_prints_the_table_and_draws_the_figure(tmp_path, capsys):
    pytest.importorskip("matplotlib")
    run = _run_dir(tmp_path, [{"agent_steps": s, "return": 5_000.0, "episodes": 8, "length": 5_000.0}
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


def _unfinished_run_dir(tmp_path, name, scenario, seed, points):
    """A run directory as `hivex train` leaves it while training: config.json, and curve.json once it checkpointed."""
    import hivex_dsl

    run = tmp_path / name
    run.mkdir()
    resolved = hivex_dsl.compile(scenario).resolved()
    (run / "config.json").write_text(json.dumps({"hyperparameters": {"seed": seed}, "scenario": resolved}))
    if points is not None:
        (run / "curve.json").write_text(json.dumps(points))
    return run


WFC_MAIN = {"hivex": 1, "environment": "wind_farm_control", "task": 0, "pattern": 0, "agents": 8,
            "episode_length": 5000, "seeds": {"train": 5000, "test": 6000}}


def test_a_run_still_training_is_measured_to_its_last_checkpoint(tmp_path, capsys):
    """No summary.json yet: the cell comes from its config.json's scenario, the curve from its last checkpoint."""
    points = [{"agent_steps": s, "return": 840.0, "episodes": 1, "length": 5_000.0} for s in range(40_000, 800_001,
                                                                                                     40_000)]
    run = _unfinished_run_dir(tmp_path, "run", WFC_MAIN, 2, points)
    read = read_run(run)
    assert (read.environment, read.task_index, read.level) == ("wind_farm_control", 0, 0)
    assert read.curve.label == "this toolkit, seed 2 (unfinished)" and read.curve.last_step == 800_000
    assert main(["curves", str(run)]) == 0
    out = capsys.readouterr().out
    assert ("this toolkit, seed 2 (unfinished) against the original's WindFarmControl_results_pattern_0_task_0.pdf"
            in out)
    assert "this run 800,000" in out
    assert "| Cumulative Reward | 10% | 800,000 | 840 (800,000) |" in out  # below the original's band there
    assert "| Cumulative Reward | 25% | 2,000,000 | - |" in out  # not trained so far yet


def test_a_run_that_has_not_checkpointed_says_so(tmp_path, capsys):
    run = _unfinished_run_dir(tmp_path, "run", WFC_MAIN, 0, None)
    assert main(["curves", str(run)]) == 2
    assert "still training" in capsys.readouterr().err


def test_hivex_curves_measures_other_seeds_runs_given_with_it(tmp_path, capsys):
    """Three seeds' run directories: each measured, then their mean against the band, by hand."""
    steps = range(40_000, 8_000_001, 40_000)
    runs = [_run_dir(tmp_path / str(seed), [{"agent_steps": s, "return": value, "episodes": 8, "length": 5_000.0}
                                            for s in steps], seed)
            for seed, value in ((0, 5_000.0), (1, 4_000.0), (2, 4_300.0))]
    args = ["curves", str(runs[0]), "--with", str(runs[1]), "--with", str(runs[2])]
    assert main(args) == 0
    out = capsys.readouterr().out
    assert out.count("| Cumulative Reward | 100% |") == 4  # seed 0, the two given with it, and the mean
    assert "| seed 0 | seed 1 | seed 2 | mean of seeds |" in out
    both = out.split("every seed and their mean:")[1]
    # (5,000 + 4,000 + 4,300) / 3 = 4,433: below the original's band of 4,559 - 4,597 at 100%
    assert "| 4,433 | 4,583 | 4,559 - 4,597 | below | within |" in both  # 4,583 lies in 4,000-5,000
    # Episode Length: every seed 4,999 as the original logs, the ends of the range included
    assert "| Episode Length | 100% |" in both and "| 4,999 | 4,999 | 4,999 - 4,999 | within | within |" in both
    # the original's 2,298 and 3,828 at 10 and 25% lie below all of 4,000-5,000; its 4,475 and 4,583 within
    assert "within their range at 6, below all at 2, above all at 0 (one more seed drawn as ours were: 50%" in both
    assert "swings" not in both  # flat curves have none to share


def test_hivex_curves_refuses_a_seed_of_another_cell(tmp_path, capsys):
    wfc = _run_dir(tmp_path, [{"agent_steps": 40_000, "return": 1.0, "episodes": 8, "length": 5_000.0}])
    other = _unfinished_run_dir(tmp_path, "other", {**WFC_MAIN, "pattern": 1}, 1,
                                [{"agent_steps": 40_000, "return": 1.0, "episodes": 8, "length": 5_000.0}])
    assert main(["curves", str(wfc), "--with", str(other)]) == 2
    assert "--with takes other seeds of the same cell" in capsys.readouterr().err


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
    seed_1, both = seed_1.split("every seed and their mean:")
    assert "| seed 0 | seed 1 | mean of seeds |" in both  # (5,000 + 840) / 2 = 2,920: below
    assert ("| Cumulative Reward | 100% | 8,000,000 | 5,000 (8,000,000), above | 840 (8,000,000), below | 2,920 | 4,583 "
            "| 4,559 - 4,597 | below |") in both


def test_a_fraction_outside_the_budget_is_refused(cell, run):
    for fractions in ((1.5,), (0.0,), ()):
        with pytest.raises(compare.CompareError, match=r"each in \(0, 1\]"):
            compare.measure(run, cell, fractions)


@pytest.fixture
def seeds() -> list[compare.RunCurve]:
    """Three seeds of the made-up cell (band at 100: 5-15; at 1,000: 95-105): seed 0 pools 10 and 26 (one episode
    each) near 100 and ends at 104; seed 1 logs 6 at 100 and ends at 110; seed 2 logs only 90 at 1,000."""
    def run(points, seed):
        return compare.from_points([{"agent_steps": s, "return": r, "episodes": 1} for s, r in points],
                                   f"this toolkit, seed {seed}")
    return [run([(95, 10.0), (105, 26.0), (1000, 104.0)], 0), run([(100, 6.0), (1000, 110.0)], 1),
            run([(1000, 90.0)], 2)]


def test_every_seed_and_their_mean_against_the_band_by_hand(cell, seeds):
    rows = {r.fraction: r for r in measure_seeds(seeds, cell) if r.panel == "Cumulative Reward"}
    at_10 = rows[0.1]
    assert [o.value for o in at_10.seeds] == [18.0, 6.0, None]  # (10 + 26) / 2; seed 2 has no point within 50
    assert at_10.value == 12.0 and at_10.verdict == "within"  # (18 + 6) / 2 in 5-15, though seed 0 alone is above
    last = rows[1.0]
    assert last.value == pytest.approx((104 + 110 + 90) / 3) and last.verdict == "within"
    assert [compare.verdict(o.value, last.lower, last.upper) for o in last.seeds] == ["within", "above", "below"]
    assert rows[0.25].value is None and rows[0.25].verdict == "no point"  # no seed within 50 of 250
    # the original's mean (10 at 100, 100 at 1,000) among the seeds: 6-18 holds 10; 90-110 holds 100
    assert at_10.among == "within" and last.among == "within" and rows[0.25].among == "too few seeds"
    assert among_tally(list(rows.values())) == {"within": 2, "below all": 0, "above all": 0}
    # the band's width over the seeds' range: 10 / (18 - 6) at 10%, 10 / (110 - 90) at 100%; their median
    assert band_over_range(list(rows.values())) == pytest.approx((10 / 12 + 10 / 20) / 2)
    assert band_over_range([rows[0.25]]) is None  # no seed there, so no range
    assert among_words(list(rows.values()), 3).startswith(
        "the original's mean among our 3 seeds, at the 2 points where two or more have a value: within their range "
        "at 2, below all at 0, above all at 0 (one more seed drawn as ours were: 50%, 25% and 25% of points")
    table = seeds_table(list(rows.values()), ["seed 0", "seed 1", "seed 2"])
    assert "| panel | budget | agent-step | seed 0 | seed 1 | seed 2 | mean of seeds |" in table
    assert ("| Cumulative Reward | 10% | 100 | 18.00 (95-105), above | 6.00 (100), within | - | 12.00 | 10.00 | "
            "5.00 - 15.00 | within | within |") in table
    assert "| Cumulative Reward | 25% | 250 | - | - | - | - | 25.00 | 20.00 - 30.00 | no point | too few seeds |" in table


def test_where_the_original_falls_among_the_seeds_by_hand():
    assert among_seeds(146.0, [397.0, 157.0, 248.0]) == "below all"  # OPC's Episode Length at 50%, by hand
    assert among_seeds(400.0, [397.0, 157.0, None]) == "above all"
    assert among_seeds(157.0, [397.0, 157.0, 248.0]) == "within"  # the range's ends belong to it
    assert among_seeds(4999.0, [4999.0, 4999.0]) == "within"  # a panel every run logs alike
    assert among_seeds(10.0, [12.0, None, None]) == "too few seeds"  # one value has no range
    # n + 1 exchangeable draws: each is the lowest with chance 1 / (n + 1); three seeds hold the fourth half the time
    assert exchangeable_shares(3) == {"within": 0.5, "below all": 0.25, "above all": 0.25}
    assert sum(exchangeable_shares(5).values()) == pytest.approx(1.0) and exchangeable_shares(2)["within"] == 1 / 3
    with pytest.raises(compare.CompareError, match="two seeds or more"):
        exchangeable_shares(1)


def _swinging(steps, trend_slope, swing, panel=compare.RETURN) -> compare.RunCurve:
    """A run whose ``panel`` is a straight trend plus ``swing`` (n,) at ``steps``."""
    steps = np.asarray(steps, dtype=float)
    return compare.RunCurve(steps, np.ones(len(steps)), {panel: trend_slope * steps / 1000 + swing})


def test_shared_swings_by_hand():
    steps = np.arange(60) * 1000
    swing = np.where(np.arange(60) % 2 == 0, 5.0, -5.0)  # every other point up, then down
    # a straight trend is its own running mean: the swings about it are the same whatever the slope
    same = [_swinging(steps, 2.0, swing), _swinging(steps, -1.0, swing), _swinging(steps, 0.0, swing)]
    assert shared_swings(same) == pytest.approx(1.0)
    assert swings_words(same).startswith("their return's swings from point to point correlate at 1.00 between seeds")
    # pairs 1, -1 and -1: their median
    assert shared_swings([*same[:2], _swinging(steps, 0.0, -swing)]) == pytest.approx(-1.0)
    # a seed logged twice as often is read at the first seed's steps, where its points agree with the first's
    finer = np.arange(119) * 500
    finer_swing = np.where(finer % 1000 == 0, np.where(finer % 2000 == 0, 5.0, -5.0), 0.0)
    assert shared_swings([same[0], _swinging(finer, 0.0, finer_swing)]) == pytest.approx(1.0)
    assert shared_swings([same[0], _swinging(steps, 0.0, np.zeros(60))]) is None  # no swing: no correlation
    assert swings_words([same[0], _swinging(steps, 0.0, np.zeros(60))]) == ""
    rng = np.random.default_rng(3)
    own = [_swinging(np.arange(500) * 1000, 1.0, rng.normal(size=500)) for _ in range(3)]
    assert abs(shared_swings(own)) < 0.15  # swings of their own: no more shared than chance
    assert shared_swings(same[:1]) is None  # one seed shares with none
    assert shared_swings([_swinging(steps[:26], 0.0, swing[:26])] * 2) is None  # under 3 windows of points
    assert shared_swings([same[0], _swinging(steps, 0.0, swing, panel="Episode Length")]) is None


def test_the_exchangeable_shares_hold_for_draws_of_one_distribution():
    rng = np.random.default_rng(7)
    draws = rng.normal(size=(20_000, 4))  # three seeds and one more run, all drawn alike
    found = [among_seeds(row[3], row[:3]) for row in draws]
    for word, share in exchangeable_shares(3).items():
        assert found.count(word) / len(found) == pytest.approx(share, abs=0.015)


def test_a_record_marked_stale_is_labelled_so():
    assert compare.is_stale({"note": "Stale (issue 52): trained with planes flying 5 m a step"})
    assert compare.is_stale({"note": "STALE since the dynamics changed (issue 52)"})
    assert compare.is_stale({"note": "Levels 2 and 10 match. Stale since issue 52: planes now fly 3 m a step"})
    assert not compare.is_stale({"note": "Under the dynamics of issue 52; not stale"})
    assert not compare.is_stale({"note": "Trained again, so this record is not stale. Stalemate aside."})
    assert not compare.is_stale({})
    rows = [[s, 0.0, 100.0] for s in (40_000, 80_000)]
    record = {"environment": "wind_farm_control", "seed": 0, "curve": rows, "note": "Stale (test): before a change",
              "other_seeds": [{"seed": 1, "curve": rows}]}
    curves = compare.seed_curves(record)
    assert [(c.label, c.stale) for c in curves] == [("this toolkit, seed 0 (stale record)", True),
                                                   ("this toolkit, seed 1 (stale record)", True)]
    assert not any(c.stale for c in compare.seed_curves(record | {"note": "fresh"}))


def test_the_original_wfc_cell_holds_its_event_files_facts():
    """The facts the event files give (ORIGINAL-DATA.md; ../shared/paper/original-wfc-event-scalars.json): the three
    runs' first points 838.1, 839.8 and 846.9, at 2.44M agent-steps 4,160.8, 4,286.6 and 4,351.9, budget 8M, and the
    policy's entropy first at 1.0961 (uniform over 3 actions: log 3 = 1.0986), in the shipped mean and band."""
    cell = original_curves("wind_farm_control", 0, 0)
    panel = cell.panel("Cumulative Reward")
    training, tolerance = panel.training, VALUE_RESOLUTION_PT * panel.y_per_pt + 0.05  # the facts' 0.1 rounding
    assert training.last_step == 8_000_000
    for step, runs in ((40_000, (838.1, 839.8, 846.9)), (2_440_000, (4160.8, 4286.6, 4351.9))):
        i = int(np.searchsorted(training.band_steps, step))
        assert training.band_steps[i] == step
        assert training.mean_at(step) == pytest.approx(sum(runs) / 3, abs=tolerance)
        assert (training.lower[i], training.upper[i]) == pytest.approx((min(runs), max(runs)), abs=tolerance)
    entropy = cell.panel("Entropy")
    assert entropy.training.mean_at(40_000) == pytest.approx(1.0961, abs=VALUE_RESOLUTION_PT * entropy.y_per_pt + 5e-5)


def test_a_record_keeps_every_panel_of_its_curve_and_gives_it_back(cell, run):
    """The fixture run (points at 90 and 110 of one and three episodes, lengths 210) kept as a record keeps it: the
    return in ``curve`` rows, the episodes and the other panels beside them; measured as the run itself is."""
    rows = [[int(s), 0.0, float(r)] for s, r in zip(run.steps, run.panels["Cumulative Reward"])]
    kept = compare.record_panels(run)
    assert kept["curve_episodes"] == [1, 3, 2, 2, 1, 1]
    assert kept["curve_panels"] == {"Episode Length": [210.0] * 6, "Not Logged There": [1.0] * 6}
    again = compare.from_record({"environment": "aerial_wildfire_suppression", "seed": 0, "curve": rows} | kept)
    assert [(r.panel, r.fraction, r.ours) for r in compare.measure(again, cell)] == \
        [(r.panel, r.fraction, r.ours) for r in compare.measure(run, cell)]
    at_10 = [r for r in compare.measure(again, cell) if r.fraction == 0.1]
    # 210 decisions an episode, logged as ML-Agents logs them: 209
    assert [(r.panel, r.ours.value) for r in at_10] == [("Cumulative Reward", 18.0), ("Episode Length", 209.0)]
    # a record of before (the return only) weighs every point alike: (12 + 20) / 2 at 10%
    plain = compare.from_record({"environment": "aerial_wildfire_suppression", "curve": rows})
    assert compare.measure(plain, cell)[0].ours.value == 16.0 and list(plain.panels) == ["Cumulative Reward"]
    with pytest.raises(compare.CompareError, match="curve_episodes of another length than its 6 curve rows"):
        compare.from_record({"environment": "x", "curve": rows, "curve_episodes": [1]})


def _synchronous_run(budget_steps: float = 1.8e6) -> compare.RunCurve:
    """Worlds that end together every 108,000 agent-steps (36 plane-episodes at 600 each), two crashes between."""
    steps = np.array([0.0, 50_000.0, 60_000.0, 108_000.0, 216_000.0])
    episodes = np.array([36.0, 1.0, 1.0, 36.0, 36.0])
    returns = np.array([600.0, -100.0, -100.0, 600.0, 600.0])
    return compare.RunCurve(steps, episodes, {compare.RETURN: returns})


def test_a_window_between_synchronous_ends_widens_to_a_full_point():
    """At 54,000 agent-steps the original's 9,000-step window holds one crash (-100). Half a full point is 18
    episodes (the 95th percentile of the points is 36), first reached with the point at 108,000, 54,000 away: the
    pool is then every point within 54,000, (2 x 36 x 600 - 2 x 100) / 74 = 581.08."""
    ours = compare.ours_at(_synchronous_run(), compare.RETURN, 54_000, 9_000, 1.8e6)
    assert ours.value == pytest.approx((2 * 36 * 600 - 2 * 100) / 74)
    assert (ours.first, ours.last) == (0, 108_000)
    # no wider than 5% of the budget: with a budget of 500,000 (25,000) the window stays the original's
    assert compare.ours_at(_synchronous_run(), compare.RETURN, 54_000, 9_000, 5e5).value == -100.0
    # a window that already holds a full point pools it alone
    assert compare.ours_at(_synchronous_run(), compare.RETURN, 110_000, 9_000, 1.8e6).value == 600.0


def test_the_original_s_test_average_of_a_paper_cell(wfc_event_runs):
    """The average sheet's value of a cell (what `hivex evaluate` sets beside our Episode Length): for WFC pattern 0
    the mean of its three test runs' every summary point in the event files, to the printed decimal."""
    for tag in ("Environment/Episode Length", "Environment/Cumulative Reward"):
        points = [value for run in ("test_run_0", "test_run_1", "test_run_2") for _, value in wfc_event_runs[run][tag]]
        average = compare.original_test_average("wind_farm_control", 0, 0, tag)
        assert average == pytest.approx(np.mean(points), abs=0.05), tag
    assert compare.original_test_average("wind_farm_control", 0, 0, "Environment/No Such Tag") is None
    assert compare.original_test_average("ocean_plastic_collection", 0, None, "Environment/Episode Length") < 999
    # the pages' "Task: 2" of DBR is not the paper's task 2 (issue 52 item 11), so no value is lent to it
    assert compare.original_test_average("drone_based_reforestation", 2, 1, "Environment/Episode Length") is None
    assert compare.original_test_average("drone_based_reforestation", 0, 1, "Environment/Episode Length") <= 399


def test_a_small_value_keeps_two_significant_digits_in_the_tables():
    """A curiosity loss of 0.0053 would read 0.01 at two decimals, and the original's 0.0026 0.00."""
    assert [compare.number(v) for v in (0.0053, 0.0026, -0.012, 0.0, 0.5, 4.25, 1234.5)] == [
        "0.0053", "0.0026", "-0.012", "0.00", "0.50", "4.25", "1,234"]
