"""What Ocean Plastic Collection's Local Reward counts: Collect Trash's pay alone (+1 a pebble, -1 in Avoid Plastic),
not the crash's -100 and not Collide with Trash (the reward table's Local note has the evidence).

The original's untrained policy (its first training point, uniform over both action branches in every task) logs
Local +18.97 in the main task and -18.94 in Avoid Plastic: the same policy in the same world collects the same
pebbles, so the statistic moves by +1 and -1 a pebble. Counting the crash would pull both down by about
200 f / (x + f) together (f >= 1/3 of vessel-episodes pay -100: every untrained world ends on a crash, which
charges at least one of its three vessels; x <= 18 pebbles a vessel-episode), at least 3.6; counting Collide with
Trash would double Avoid Plastic's.
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest

import hivex_dsl
from hivex_dsl.envs.ocean_plastic_collection.camera import build_field
from hivex_dsl.evaluation.original.curves import original_curves
from hivex_dsl.runtime.batched import BatchedEnv

ENV = "ocean_plastic_collection"
GO, NOOP = [1, 0], [0, 0]


def first_point(task: int, panel: str) -> float:
    """The original's training mean at its first summary point (15,000 agent-steps): the untrained policy."""
    return float(original_curves(ENV, task, None).panels[panel].training.mean_at(15_000))


def test_the_originals_untrained_local_is_a_mirror_image_across_the_main_task_and_avoid_plastic():
    main, avoid = first_point(0, "Local Reward"), first_point(3, "Local Reward")
    assert main > 15 and abs(main + avoid) < 0.5, (main, avoid)
    # tasks 1 and 2 pay the same +1 a pebble and log about the same (their shaping terms stay out of Local)
    assert all(abs(first_point(task, "Local Reward") - main) < 1.5 for task in (1, 2))


def collect_then_cross(task: int, pebbles: tuple[tuple[float, float], ...] = ((191.0, 0.0),)) -> BatchedEnv:
    """One world at the default decision period (5): vessel 0 at x = 186 m heading +x at its top speed (2 m a physics
    step), ``pebbles`` (one at (191, 0) by default) in its path, the other vessels far from it, the border and each
    other. Its collector sweeps the pebbles at x <= 196 within the first decision, and it leaves the world at physics
    step 8 (x = 202), inside the second decision (test_opc_endings works the same run out)."""
    compiled = hivex_dsl.compile({"hivex": 1, "environment": ENV, "task": task, "agents": 3, "episode_length": 5000,
                                  "seeds": {"train": 5000, "test": 6000}})
    env = BatchedEnv(compiled, batch=1, split="test")
    env.reset()
    env.state = replace(env.state, position=np.array([[[186.0, 0.0], [0.0, 0.0], [-60.0, 60.0]]]),
                        heading=np.zeros((1, 3)), speed=np.array([[2.0, 0.0, 0.0]]),
                        pebbles=build_field(np.array([[*pebbles, (-150.0, -150.0)]]), env.sim.geometry))
    for _ in range(2):
        env.step(np.array([[GO, NOOP, NOOP]]))
    return env


@pytest.mark.parametrize(("task", "sign"), [(0, 1), (3, -1)])
def test_a_vessel_that_takes_one_pebble_and_crosses_the_border_logs_the_pebble_alone(task, sign):
    """By hand: the vessel's Collect Trash total steps to +1 (main task) or -1 (Avoid Plastic) when it takes the
    pebble and does not move again, so its Local is +1 or -1; the crash's -100 and Avoid Plastic's Collide with
    Trash are paid (the return is 1 - 100 = -99, or -1 - 100 = -101: in Avoid Plastic Collect Trash's -1 is logged,
    not paid) but not counted. Counting them, as this toolkit did, logged (1 + (1 - 100)) / 2 = -49 and
    (-2 + (-2 - 100)) / 2 = -52; paying Collect Trash there too returned -102."""
    env = collect_then_cross(task)
    assert env.term_sums["collect_trash"][0].tolist() == [1.0, 0.0, 0.0]
    assert env.returns[0].tolist() == [-99.0 if task == 0 else -101.0, 0.0, 0.0]
    assert env.statistic_sums()["Local Reward"][0].tolist() == [sign * 1.0, 0.0, 0.0]


@pytest.mark.parametrize(("task", "sign"), [(0, 1), (3, -1)])
def test_a_vessel_that_takes_two_pebbles_on_two_steps_logs_their_total_not_a_running_mean(task, sign):
    """By hand: pebbles at x = 191 and 196 m are swept on different physics steps (the vessel moves 2 m a step, its
    collector reaching 3 m ahead), so the Collect Trash total steps to +1 then +2 (-1, -2 in Avoid Plastic). Added
    once per vessel-episode, Local is the total, 2 (-2); the running mean this toolkit logged before averaged the
    totals after each change, (1 + 2) / 2 = 1.5 (-1.5)."""
    env = collect_then_cross(task, ((191.0, 0.0), (196.0, 0.0)))
    assert env.term_sums["collect_trash"][0].tolist() == [2.0, 0.0, 0.0]
    assert env.statistic_sums()["Local Reward"][0].tolist() == [sign * 2.0, 0.0, 0.0]


