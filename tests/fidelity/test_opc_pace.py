"""Ocean Plastic Collection's vessel pace and pebble supply against the original's own curves (issue 52).

Two records fix the pace (the reward table's pace note has the numbers):

- crash timing: the original's untrained policy (uniform, its first training point) lives 32.5-35.2 decisions a
  vessel-episode; random play here lives as long at the default pace (test_opc_endings checks it);
- collection pace of trained vessels: at every test point of tasks 0-2 the original's Local Reward equals its
  Episode Length (ratio 0.98-1.00). Both are added once per vessel-episode (Local its collected count: the reward
  table's Local note), so a summary point's ratio is the pebbles its vessel-episodes collected over the decisions
  they lived: the original's trained vessels collected r = 1.0 pebble a decision.

The supply is then the one at which random play collects what the original's untrained policy did, its Local
18.97 (test_opc_supply); over trained lives the skipper then collects within half as much again of r.
"""

from __future__ import annotations

import numpy as np

import hivex_dsl
from hivex_dsl.evaluation.original.curves import original_curves
from hivex_dsl.evaluation.rollout import rollout

ENV = "ocean_plastic_collection"
TRAINED_LIFE = 150  # decisions: the original's trained vessel-episodes last 133-184 at its main task's test points


def compiled(episode_length: int, camera_source: str = "pebbles"):
    return hivex_dsl.compile({"hivex": 1, "environment": ENV, "task": 0, "agents": 3,
                              "episode_length": episode_length, "seeds": {"train": 5000, "test": 6000},
                              "params": {"camera_source": camera_source}})


def skipper_pace(camera_source: str, worlds: int) -> tuple[float, float]:
    """The scripted skipper over 150-decision lives on test worlds: pebbles a vessel a decision lived, and the
    share of worlds that lived to the end (none crashed)."""
    play = rollout(compiled(TRAINED_LIFE * 5, camera_source), "scripted", worlds, split="test")
    return float(play.terms["collect_trash"].sum() / (play.lengths.sum() / 5)), float(np.mean(play.lengths == 750))


def local_per_episode_length(task: int) -> float:
    """The mean over the original's test points of Local Reward / Episode Length: pebbles a decision."""
    panels = original_curves(ENV, task, None).panels
    steps = panels["Episode Length"].test.steps
    return float(np.mean(panels["Local Reward"].test.mean_at(steps) / panels["Episode Length"].test.mean_at(steps)))


def test_the_originals_trained_local_tracks_its_episode_length():
    ratios = [local_per_episode_length(task) for task in range(3)]
    assert all(0.95 < r < 1.05 for r in ratios), ratios


def test_the_skipper_collects_at_the_originals_trained_pace_over_a_trained_life():
    """The scripted skipper steering by the pebbles it sees (the pebble camera) over 150-decision lives (all as long:
    750 physics steps, none crashes in these 4 test worlds) collects 1.43 pebbles a vessel a decision (1.40 over
    200), at least the original's trained r (about 1.0, the module docstring) and under 1.5 r, as a long-lived
    collector steering for pebbles should. The supply and map fitted to the untrained records (6,000 pebbles,
    contrast 1.5, no hotspots) keep it there: the same supply under the four hotspots first chosen gave it 1.92, an
    even map 1.24. At the pace before issue 52's fit (top speed 0.5 m a step, 3,000 pebbles) it collected 0.43 a
    decision, under half of r: the original's vessels could not have been that slow."""
    play = rollout(compiled(TRAINED_LIFE * 5, "pebbles"), "scripted", 4, split="test")
    assert (play.lengths == TRAINED_LIFE * 5).all()
    pace = play.terms["collect_trash"].mean() / TRAINED_LIFE
    ratio = local_per_episode_length(0)
    assert ratio <= pace <= 1.5 * ratio, (pace, ratio)


