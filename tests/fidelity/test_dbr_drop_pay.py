"""Why the trained Drone-Based Reforestation main task earns about twice the original's return (issue 52; the reward
table's note "Why the trained main task earns about twice the original's"): the original's own curves, read as data,
against this toolkit's world and its committed baseline record.

1. The battery and the speed agree with the records: under this toolkit's energy rule a drone that holds its seed s
   physics steps and never refills runs out at physics step 2,000 - s, and the original's main-task Episode Length,
   Out of Energy Count and path to the drop give s for a path flown at about 1 m a physics step, this toolkit's top
   speed, at every level.
2. The original's returns reload a seed in the main task: single runs' summary points average up to 1.4-2.1 drops a
   drone-episode at every level, and more drops come with fewer run-outs, as here.
3. What differs is the pay of a far drop: the original's drops earned about 2 more of r_s 50-70 m from the station
   than within 20 m, and no record places its drops farther out on average; this toolkit's forest rings the station
   beyond an 80 m clearing, so a straight flight in any direction meets it and a drop 60 m out earns about 11 more
   than one 10 m out.
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

import hivex_dsl
from hivex_dsl.envs.drone_based_reforestation.fertility import FAR_M, seed_reward
from hivex_dsl.envs.drone_based_reforestation.params import DBR_FOREST, DroneBasedReforestationParams
from hivex_dsl.envs.drone_based_reforestation.simulator import returns_reload
from hivex_dsl.evaluation.original.compare import seed_curves
from hivex_dsl.evaluation.original.curves import original_curves
from hivex_dsl.runtime.batched import BatchedEnv

ENV = "drone_based_reforestation"
RECORD = Path(__file__).resolve().parents[2] / "benchmarks" / "baselines" / f"{ENV}.json"
LEVELS = range(1, 11)
FULL_EPISODE = 399  # decisions of an episode the time limit ends: 2,000 physics steps / period 5, less one
PERIOD = 5
SDD_BINS = ((0, 20), (20, 30), (30, 40), (40, 50), (50, 70))  # metres from the station, a drop on average


def main_panels(level: int, steps: np.ndarray | None = None) -> dict[str, np.ndarray]:
    """The original's main-task training means (three runs) at ``steps`` (default: every summary point)."""
    cell = original_curves(ENV, 0, level)
    at = cell.panel("Tree Drop Count").training.band_steps if steps is None else steps
    return {"steps": at, **{name: panel.training.mean_at(at) for name, panel in cell.panels.items()
                            if panel.training is not None}}


def per_drop(points: dict[str, np.ndarray]) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Each point's mean station distance of a drop (from r_d = 10 sdd / 200), r_s and det a drop."""
    drops = points["Tree Drop Count"]
    return (points["Cumulative Distance Reward"] * 20.0 / drops, points["Cumulative Tree Drop Reward"] / drops,
            points["Cumulative Distance to Existing Trees"] / drops)


def binned(sdd: np.ndarray, values: np.ndarray) -> list[float]:
    """``values`` averaged over the points whose drops lie, on average, in each of SDD_BINS."""
    return [float(values[(sdd >= low) & (sdd < high)].mean()) for low, high in SDD_BINS]


def hinge(det: np.ndarray) -> np.ndarray:
    """r_s of a drop det metres from the nearest existing tree, the new trees aside: 20 (75 - det)+ / 72.5."""
    return 20.0 * np.clip(75.0 - det, 0.0, None) / 72.5


