"""benchmarks/wrm_untrained_shares.py: how the original's untrained towers shared their resources, and ours.

Facts read from the digitised pages (every cell, levels 1-10 x tasks 0-2) and measured on this toolkit's untrained
networks; the reward table's note 'The untrained towers' says what they mean:

- the original's untrained towers (the first training point, one network on the same fires in all three tasks)
  kept 0.15-0.43 of their Individual Performance and gave 0.51-1.00 of it, at every level and in every task;
- its main task at level 1 learned to give about three times its Individual Performance and to keep almost nothing;
- trained (own_term_weight 'kept', the default since session 79), this toolkit's towers give as the published in
  Distribute All and learn to give in the main task at every level, keeping less than the original's; Keep All
  keeps a little more than the published;
- under the terms as this project read them until session 74 (P r_self^2, the neighbours' summed P times the share
  given), this toolkit's untrained networks gave more than twice what the original's gave and kept less; with the
  terms reading what the towers hold (P times the share held, in sessions 77-78 the share allocated, times r_self,
  and since session 79 P r_self; each neighbour's P times its share held times the share given it) they keep and
  give what the original's did (the reward table's note 'The terms read what the towers hold').
"""

from __future__ import annotations

import numpy as np
import pytest

from ..benchmark_scripts import benchmark_script
from ..untrained import untrained_checkpoint

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


def test_the_original_s_main_task_runs_end_keeping_at_some_levels():
    """Over the last tenth of training the original's main task keeps almost nothing at level 1, but at four levels
    its band's upper edge (about its highest run of three) keeps a fifth or more, at level 2 about half; Keep All
    keeps about 0.85 and Distribute All almost nothing at every level."""
    trained = {(task, level): script.original_trained_keeping(task, level) for task, level in CELLS}
    main = {level: trained[(0, level)] for level in range(1, 11)}
    assert main[1][2] < 0.03 and main[2][2] > 0.4
    assert [level for level, (_, _, upper, _) in main.items() if upper > 0.2] == [2, 3, 9, 10]
    assert all(lower <= keeping <= upper for keeping, lower, upper, _ in trained.values())
    assert all(0.82 < trained[(1, level)][0] < 0.87 and trained[(2, level)][0] < 0.03 for level in range(1, 11))


def test_recorded_keeping_reads_the_last_tenth_of_a_curve():
    """Ten points, the last holding Self 2 of Individual Performance 8 in task 0 and Self 30 of 10 in Keep All (x10);
    a point without an episode (None) counts for nothing."""
    panels = {script.SELF: [5.0] * 9 + [2.0], script.INDIVIDUAL: [1.0] * 9 + [8.0]}
    assert script.recorded_trained_keeping(panels, 0) == pytest.approx(0.25)
    panels = {script.SELF: [None] * 18 + [30.0, None], script.INDIVIDUAL: [None] * 18 + [10.0, None]}
    assert script.recorded_trained_keeping(panels, 1) == pytest.approx(0.3)


def test_a_grid_point_s_keeping_is_read_for_each_of_its_seeds():
    """A point of Self 1 of Individual Performance 4 and another seed of Self 3 of 4 (one point each)."""
    point = {"curve_panels": {script.SELF: [1.0], script.INDIVIDUAL: [4.0]},
             "other_seeds": [{"curve_panels": {script.SELF: [3.0], script.INDIVIDUAL: [4.0]}}]}
    assert script.grid_trained_keeping(point, 0) == pytest.approx([0.25, 0.75])
    assert script.grid_trained_keeping({"curve_panels": point["curve_panels"]}, 0) == pytest.approx([0.25])


def test_towers_gather_on_the_centre_the_one_neighbour_of_all_eight_others(tmp_path):
    """Every tower but the centre has the centre among its three neighbours (the process figure draws a corner's
    three: its two edges and the centre), so under an untrained network's near-uniform play the centre holds the
    most; a tower keeps no more than it holds, and the nine hold together what the agents allocated (at most 8.1)."""
    from hivex_dsl.envs.wildfire_resource_management.resources import NEIGHBOURS

    assert all(4 in NEIGHBOURS[tower] for tower in range(9) if tower != 4)
    checkpoint = untrained_checkpoint(tmp_path / "c.pt", short(script.ENVIRONMENT, 60))
    kept, held = script.tower_holdings(str(checkpoint), episodes=2)
    assert kept.shape == held.shape == (9,)
    assert held.argmax() == 4 and (kept <= held + 1e-12).all() and 0 < held.sum() <= 8.1 + 1e-9