def test_what_the_camera_shows_sets_the_skippers_pace_and_a_blind_one_collects_the_originals():
    """The same skipper over the same 16 test worlds and 150-decision lives, by what its camera shows
    (params.camera_source; the reward table's note 'What the vessels saw'): steering by the pebbles it collects 1.48
    pebbles a decision, by the heat map, which does not show the water swept, 1.23, and blind (a blank camera: it
    goes straight at full speed and turns home at the border) 0.92, within a tenth of the original's trained r
    (about 1.0, the module docstring), which no collector that aims can come down to."""
    paces = {source: skipper_pace(source, 16) for source in ("pebbles", "heat_map", "blank")}
    (by_pebbles, lived_pebbles), (by_heat, _), (blind, lived_blind) = paces.values()
    ratio = local_per_episode_length(0)
    assert lived_pebbles == lived_blind == 1.0
    assert blind < ratio < by_heat < 0.9 * by_pebbles, paces
    assert abs(blind - ratio) < 0.1 * ratio, (blind, ratio)


def test_the_originals_training_pace_stays_near_a_pebble_a_decision_in_every_collecting_task():
    """Over the last 70% of the budget the original's training means of Local Reward over Episode Length, read at
    the same steps (its vessel-episodes' pebbles over their decisions), average 0.95, 1.00 and 0.94 in tasks 0-2 and
    never pass 1.06, 1.11 and 1.07, though the three tasks pay collection differently: a ceiling near one pebble a
    decision (the reward table's pace note), where this toolkit's trained vessels pass 1.28 by half the budget."""
    for task, mean, peak in ((0, 0.95, 1.06), (1, 1.00, 1.11), (2, 0.94, 1.07)):
        panels = original_curves(ENV, task, None).panels
        length = panels["Episode Length"].training
        late = length.steps[length.steps >= 0.3 * length.steps.max()]
        ratio = panels["Local Reward"].training.mean_at(late) / length.mean_at(late)
        assert len(late) > 130
        assert round(float(ratio.mean()), 2) == mean and round(float(ratio.max()), 2) == peak


def avoid_plastic_touches_and_local(params: dict) -> tuple[np.ndarray, np.ndarray]:
    """Random play in Avoid Plastic (4 test worlds): what touching paid each vessel-episode (Collide with Trash, -1
    a step that takes pebbles) and its Local (-1 a pebble)."""
    scenario = hivex_dsl.compile({"hivex": 1, "environment": ENV, "task": 3, "agents": 3, "episode_length": 5000,
                                  "seeds": {"train": 5000, "test": 6000}, "params": params})
    played = rollout(scenario, "random", 4, split="test")
    return played.terms["collide_with_trash"].ravel(), played.statistics["Local Reward"].ravel()


def test_a_cap_of_one_pebble_a_decision_cannot_give_the_originals_avoid_plastic_records():
    """The ceiling near a pebble a decision is not a cap (params.collect_per_decision 1, the capped reading of the
    pace note). Under a cap of one a step takes at most one pebble, so Avoid Plastic pays -1 for every pebble its
    Local counts and a vessel-episode returns exactly its Local, whatever the policy; the original's test points
    that lived to the limit return 0.45-0.99 of their Local (test_opc_local), so some of its touching steps took
    several pebbles. Uncapped, as by default, they do here too."""
    capped_touches, capped_local = avoid_plastic_touches_and_local({"collect_per_decision": 1})
    assert capped_local.sum() < -20 and np.array_equal(capped_touches, capped_local)
    touches, local = avoid_plastic_touches_and_local({})
    assert local.sum() < -20 and touches.sum() / local.sum() < 0.99
    panels = original_curves(ENV, 3, None).panels
    steps = panels["Episode Length"].test.steps
    lived = panels["Episode Length"].test.mean_at(steps) > 990
    ratio = panels["Cumulative Reward"].test.mean_at(steps)[lived] / panels["Local Reward"].test.mean_at(steps)[lived]
    assert lived.sum() == 9 and ratio.max() < 0.995, ratio
