"""Why the trained Drone-Based Reforestation main task earns about twice the original's return (issue 52; the reward
table's note "Why the trained main task earns about twice the original's"): the original's own curves, read as data,
against this toolkit's world and its committed baseline record.

1. The battery and the speed agree with the records: under this toolkit's energy rule a drone that holds its seed s
   physics steps and never refills runs out at physics step 2,000 - s, and the original's main-task Episode Length,
   Out of Energy Count and path to the drop give s for a path flown at about 1 m a physics step, this toolkit's top
   speed, at every level.
2. The original's returns reload a seed in the main task: single runs' summary points average up to 1.4-2.1 drops a
   drone-episode at every level, and more drops come with fewer run-outs, as here.
3. What differed is the pay of a far drop: the original's drops earned about 2 more of r_s 50-70 m from the station
   than within 20 m, and no record places its drops farther out on average; this toolkit's forest ringed the station
   beyond an 80 m clearing, so a straight flight in any direction met it and a drop 60 m out earned about 11 more
   than one 10 m out. The forest is now fitted to those records (hivex_dsl/envs/drone_based_reforestation/forest.py):
   blind drops pay r_s, lie at det and spread as the original's drops bin by bin, the same at every terrain level.
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

import hivex_dsl
from hivex_dsl.envs.drone_based_reforestation.fertility import FAR_M, seed_reward
from hivex_dsl.envs.drone_based_reforestation.params import DroneBasedReforestationParams
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
PROBE_WORLDS = 96  # fresh worlds of blind drops: their forests differ widely (two samples' det differ by up to 6 m)


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
    committed record's three seeds (this toolkit's rule: a full battery and a seed a return) it falls with the drops
    too (correlation -0.77 after 10% of the budget), to about 0 where its drones shuttle home for seed after seed
    (3-9 drops a drone-episode over the last tenth; the record's note), which the original's runs, ending at 1.01-1.11
    drops, never did: a relation, not a level, that the two share."""
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
    our_drops = np.concatenate([run.panels["Tree Drop Count"][m] for run, m in zip(runs, late)])
    our_run_outs = np.concatenate([run.panels["Out of Energy Count"][m] for run, m in zip(runs, late)])
    assert np.corrcoef(our_drops, our_run_outs)[0, 1] < -0.5


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


