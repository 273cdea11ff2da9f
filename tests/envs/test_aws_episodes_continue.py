"""Aerial Wildfire Suppression's ``episodes_continue``: the release's MaxStep continues the world (issue 52).

In the hivex team's compiled AWS build (the reward table's notes) an episode cut by MaxStep only calls each
plane's OnEpisodeBegin, which respawns it and clears its own flags; the island, the forest and its fire, the
AgentManager's count of AgentDone calls and the CityGenerator's flag that fire reached the village go on, and
only TriggerDone (the count reaching the plane count; a fire going out makes every flying plane call it)
draws a new world. TooCloseToCityReward pays each plane once an episode while that flag is set, so a world
whose fire reached the village costs its planes again on the first step of every episode after.
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np

import hivex_dsl
from hivex_dsl.envs.aerial_wildfire_suppression import statistics, terms
from hivex_dsl.runtime import BatchedEnv


def compiled(**params):
    return hivex_dsl.compile({"hivex": 1, "environment": "aerial_wildfire_suppression", "task": "main", "agents": 3,
                              "episode_length": 3000, "seeds": {"train": 5000, "test": 6000},
                              "params": {"finished_planes": "wait", **params}})


def zeros(env: BatchedEnv) -> dict:
    shape = (env.batch, env.agents, 1)
    return {"continuous": np.zeros(shape, np.float32), "discrete": np.zeros(shape, np.int64)}


def played(continues: int, finishes, burning, steps: int = 40) -> tuple[BatchedEnv, object]:
    """Three worlds after ``steps`` straight-flight steps, their count of finishes and fire set by hand; returns
    the env and a copy of the state before the new episodes."""
    env = BatchedEnv(compiled(episodes_continue=continues), batch=3)
    env.reset(seed=0)
    for _ in range(steps):
        env.step(zeros(env))
    env.state = replace(env.state, finishes=np.asarray(finishes, np.int64), burning=np.asarray(burning, bool))
    before = replace(env.state, fire=replace(env.state.fire, trees=env.state.fire.trees.copy()),
                     position=env.state.position.copy())
    return env, before


def test_a_world_cut_by_the_time_limit_goes_on_with_its_fire_and_count_and_respawned_planes():
    # world 0: burning, one finish counted (MaxStep cut it); world 1: the fire went out; world 2: three finishes
    env, before = played(1, finishes=[1, 0, 3], burning=[True, False, True])
    env.reset_worlds(np.ones(3, bool))
    after = env.state
    np.testing.assert_array_equal(after.fire.trees[0], before.fire.trees[0])
    np.testing.assert_array_equal(after.maps.height[0], before.maps.height[0])
    np.testing.assert_array_equal(after.maps.village[0], before.maps.village[0])
    assert after.finishes.tolist() == [1, 0, 0] and after.tick == before.tick
    assert after.flying.all()
    assert not np.allclose(after.position[0], before.position[0])  # every plane of the going world respawned
    for fresh in (1, 2):  # TriggerDone's worlds: a new island ('episode') and a new fire
        assert not np.array_equal(after.maps.height[fresh], before.maps.height[fresh])


def test_without_it_every_episode_starts_a_fresh_world():
    env, before = played(0, finishes=[1, 0, 0], burning=[True, True, True])
    env.reset_worlds(np.ones(3, bool))
    for world in range(3):
        assert not np.array_equal(env.state.maps.height[world], before.maps.height[world])


def test_a_fire_that_reached_the_village_costs_every_plane_again_on_the_next_episode_s_first_step():
    env, _ = played(1, finishes=[0, 0, 0], burning=[True, True, True])
    reached = np.array([True, False, False])
    env.state = replace(env.state, village_reached=reached, village_hit=reached.copy())
    env.reset_worlds(np.array([True, True, False]))
    assert env.state.village_hit.tolist() == [False, False, False] and env.state.village_reached.tolist() == [
        True, False, False]
    prev = env.state
    env.step(zeros(env))
    new = env.state
    assert not new.sighting.village_threat[0]  # no tree burns near the village now: the kept flag pays
    params = env.compiled.params
    np.testing.assert_array_equal(terms.too_close_to_village(prev, new, None, params)[0], [-50.0] * 3)
    np.testing.assert_array_equal(statistics.fire_too_close_to_city(prev, new, None, params)[0], [True] * 3)
    assert not new.village_threatened[1]  # world 1's fire never came near: nothing owed
    env.step(zeros(env))
    assert not env.state.village_threatened[0]  # once an episode