def original_range_over_every_cell() -> tuple[np.ndarray, np.ndarray]:
    """((lowest, highest) keeping, (lowest, highest) giving) of the original's untrained point over all 30 cells."""
    first = np.array([script.original_first_point(*cell)[:2] for cell in CELLS])
    return np.array([first[:, 0].min(), first[:, 0].max()]), np.array([first[:, 1].min(), first[:, 1].max()])


def test_this_toolkit_s_untrained_towers_keep_and_give_as_the_original_s():
    """At level 1 the original's three first points keep 0.16-0.22 and give 0.68-0.72; over its 30 cells 0.15-0.43
    and 0.51-1.00. Ours (two training seeds' networks) keep within that range and give within a tenth of it."""
    pytest.importorskip("torch")
    keep_range, give_range = original_range_over_every_cell()
    for seed in (0, 1):
        keeping, giving = script.untrained_shares(1, seed, worlds=4, decisions=400)
        assert keep_range[0] < keeping < keep_range[1]
        assert give_range[0] < giving < give_range[1] + 0.1


def test_under_the_terms_as_printed_the_untrained_towers_gave_their_resources_away():
    pytest.importorskip("torch")
    lowest_original_keep = min(script.original_first_point(task, 1)[0] for task in script.TASK_WEIGHTS)
    highest_original_give = max(script.original_first_point(task, 1)[1] for task in script.TASK_WEIGHTS)
    for seed in (0, 1):
        keeping, giving = script.untrained_shares(1, seed, worlds=4, decisions=400, params=script.AS_PRINTED)
        assert giving > 2 * highest_original_give
        assert keeping < lowest_original_keep


def test_trained_towers_here_give_as_the_published_and_keep_all_keeps_a_little_more():
    """The committed 30-point grid (own_term_weight 'kept', session 79) against the published cell of the same task and
    level (test episodes) and the original's curves (the last tenth of training): Distribute All keeps almost nothing
    as published; Keep All keeps more than the published at every level, by under a tenth (under 'allocated_kept' it
    kept less at every level: a tenth given raised the allocated share the own term paid for); the main task learns
    to give at every level, its three seeds keeping most at level 9 as the original's runs keep most at levels 2, 9 and
    10, but less than the original's on average (levels 2-4 keep 0.11-0.29 there and 0.05 or less here)."""
    import json
    from pathlib import Path

    from hivex_dsl.evaluation.published import cell

    grid = Path(__file__).resolve().parents[2] / "benchmarks" / "baselines" / "grids" / f"{script.ENVIRONMENT}.json"
    points = {(p["task_index"], p["level"]): p for p in json.loads(grid.read_text())["points"]}
    assert sorted(points) == sorted(CELLS)

    def measured(means: dict, task: int) -> tuple[float, float]:
        mean = {name.split("/")[-1]: value for name, value in means.items()}
        return script.shares(mean[script.SELF], mean[script.NEIGHBOURS], mean[script.INDIVIDUAL], task)

    for level in range(1, 11):
        ours = {task: measured({name: value["mean"] for name, value in points[(task, level)]["statistics"].items()},
                               task) for task in script.TASK_WEIGHTS}
        published = {task: measured({name: mean for name, (mean, _) in cell(script.ENVIRONMENT, task, level)
                                     .statistics.items()}, task) for task in script.TASK_WEIGHTS}
        assert published[1][0] < ours[1][0] < published[1][0] + 0.1 and ours[1][1] < 0.2, (level, ours[1], published[1])
        assert ours[2][0] < 0.05 and ours[2][1] > 1.8 and published[2][0] < 0.02, (level, ours[2], published[2])
    seeds = [script.grid_trained_keeping(points[(0, level)], 0) for level in range(1, 11)]
    main_ours = np.array([np.mean(keeping) for keeping in seeds])
    main_theirs = np.array([script.original_trained_keeping(0, level)[0] for level in range(1, 11)])
    assert main_ours.max() < 0.1 and main_ours.mean() < main_theirs.mean() / 2
    highest_theirs = set(np.argsort(main_theirs)[-3:] + 1)
    assert highest_theirs == {2, 9, 10} and int(np.argmax(main_ours)) + 1 == 9
    # like with like: the original's three runs agree (its band about its lowest and highest run), and so do our three
    # seeds a level: their range is narrower than its band at five levels of ten and never wider than 0.13 (two seeds
    # under 'held_kept': wider at eight, seeds wandering 0.02-0.52 at level 7)
    assert all(len(keeping) == 3 for keeping in seeds)
    bands = [script.original_trained_keeping(0, level)[1:3] for level in range(1, 11)]
    assert sum(max(k) - min(k) > upper - lower for k, (lower, upper) in zip(seeds, bands)) <= 5
    assert max(max(k) - min(k) for k in seeds) < 0.13