def blind_drops(level: int, worlds: int = PROBE_WORLDS, seed: int = 0) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """This toolkit's forest under blind drops: in each of SDD_BINS (the first from the pad's edge, 7.5 m), 16 drops a
    world in random directions at uniformly random distances from the station, over ``worlds`` fresh worlds of
    ``level``. Per bin (5,): the mean r_s (the new trees aside; nothing within 2.5 m of a tree), the mean det, and the
    convexity excess r_s - hinge(mean det) of groups of 15 drops drawn across the worlds, a summary point's ~15
    drone-episodes of about 5 world-episodes pooled as the original's points pool them."""
    compiled = hivex_dsl.compile({"hivex": 1, "environment": ENV, "task": "main", "terrain_level": level})
    state = compiled.entry.make_simulator(compiled).reset(np.random.default_rng(seed), worlds)
    draw = np.random.default_rng(seed + 1)
    det = np.empty((len(SDD_BINS), worlds, 16))
    for world in range(worlds):
        trees = state.tree_xy[world].reshape(-1, 2)
        trees = trees[trees[:, 0] < FAR_M]
        for b, (low, high) in enumerate(SDD_BINS):
            out, angle = draw.uniform(max(low, 7.5), high, 16), draw.uniform(0.0, 2.0 * np.pi, 16)
            points = state.station[world, :2] + out[:, None] * np.stack([np.cos(angle), np.sin(angle)], axis=-1)
            det[b, world] = np.sqrt(((points[:, None, :] - trees[None]) ** 2).sum(-1)).min(axis=1)
    det = det.reshape(len(SDD_BINS), -1)
    pay = seed_reward(det, np.full_like(det, np.inf), 2.5, 75.0, 20.0)
    groups = draw.permutation(det.shape[1])[: det.shape[1] // 15 * 15].reshape(-1, 15)
    excess = (pay[:, groups].mean(-1) - hinge(det[:, groups].mean(-1))).mean(-1)
    return pay.mean(-1), det.mean(-1), excess


@pytest.fixture(scope="module")
def ours():
    """blind_drops at level 1 (the forest is the same at every level: the test below)."""
    return blind_drops(1)


def test_our_forest_is_the_same_at_every_terrain_level():
    """The trees follow a patch field of their own, on land (ground above sea level), none in the station's clearing:
    the terrain levels scale the same heights (peaks 8 m at level 1, 30 m at level 10), which changes neither, so a
    seed draws the same forest at every level, as the original's drop records are the same at every level (the test
    above; published det 48-65 m a drop). The height band it replaced grew patchier with the hills (dbr5's note)."""
    forests = []
    for level in (1, 4, 10):
        compiled = hivex_dsl.compile({"hivex": 1, "environment": ENV, "task": "main", "terrain_level": level})
        forests.append(compiled.entry.make_simulator(compiled).reset(np.random.default_rng(7), 4).tree_xy)
    assert np.array_equal(forests[0], forests[1]) and np.array_equal(forests[0], forests[2])


def test_our_forest_pays_blind_drops_as_the_original_s_records_pay_its_drops(ours):
    """Fitted to the original's 2,000 main-task summary points (the test above), bin by bin: r_s a drop 4.1, 4.3, 5.0,
    5.7 and 6.1, det 68.7, 67.6, 63.5, 59.2 and 56.6 m, convexity excess 2.1, 2.1, 1.8, 1.4 and 1.0 within 20, 20-30,
    30-40, 40-50 and 50-70 m of the station. Blind drops here (96 worlds, level 1): r_s 4.4, 4.5, 4.8, 5.6 and 5.8, det
    68.0, 67.6, 66.6, 64.7 and 63.7 m, excess 2.3, 2.4, 2.3, 2.6 and 2.4 (another 96 worlds: r_s 4.7-6.1, det 58-64 m,
    excess 1.4-1.6; the forests differ widely between worlds, as the records' spread says the original's did): r_s
    within 0.7 of the records' in every bin, det within 7.5 m (their means over the bins within 4 m), the records'
    spread near the station (drops beyond the forest's reach in some directions, far nearer in others), and a drop
    50-70 m out paying 1.4 more than one within 20 m (the records 2.0). The ring forest before paid 1.7, 4.1, 6.6, 9.0
    and 12.4 at det 70, 60, 51, 43 and 30 m without spread (excess 0.0-0.2). What is left: the records fall more
    steeply with the distance (det 12 m over the bins, here 4-6 m) and spread less far out (excess 1.0 at 50-70 m,
    here 1.4-2.4). The records are trained policies' drops, these blind ones: no record shows the forest itself."""
    sdd, reward, det = original_per_drop()
    pay, distance, excess = ours
    assert np.abs(pay - np.array(binned(sdd, reward))).max() < 0.7
    assert np.abs(distance - np.array(binned(sdd, det))).max() < 7.5
    assert abs(distance.mean() - np.mean(binned(sdd, det))) < 4.0
    assert excess.min() > 1.2 and np.abs(excess[:2] - np.array(binned(sdd, reward - hinge(det)))[:2]).max() < 0.6
    assert 0.5 < pay[-1] - pay[0] < 2.5


def test_a_blind_straight_flight_no_longer_pays_far_more_than_a_drop_near_the_station():
    """The ring forest beyond an 80 m clearing paid a drop 80-100 m out in any direction r_s + r_d 16-17 on average
    (the note), which the committed record's seed 0 learned. The fitted forest thins towards the station without a
    ring: averaged over 72 directions of 12 worlds (level 1), r_s is 4.5 at 10 m, 6.0 at 60 m and 6.5-6.8 at 80-100 m
    (det 64-69 m throughout), so a drop 80-100 m out earns r_s + r_d 10.5-11.8, about 6 more than one 10 m out (5.0),
    where the records' drops earn about 2 more 50-70 m out than within 20 m."""
    compiled = hivex_dsl.compile({"hivex": 1, "environment": ENV, "task": "main"})
    state = compiled.entry.make_simulator(compiled).reset(np.random.default_rng(0), 12)
    directions = np.linspace(0.0, 2.0 * np.pi, 72, endpoint=False)
    rays = np.stack([np.cos(directions), np.sin(directions)], axis=-1)
    pay = {}
    for out in (10.0, 60.0, 90.0):
        det = []
        for world in range(12):
            trees = state.tree_xy[world].reshape(-1, 2)
            trees = trees[trees[:, 0] < FAR_M]
            points = state.station[world, :2] + out * rays
            det.append(np.sqrt(((points[:, None, :] - trees[None]) ** 2).sum(-1)).min(axis=1))
        pay[out] = seed_reward(np.concatenate(det), np.full(12 * 72, np.inf), 2.5, 75.0, 20.0).mean() + 10.0 * out / 200
    assert pay[10.0] > 4.0 and pay[60.0] - pay[10.0] < 5.0 and pay[90.0] < 12.5


def test_no_world_grows_without_trees_and_none_grows_in_the_station_s_clearing():
    """The patch noise is normalised over each world's land outside the clearing, so every world's highest patch
    clears the threshold: over 64 worlds the sparsest grows 20 trees (2 under 50, median 114), none within
    station_clear_radius_m (45 m) of the station."""
    compiled = hivex_dsl.compile({"hivex": 1, "environment": ENV, "task": "main"})
    state = compiled.entry.make_simulator(compiled).reset(np.random.default_rng(3), 64)
    trees = state.tree_xy[..., 0] < FAR_M
    assert trees.sum(axis=(1, 2)).min() >= 10
    out = np.hypot(*(state.tree_xy - state.station[:, None, None, :2]).transpose(3, 0, 1, 2))
    assert out[trees].min() > compiled.generators["forest"].station_clear_radius_m
