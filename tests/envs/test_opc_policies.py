"""The scripted skipper collects far more than random play on the same seeds, and suits every task.

Its rules were written for the pebble camera (params.camera_source 'pebbles'), which these tests give it whatever
the default: steering by the heat map its vessels gather over the densest water and one world in 16 collides within
500 decisions (tests/fidelity/test_opc_pace.py measures what it collects by each camera).
"""

from __future__ import annotations

import pytest

import hivex_dsl
from hivex_dsl.evaluation.report import collect_returns

ENV = "ocean_plastic_collection"
STEPS = 1000


def short(task: str, **params):
    return hivex_dsl.compile({"hivex": 1, "environment": ENV, "task": task, "episode_length": STEPS,
                              "params": {"camera_source": "pebbles", **params}})


@pytest.fixture(scope="module")
def main_runs():
    sc = short("plastic_collection")
    return {policy: collect_returns(sc, policy, episodes=2, split="test", seed=6000) for policy in ("scripted", "random")}


def test_scripted_collects_several_times_what_random_collects(main_runs):
    scripted, random = main_runs["scripted"][1]["collect_trash"], main_runs["random"][1]["collect_trash"]
    # random play drifts off and crosses the border; the skipper heads for the trash it sees
    assert scripted.mean() >= 15.0
    assert scripted.mean() >= 4.0 * max(random.mean(), 1.0)
    assert main_runs["scripted"][0].mean() > main_runs["random"][0].mean() + 100.0


def test_scripted_stays_inside_the_border_and_clear_of_the_others(main_runs):
    sums = main_runs["scripted"][1]
    assert sums["crossed_border"].sum() == 0.0 and sums["collided_with_other_vessel"].sum() == 0.0
    assert sums["lowest_collected_trash_count"].min() > 0.0  # every vessel collected something


def test_avoid_plastic_holds_still_and_group_up_keeps_company():
    avoid, sums = collect_returns(short("avoid_plastic"), "scripted", episodes=1, split="test", seed=6000)
    assert sums["collect_trash"].sum() <= 1.0 and avoid.mean() >= -101.0 / 3
    # with vessels colliding within 5 m, a 5-10 m band where closeness pays without a crash
    group, sums = collect_returns(short("group_up", collision_distance_m=5.0), "scripted", episodes=1, split="test",
                                  seed=6000)
    assert sums["collided_with_other_vessel"].sum() == 0.0
    assert sums["close_to_other_vessel"].mean() >= 1.0 * STEPS / 2  # close (+1 a step) for at least half the steps


def test_group_up_collects_where_closeness_would_be_a_collision(main_runs):
    """At the default collision distance, 10 m, no closer than the close distance, closeness pays nothing (a
    vessel that near has collided): the skipper collects as in the main task instead, the same pebbles."""
    group, sums = collect_returns(short("group_up"), "scripted", episodes=2, split="test", seed=6000)
    assert sums["collided_with_other_vessel"].sum() == 0.0 and sums["close_to_other_vessel"].sum() == 0.0
    assert sums["collect_trash"].tolist() == main_runs["scripted"][1]["collect_trash"].tolist()