def test_a_tower_takes_back_a_tenth_its_neighbours_gave_it_first_by_hand():
    from hivex_dsl.envs.wildfire_resource_management.resources import NEIGHBOURS, initial_resources

    assert NEIGHBOURS[1, 2] == 4  # tower 1's third neighbour is the centre, tower 4
    allocation, budget = initial_resources(3, 9, 0)
    allocation[:2, 4, 0] = 3  # worlds 0 and 1: the centre keeps three tenths
    allocation[0, 1, 3] = 2  # world 0: tower 1 gave it two more; world 2: it holds nothing
    budget -= allocation.sum(-1).astype(budget.dtype)
    total = allocation.sum(axis=(1, 2)) + budget.sum(-1)
    asks = np.zeros((3, 9), bool)
    asks[:, 4] = True
    script._take_back(allocation, budget, asks, "received_first", np.random.default_rng(0))
    assert allocation[0, 1, 3] == 1 and budget[0, 1] == 9 and allocation[0, 4, 0] == 3  # back to its giver
    assert allocation[1, 4, 0] == 2 and budget[1, 4] == 8  # nothing received: its own
    assert not allocation[2].any() and (budget[2] == 10).all()  # nothing held: nothing moves
    np.testing.assert_array_equal(allocation.sum(axis=(1, 2)) + budget.sum(-1), total)


def test_taking_back_what_was_given_keeps_it_from_the_neighbours():
    """Uniform random play on the allocations alone: the environment's moves give most away; a 'Sub from Self'
    that takes back first what neighbours gave keeps most, one in proportion to what is held lies between."""
    giving = {mode: script.allocation_model(mode, worlds=400)[1] for mode in script.TAKE_BACKS}
    assert giving["received_first"] < 0.8 < giving["proportional"] < 1.6 < 2.0 < giving["none"]
    with pytest.raises(script.HivexError, match="take_back must be one of"):
        script.allocation_model("sometimes")


def test_uniform_random_play_read_as_the_terms_now_read_keeps_and_gives_as_the_original_s_untrained_towers():
    """Each tenth given is held by the neighbour whose P pays for it, so over a world's towers giving read as that
    neighbour's P times the share given it is at most Individual Performance, which the original's trained towers
    exceed 2.7-2.8 times (ruled out); read as the neighbour's performance (P times what it holds) times the share
    given it, it is not bounded so, and random play keeps and gives within the original's untrained range, as the
    summed reading (about three times what is given over what is held) does not."""
    found = script.readings(1, worlds=4, steps=400)
    keep_range, give_range = original_range_over_every_cell()
    assert found["given_each"] <= 1.0
    assert found["given_total"] > 1.5 > give_range[1] and found["self_squared"] < keep_range[0] < found["self_held"]
    assert keep_range[0] < found["self_held"] < keep_range[1] and give_range[0] < found["given_each_held"] < 1.1
    assert keep_range[0] < found["self_allocated"] < keep_range[1]  # the own term's default of sessions 77-78
    # P r_self, the default since session 79: a kept tenth pays P / 10 whatever is allocated, so it reads more than
    # P times the allocated share times r_self, within the original's untrained range
    assert found["self_allocated"] < found["self_kept"] and keep_range[0] < found["self_kept"] < keep_range[1]


def test_bad_counts_are_refused_with_exit_2(capsys):
    assert script.main(["--inits", "0"]) == 2
    assert "must be at least 1" in capsys.readouterr().err


def test_holdings_of_a_missing_or_other_environment_s_checkpoint_are_refused_with_exit_2(tmp_path, capsys):
    assert script.main(["--holdings", str(tmp_path / "none.pt")]) == 2
    assert "no checkpoint at" in capsys.readouterr().err
    checkpoint = untrained_checkpoint(tmp_path / "c.pt", short("wind_farm_control", 20))
    assert script.main(["--holdings", str(checkpoint)]) == 2
    err = capsys.readouterr().err
    assert "trained wind_farm_control, not wildfire_resource_management" in err and "Traceback" not in err


def short(environment: str, episode_length: int):
    """``environment``'s default scenario with ``episode_length``-step episodes, compiled."""
    return script.hivex_dsl.compile({"hivex": 1, "environment": environment, "episode_length": episode_length})