def original_per_drop() -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Every summary point of the ten levels' main-task training (2,000 points), a drop's sdd, r_s and det."""
    parts = [per_drop(main_panels(level)) for level in LEVELS]
    return tuple(np.concatenate(column) for column in zip(*parts))


def implied_speed(level: int) -> float:
    """Metres a physics step the original's drones flew their seed out over the last quarter of its main-task training:
    the path to a drop over s = 5 (399 - Episode Length) / Out of Energy Count, the physics steps a drone that runs out
    at 2,000 - s held its seed (the test below)."""
    points = main_panels(level, np.arange(900_000, 1_200_001, 6_000, dtype=float))
    held = PERIOD * (FULL_EPISODE - points["Episode Length"].mean()) / points["Out of Energy Count"].mean()
    return float((points["Cumulative Distance Until Tree Drop"] / points["Tree Drop Count"]).mean() / held)


def test_a_seed_held_s_physics_steps_runs_the_battery_out_at_2000_less_s():
    """Hand-computed: a drone flies out at full throttle for 10 decisions (50 physics steps) with its seed, drops it
    on the next physics step and hovers. Its battery holds 1 - 51 / 1000 = 0.949 after the drop (the drop step is
    paid with the seed, -1/1000), which lasts 0.949 x 2000 = 1,898 seedless steps: empty on physics step 51 + 1,898 =
    1,949 = 2,000 - 51, in decision 390 (of the 399 a full episode holds)."""
    env = BatchedEnv(hivex_dsl.compile({"hivex": 1, "environment": ENV, "task": "main"}), batch=1, split="test")
    env.reset()
    fly = {"continuous": np.tile(np.float32([1.0, 0.0, 0.0]), (1, 3, 1)), "discrete": np.zeros((1, 3, 1), np.int64)}
    hover = {"continuous": np.zeros((1, 3, 3), np.float32), "discrete": np.ones((1, 3, 1), np.int64)}
    for _ in range(10):
        env.step(fly)
    assert env.state.holding.all()
    decisions = 10
    while not env.step(hover).ended.any():
        decisions += 1
    summary = env.episode_summary(0, 0)
    assert summary["statistics"]["Tree Drop Count"] == 1.0
    assert summary["length"] == 1949 and summary["decisions"] == decisions + 1 == 390
    assert summary["statistics"]["Out of Energy Count"] == 1.0


@pytest.mark.parametrize("level", LEVELS)
def test_the_original_s_drones_flew_their_seed_out_at_about_this_toolkit_s_top_speed(level):
    """Over the last quarter of the original's main-task training its drones run out in 86-96% of drone-episodes with
    Episode Length 386-391: under the energy rule above a drone that held its seed s physics steps ends at decision
    (2,000 - s) / 5, so s = 5 (399 - Episode Length) / Out of Energy Count, 43-68 steps, for a path to the drop of
    53-73 m: 0.81-1.24 m a physics step, 1.00 on average over the ten levels, this toolkit's drone_speed_m (1 m at full
    throttle). The battery and the speed agree with the records; neither kept the original's drones near the station
    (a battery holding a seed lasts 1,000 physics steps, about 1 km)."""
    assert 0.75 < implied_speed(level) < 1.3
    assert DroneBasedReforestationParams().drone_speed_m == 1.0


def test_the_original_s_drones_flew_at_one_metre_a_step_on_average_over_the_levels():
    assert np.mean([implied_speed(level) for level in LEVELS]) == pytest.approx(
        DroneBasedReforestationParams().drone_speed_m, abs=0.05)


@pytest.mark.parametrize("level", LEVELS)
def test_the_original_s_main_task_returns_reload_a_seed(level):
    """A drone-episode holds one seed unless a return hands over another, so a summary point can average more than one
    drop a drone-episode only with returns that reload. The band over the original's three runs reaches its highest
    run (seaborn's 95% bootstrap of three values: a resample of the highest thrice is 1 in 27), and at every level a
    run's point averages 1.4 to 2.1 drops (its means over the three runs up to 1.2-1.4), so the main task reloads, as
    returns_reload says, and a second drop is possible in the original; its runs end training at 1.01-1.11."""
    drops = original_curves(ENV, 0, level).panel("Tree Drop Count").training
    assert drops.upper.max() > 1.35
    assert returns_reload("main")


def test_more_drops_come_with_fewer_run_outs_in_the_original_as_here():
    """A return that reloads refills the battery too: over the original's summary points after 10% of its budget (ten
    levels, 1,810 points) Out of Energy Count falls by 0.53 a drop (1.46 - 0.53 x drops, correlation -0.51); over the
    committed record's three seeds (this toolkit's rule: a full battery and a seed a return) by 0.69 (1.64 - 0.69 x
    drops). So the record's lower Out of Energy Count at the end (0.38-0.50 for the seeds that drop 1.7-1.9 seeds a
    drone-episode, the original 0.93-1.00 at 1.00-1.07 drops) is its second drops, on the original's own relation
    (0.48-0.57 at those drops)."""
    drops, run_outs = [], []
    for level in LEVELS:
        points = main_panels(level)
        late = points["steps"] >= 120_000
        drops.append(points["Tree Drop Count"][late])
        run_outs.append(points["Out of Energy Count"][late])
    slope, intercept = np.polyfit(np.concatenate(drops), np.concatenate(run_outs), 1)
    assert -0.7 < slope < -0.35 and 1.3 < intercept < 1.6
    runs = seed_curves(json.loads(RECORD.read_text()))
    late = [run.steps >= 120_000 for run in runs]
    our_slope, _ = np.polyfit(np.concatenate([run.panels["Tree Drop Count"][m] for run, m in zip(runs, late)]),
                              np.concatenate([run.panels["Out of Energy Count"][m] for run, m in zip(runs, late)]), 1)
    assert -0.9 < our_slope < -0.45


def test_the_original_s_drop_pay_barely_rises_with_the_drop_s_distance_from_the_station():
    """The original's 2,000 main-task summary points (ten levels), binned by where their drops lie on average (sdd from
    r_d): r_s a drop 4.1, 4.3, 5.0, 5.7 and 6.1 within 20, 20-30, 30-40, 40-50 and 50-70 m of the station, det a drop
    68.7, 67.6, 63.5, 59.2 and 56.6 m. A drop 50-70 m out earned about 2 more than one within 20 m, and no point's
    drops lie farther than 68 m out on average (the runs' single points reach 72-110 m, their band). And the drops at
    one distance lay at widely different distances from the forest: r_s = 20 (75 - det)+ / 72.5 is convex in det, so a
    point's r_s exceeds that of its mean det by 0.276 E[(det - 75)+], the drops beyond the forest's reach, paid nothing;
    the original's points exceed it by 2.1, 2.1, 1.8, 1.4 and 1.0 in the five bins (about 7.5 m of det beyond 75 a drop
    within 30 m of the station), while others of their drops lay far nearer than the mean: trees near the station in
    some directions, none within 75 m in others (the test below: this toolkit's ring gives 0.1 or less)."""
    sdd, reward, det = original_per_drop()
    pay, distance = binned(sdd, reward), binned(sdd, det)
    assert pay[-1] - pay[0] < 2.5
    assert min(distance) > 55.0
    assert sdd.max() < 70.0
    assert min(binned(sdd, reward - hinge(det))) > 0.9


def test_our_forest_pays_a_drop_60_m_out_far_more_than_one_10_m_out():
    """This toolkit's forest grows nowhere within 80 m of the station (DBR_FOREST village_clear_radius_m) and on the
    hillsides around, so a drop d metres out lies at least 80 - d from any tree (within 20 m of the station it earns at
    most 20 x (75 - 60) / 72.5 = 4.1, 1.4 at 10 m) and, in any direction, nearer the forest the farther out it is:
    averaged over 72 directions of four worlds (level 1), r_s is 0.8 at 10 m and 12.1 at 60 m, and a drop 80 m out
    in any direction is within 75 m of a tree (det 16 m on average). The original's drops earned about 2 more 50-70 m
    out than within 20 m (the test above); here 11 more: a straight flight outward, no looking needed, multiplies a
    drop's pay, which the committed record's seed 0 learned (one drop a drone-episode 114 m out, 20 m from the forest,
    r_s 15.2)."""
    compiled = hivex_dsl.compile({"hivex": 1, "environment": ENV, "task": "main"})
    state = compiled.entry.make_simulator(compiled).reset(np.random.default_rng(0), 4)
    directions = np.linspace(0.0, 2.0 * np.pi, 72, endpoint=False)
    rays = np.stack([np.cos(directions), np.sin(directions)], axis=-1)
    pay = {}
    for out in (10.0, 60.0, 80.0):
        det = []
        for world in range(4):
            trees = state.tree_xy[world].reshape(-1, 2)
            trees = trees[trees[:, 0] < FAR_M]
            points = state.station[world, :2] + out * rays
            det.append(np.sqrt(((points[:, None, :] - trees[None]) ** 2).sum(-1)).min(axis=1))
        det = np.concatenate(det)
        assert det.min() >= DBR_FOREST["village_clear_radius_m"] - out
        pay[out] = seed_reward(det, np.full_like(det, np.inf), 2.5, 75.0, 20.0)
        if out == 80.0:
            assert (det <= 75.0).all()
    assert pay[10.0].mean() < 1.4
    assert pay[60.0].mean() - pay[10.0].mean() > 8.0


def test_the_record_s_drops_pay_more_than_the_original_s_at_the_same_distance_from_the_station():
    """Like for like (the same statistics, pooled the same way): the committed record's summary points (three seeds)
    binned as the original's. From 30 m out its drops lie 13.6-15.5 m nearer the forest and earn 1.3-2.6 more r_s a drop
    than the original's at the same distance (6.2, 7.6 and 8.7 against 5.0, 5.7 and 6.1 at 30-40, 40-50 and 50-70 m),
    and a third of its points' drops lie beyond 50 m on average (3% beyond 70 m), where the original's lie within
    68 m: the gap of the
    trained return is mostly this pay, not the number of drops."""
    sdd, reward, det = original_per_drop()
    ours = [per_drop(run.panels) for run in seed_curves(json.loads(RECORD.read_text()))]
    our_sdd, our_reward, our_det = (np.concatenate(column) for column in zip(*ours))
    dropped = np.isfinite(our_sdd)
    our_pay = binned(our_sdd[dropped], our_reward[dropped])
    our_distance = binned(our_sdd[dropped], our_det[dropped])
    pay, distance = binned(sdd, reward), binned(sdd, det)
    for bin_ in (2, 3, 4):  # 30-40, 40-50, 50-70 m
        assert our_pay[bin_] - pay[bin_] > 1.0
        assert distance[bin_] - our_distance[bin_] > 10.0
    assert max(binned(our_sdd[dropped], our_reward[dropped] - hinge(our_det[dropped]))) < 0.5  # no spread beyond 75 m
