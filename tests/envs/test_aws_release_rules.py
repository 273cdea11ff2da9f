"""Aerial Wildfire Suppression under the release's own rules, by hand (issue 52, session 34).

The hivex team's compiled AWS build (the reward table's notes) turns a plane by a whole turnSpeed whatever
the steer's size (``turn_rule: full``), freezes a plane that crossed the border or met its task's end and ends
the episodes of all planes of a world together once the count of AgentManager.AgentDone calls reaches the plane
count (``finished_planes: wait``), charges the pick-up task's -100/3000 every step of that shared episode, pays
no Fire Out to a frozen plane, and lets a frozen finder of the village or the fire find it again (paid, counted)
every step it waits. Each test places planes exactly and compares with steps and returns worked out here.
"""

from __future__ import annotations

import math
from dataclasses import replace
from types import SimpleNamespace

import numpy as np
import pytest

import hivex_dsl
from hivex_dsl.envs.aerial_wildfire_suppression import statistics, terms
from hivex_dsl.runtime import BatchedEnv

from ..aws_rules import LONE_PLANES

RELEASE = {"finished_planes": "wait", "turn_rule": "full", "plane_speed_m": 5.0}
ISLAND = 600.0


def compiled(task: str, **params):
    return hivex_dsl.compile({"hivex": 1, "environment": "aerial_wildfire_suppression", "task": task, "agents": 3,
                              "episode_length": 3000, "seeds": {"train": 5000, "test": 6000}, "params": params})


def placed(env: BatchedEnv, xy, heading_deg) -> None:
    """Put world 0's planes at ``xy`` (A, 2) metres facing ``heading_deg`` (A,) degrees (0: +x)."""
    state = env.state
    env.state = replace(state, position=np.asarray(xy, float)[None], heading=np.radians(heading_deg)[None])


def zeros(env: BatchedEnv) -> dict:
    return {"continuous": np.zeros((1, env.agents, 1), np.float32), "discrete": np.zeros((1, env.agents, 1), np.int64)}


def test_a_full_turn_rule_turns_the_whole_rate_for_any_nonzero_steer():
    for rule, expected in (("full", [5.0, -5.0, 0.0]), ("proportional", [1.0, -0.05, 0.0])):
        env = BatchedEnv(compiled("main", turn_rule=rule))
        env.reset(seed=0)
        before = env.state.heading[0].copy()
        actions = zeros(env)
        actions["continuous"][0, :, 0] = [0.2, -0.01, 0.0]
        env.step(actions)
        turned = np.degrees((env.state.heading[0] - before + np.pi) % (2 * np.pi) - np.pi)
        np.testing.assert_allclose(turned, expected, atol=1e-9)


def steps_to_leave_the_island(x: float, y: float, heading_deg: float, speed: float) -> int:
    """The first step n of a straight flight at which max(|x|, |y|) > 600 (the water ring: the pick-up)."""
    c, s = math.cos(math.radians(heading_deg)), math.sin(math.radians(heading_deg))
    per_axis = [(ISLAND - p * math.copysign(1, v)) / abs(v) for p, v in ((x, c), (y, s)) if abs(v) > 1e-12]
    return math.floor(min(per_axis) / speed) + 1


def test_picked_up_planes_wait_for_the_last_and_all_pay_every_step():
    env = BatchedEnv(compiled("pick_up_water", **RELEASE))
    env.reset(seed=3)
    xy, heading = [(0.0, 0.0), (300.0, -100.0), (-250.0, 420.0)], [0.0, 90.0, 200.0]
    placed(env, xy, heading)
    own = [steps_to_leave_the_island(x, y, h, 5.0) for (x, y), h in zip(xy, heading)]
    assert own == [121, 141, 75]  # 600 / 5 + 1; 700 / 5 + 1; (600 - 250) / (5 cos 20) = 74.5, + 1 rounded down
    returns, step = np.zeros(3), 0
    while True:
        step += 1
        result = env.step(zeros(env))
        returns += result.rewards[0]
        if step == own[2] + 1:
            frozen = env.state.position[0, 2].copy()
        if step == own[2] + 5:
            np.testing.assert_array_equal(env.state.position[0, 2], frozen)  # a waiting plane stays
        if result.ended[0].any():
            break
    assert step == max(own)  # the world ends when its last plane picks up
    assert result.terminated[0].all() and result.world_terminated[0]
    assert env.world_endings(result)[0]  # so a vector env starts the world afresh, not the planes one by one
    np.testing.assert_allclose(returns, 100 - max(own) / 30)  # -100/3000 every step, the pick-up's too
    np.testing.assert_array_equal(env.lengths[0], [max(own)] * 3)


def test_a_frozen_finder_of_the_village_finds_it_again_and_ends_its_world_two_steps_later():
    # the horizontal distance, so the finding step is known without the terrain (test_aws_village_rules.py works the
    # release's 3-D distance by hand)
    env = BatchedEnv(compiled("find_village", **RELEASE, village_distance="horizontal"))
    env.reset(seed=4)
    village = env.state.maps.village[0]
    # plane 0 153 m west of the village flying east: inside 150 m after 1 step (148 m); the others 15 m on in 3
    # steps, still far from the village and the border
    xy = [village + (-153.0, 0.0), np.array([-400.0, -400.0]), np.array([400.0, 400.0])]
    far = [np.hypot(*(p - village)) for p in xy[1:]]
    assert min(far) > 150 + 3 * 5.0
    placed(env, xy, [0.0, 90.0, 270.0])
    paid = []
    for _ in range(3):
        result = env.step(zeros(env))
        paid.append(result.rewards[0].copy())
        assert not result.ended[0].any() or len(paid) == 3
    np.testing.assert_array_equal(np.array(paid), [[100, 0, 0], [100, 0, 0], [100, 0, 0]])
    assert result.terminated[0].all() and result.world_terminated[0]  # three AgentDone calls by one plane