def smallest_denominator(value: float, tolerance: float, largest: int = 60) -> int | None:
    """The smallest m <= ``largest`` with m x ``value`` within m x ``tolerance`` of an integer (None if none)."""
    return next((m for m in range(1, largest + 1) if abs(value * m - round(value * m)) < tolerance * m), None)


def test_the_originals_avoid_plastic_local_is_added_once_per_vessel_episode():
    """The Local note's evidence that the original adds Local once per vessel-episode (as this toolkit now logs it,
    the test above). Once Avoid Plastic's vessels live to the time limit (Episode Length 999), a summary of 15,000
    agent-steps holds 5 world-episodes of 3 vessels. With three runs, the 95% bootstrap band's edges are single runs'
    values (but where the 1,000 resamples happen to mix them), and each is an integer over 15 (or 21, 7
    world-episodes): reduced, 15, 5, 3 and 1 in about the shares k / 15 takes for integers k (8/15, 4/15, 2/15,
    1/15), never 2, 4 or 30. A value added at every change of a
    running total would have the count of touches as its denominator, and could not lie above -1."""
    cell = original_curves(ENV, 3, None)
    local, length = cell.panels["Local Reward"], cell.panels["Episode Length"].training
    at_limit = length.mean_at(local.training.band_steps) > 990
    edges = np.concatenate([local.training.lower[at_limit], local.training.upper[at_limit]])
    tolerance = 0.6 * 10.0 ** -local.y_decimals  # the stored values' rounding
    denominators = [smallest_denominator(v, tolerance) for v in edges]
    assert at_limit.sum() > 100
    assert sum(d in (1, 3, 5, 15) for d in denominators) / len(edges) > 0.9
    # the rest: 7 world-episodes (21, 7), or a bootstrap edge that mixes three runs' values over 15 (45, 9)
    assert all(d in (1, 3, 5, 15, 7, 21, 9, 45) for d in denominators), sorted(set(denominators), key=str)
    assert 0.4 < denominators.count(15) / len(edges) < 0.65  # 8/15 of integers k over 15 stay over 15
    assert local.test.upper.max() > -1  # a test run above -1: -19/21 at the first test point


@pytest.mark.parametrize("lowest_per_global", [1.0, 4.0])
def test_the_originals_untrained_returns_price_a_touched_pebble_under_one(lowest_per_global):
    """The untrained side of why a touched pebble costs under 1 in Avoid Plastic (the test below has the trained). With
    Local the vessel-episode's count, the untrained policy collected x = 18.97 pebbles a vessel-episode (-18.94 in
    Avoid Plastic). Main task: x + G - 100 f = -13.86; Avoid Plastic: -c x - 100 f = -51.22, with G what the lowest
    count paid a vessel-episode, at least the logged Global (1.39, a running mean of a growing total is at most its
    end) and at most about 4 times it. By hand at G = 1.39: f = (18.97 + 1.39 + 13.86) / 100 = 0.342 and
    c = (51.22 - 34.22) / 18.94 = 0.90; at G = 5.56: f = 0.384, c = 0.68. c = 2 would need G = -19.5 and c = 1
    G = -0.5, both impossible (G >= 0)."""
    pebbles, avoid_pebbles = first_point(0, "Local Reward"), -first_point(3, "Local Reward")
    lowest = lowest_per_global * first_point(0, "Global Reward")
    crashed = (pebbles + lowest - first_point(0, "Cumulative Reward")) / 100
    per_pebble = (-first_point(3, "Cumulative Reward") - 100 * crashed) / avoid_pebbles
    assert 1 / 3 - 0.01 < crashed < 0.4, crashed
    assert 0.6 < per_pebble < 0.95, per_pebble


def test_the_originals_trained_avoid_plastic_pays_less_than_its_local_so_collect_trash_is_not_paid():
    """Why Avoid Plastic logs Collect Trash's -1 a pebble in Local but does not pay it (its task column's unpaid).
    At the original's test points 2-10 every vessel-episode lives to the time limit (Episode Length 999), so none paid
    a crash, and the return is what touching pebbles cost. Were Collect Trash's -1 a pebble paid, the return could
    not lie above Local (-1 a pebble, plus whatever else a touch costs); it lies above it at all nine, return / Local
    0.45-0.99. Here a touch pays Collide with Trash's -1 a step however many pebbles it takes (random play: about
    0.9 touch steps a pebble), under 1 a pebble as those points are."""
    panels = original_curves(ENV, 3, None).panels
    steps = panels["Episode Length"].test.steps
    lived_to_the_limit = panels["Episode Length"].test.mean_at(steps) > 990
    local, paid = (panels[name].test.mean_at(steps)[lived_to_the_limit]
                   for name in ("Local Reward", "Cumulative Reward"))
    assert lived_to_the_limit.sum() == 9
    assert (local < paid).all() and (paid < 0).all(), (local, paid)  # -1 a pebble paid would need paid <= local
    compiled = hivex_dsl.compile({"hivex": 1, "environment": ENV, "task": 3})
    assert compiled.unpaid == {"collect_trash"} and compiled.weights["collide_with_trash"] == 1.0