def test_crashed_planes_wait_and_the_world_ends_with_the_last_crash():
    env = BatchedEnv(compiled("main", **RELEASE))
    env.reset(seed=5)
    xy = [(744.0, 0.0), (0.0, -740.0), (-700.0, 0.0)]  # border at 750: crossing after 2, 3 and 11 steps
    placed(env, xy, [0.0, 270.0, 180.0])
    crossed_at, step = {}, 0
    while not env.state.fire.out[0]:
        step += 1
        result = env.step(zeros(env))
        for plane in np.flatnonzero(env.state.crossed[0]):
            crossed_at[int(plane)] = step
        if result.ended[0].any():
            break
    assert crossed_at == {0: 2, 1: 3, 2: 11}
    assert step == 11 and result.terminated[0].all()
    np.testing.assert_array_equal(env.lengths[0], [11, 11, 11])


def test_fire_out_pays_and_counts_only_the_planes_still_flying():
    waiting = SimpleNamespace(finished_planes="wait")
    respawning = SimpleNamespace(finished_planes="respawn")
    state = SimpleNamespace(flying=np.array([[True, False, True]]), fire_went_out=np.array([True]))
    np.testing.assert_array_equal(terms.fire_out(None, state, None, waiting), [[10.0, 0.0, 10.0]])
    np.testing.assert_array_equal(terms.fire_out(None, state, None, respawning), [[10.0, 10.0, 10.0]])
    np.testing.assert_array_equal(statistics.fire_out(None, state, None, waiting), [[True, False, True]])
    np.testing.assert_array_equal(statistics.fire_out(None, state, None, respawning), [[True, True, True]])


def test_the_pick_up_tasks_cost_of_time_charges_waiting_planes_only_when_they_wait():
    params = SimpleNamespace(finished_planes="wait", water_wait_penalty=1 / 30)
    state = SimpleNamespace(flying=np.array([[True, True, False]]), water=np.array([[False, True, True]]))
    np.testing.assert_allclose(terms.time_step_without_water(None, state, None, params), [[-1 / 30, 0.0, -1 / 30]])
    params.finished_planes = "respawn"
    np.testing.assert_allclose(terms.time_step_without_water(None, state, None, params), [[-1 / 30, 0.0, 0.0]])


@pytest.mark.parametrize("params", [LONE_PLANES, RELEASE, {}])
def test_respawning_and_waiting_planes_keep_one_episode_per_plane_or_per_world(params):
    env = BatchedEnv(compiled("pick_up_water", **params))
    env.reset(seed=6)
    lengths = []
    for _ in range(400):
        result = env.step(zeros(env))
        if result.ended[0].any():
            lengths.append(env.lengths[0][result.ended[0]].tolist())
            break
    # a respawning plane ends alone on its pick-up; waiting ones (the default since session 43) all end together
    assert (len(lengths[0]) == 3) == (params.get("finished_planes", "wait") == "wait")


def test_the_rules_added_late_keep_the_fingerprints_of_the_lone_planes_and_of_the_release_s_rules():
    """The fingerprint leaves the rules added in sessions 34-38 out while they hold what was done before them (the
    lone planes' proportional turn, respawn, spawn and fresh worlds), so every record trained before them stays
    matched to its scenario; the defaults since session 43 (the release's rules) hash as the release's rules
    spelled out did, so the runs trained so before match today's main scenario; any other value is another world."""
    plain = compiled("main")
    release = {"finished_planes": "wait", "turn_rule": "full", "spawn_rule": "release", "episodes_continue": 1,
               "plane_speed_m": 5.0}
    assert compiled("main", **release).fingerprint == plain.fingerprint
    lone = compiled("main", **LONE_PLANES)
    before = dict(LONE_PLANES)
    del before["plane_speed_m"]  # not a late rule: always hashed
    assert compiled("main", plane_speed_m=3.0).fingerprint != lone.fingerprint  # the late rules count here
    assert {name: type(plain.params).added_fields()[name] for name in before} == before
    for name, value in (("finished_planes", "respawn"), ("turn_rule", "proportional"), ("spawn_rule", "ours")):
        assert compiled("main", **{name: value}).fingerprint != plain.fingerprint, name


def test_the_release_spawn_is_uniform_in_distance_along_directions_drawn_from_a_square():
    """RespawnAgent: a distance uniform on [0, 750] (mean 375, where a uniform draw over the disk has 500) along a
    direction normalised from a uniform point of [-1, 1]^2, which lies within 22.5 degrees of an axis with the
    chance of the four wedges' area over the square's, 4 tan(22.5) / 4 = 0.414 (0.5 for a uniform angle); and
    nothing is kept away from the village."""
    from hivex_dsl.envs.aerial_wildfire_suppression.simulator import AerialWildfireSimulator

    sim = AerialWildfireSimulator(compiled("pick_up_water", spawn_rule="release"))
    count = 4000
    village = np.zeros((count, 2))
    position, heading, water = sim._spawn(np.random.default_rng(0), count, village)
    distance = np.hypot(position[..., 0], position[..., 1]).ravel()
    assert distance.max() <= 750.0 and abs(distance.mean() - 375.0) < 4 * 750 / math.sqrt(12 * distance.size)
    angle = np.degrees(np.arctan2(position[..., 1], position[..., 0])).ravel() % 90.0
    near_axis = np.mean((angle < 22.5) | (angle > 67.5))
    assert abs(near_axis - math.tan(math.radians(22.5))) < 4 * math.sqrt(0.25 / distance.size)
    assert (distance < 150.0).any() and not water.any()  # inside the village radius too; no water in this task
