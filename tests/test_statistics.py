"""Per-episode statistics under the published names: coverage of the published file, sums, infos."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

import hivex_dsl
from hivex_dsl.evaluation import published
from hivex_dsl.compiler import registry
from hivex_dsl.evaluation.policies import make_policy
from hivex_dsl.runtime import BatchedEnv
from hivex_dsl.sim.statistics import StatisticSet


@pytest.mark.parametrize("env_id", published.environments())
def test_every_published_statistic_is_computed_or_listed_as_not_computable(env_id):
    statistics = registry.get(env_id).statistics
    logged = {name for c in published.cells(env_id) for name in c.statistics if name != published.RETURN}
    declared = {statistics.logged_name(n) for n in statistics.names + tuple(statistics.not_computed)}
    assert logged == declared
    assert all(len(why) > 20 for why in statistics.not_computed.values())


def _roll(compiled, policy="random", steps=None, batch=2):
    """Step ``batch`` worlds; returns the env and per-step (prev, state, term values, live) records."""
    env = BatchedEnv(compiled, batch=batch, split="test")
    observations = env.reset()
    act = make_policy(policy, compiled, env.sim.action_space, env.shape, seed=3)
    records = []
    for _ in range(steps or compiled.episode_length):
        live, prev = env.alive.copy(), env.state
        result = env.step(act(observations))
        observations = result.observations
        records.append((prev, env.state, result.terms, live))
        if not env.alive.any():
            break
    return env, records


def test_aws_counters_are_the_episode_counts_of_the_simulator_events():
    compiled = hivex_dsl.compile({"hivex": 1, "environment": "aerial_wildfire_suppression", "agents": 3,
                                  "episode_length": 250})
    env, records = _roll(compiled)
    stats = env.statistic_sums()
    pickups = sum(np.where(live, state.picked_up, 0) for _, state, _, live in records)
    crashes = sum(np.where(live, state.crossed, 0) for _, state, _, live in records)
    np.testing.assert_array_equal(stats["Water Pickup"], pickups)
    np.testing.assert_array_equal(stats["Crash Count"], crashes)
    assert stats["Crash Count"].max() <= 1  # a crash ends the plane's episode


def test_a_mirror_is_the_weighted_episode_sum_of_its_terms():
    compiled = hivex_dsl.compile({"hivex": 1, "environment": "aerial_wildfire_suppression", "task": "prepare_trees",
                                  "agents": 2, "episode_length": 200})
    env, records = _roll(compiled, policy="scripted")
    stats = env.statistic_sums()
    assert compiled.weights["preparing_tree"] == 5.0  # the paper's x5 of Preparing Trees in this task
    np.testing.assert_allclose(stats["Preparing Trees Reward"], 5.0 * stats["Preparing Trees"])
    np.testing.assert_allclose(stats["Extinguishing Trees Reward"], 5.0 * stats["Extinguishing Trees"])


def test_wfc_individual_performance_is_zero_where_the_task_does_not_pay_energy():
    main = hivex_dsl.compile({"hivex": 1, "environment": "wind_farm_control", "agents": 2, "episode_length": 30})
    avoid = hivex_dsl.compile({"hivex": 1, "environment": "wind_farm_control", "task": "avoid_damage", "agents": 2,
                               "episode_length": 30})
    env, _ = _roll(main)
    np.testing.assert_allclose(env.statistic_sums()["Individual Performance"], env.returns)
    env, _ = _roll(avoid)
    stats = env.statistic_sums()
    np.testing.assert_array_equal(stats["Individual Performance"], 0.0)
    np.testing.assert_allclose(stats["Avoid Damage Reward"], env.returns)


def test_dbr_best_so_far_statistics_are_the_best_values_reached():
    compiled = hivex_dsl.compile({"hivex": 1, "environment": "drone_based_reforestation", "agents": 2,
                                  "episode_length": 120})
    env, records = _roll(compiled)
    stats = env.statistic_sums()
    first_prev = records[0][0]
    np.testing.assert_allclose(stats["Highest Point on Terrain Found"], env.state.best_height - first_prev.best_height)
    np.testing.assert_allclose(stats["Furthest Distance Explored"],
                               env.state.best_distance - first_prev.best_distance)
    # every drop of some quality is one drop: the normalised distance of a drop is at most 1
    assert np.all(stats["Cumulative Normalized Distance Until Tree Drop"] <= stats["Tree Drop Count"] + 1e-12)


def test_opc_local_and_global_split_the_return():
    compiled = hivex_dsl.compile({"hivex": 1, "environment": "ocean_plastic_collection", "agents": 3,
                                  "episode_length": 150})
    env, _ = _roll(compiled)
    stats = env.statistic_sums()
    np.testing.assert_allclose(stats["Local Reward"] + stats["Global Reward"], env.returns)


def test_counters_add_nothing_for_ended_agents_and_reset_clears_them(restepped):
    from hivex_dsl.runtime import StepOutcome

    steps = StatisticSet("wind_farm_control", "WindFarmControl")
    steps.counter("Steps", "1 every step")(lambda prev, state, actions, params: np.ones(np.shape(actions)))

    def spins(sim, state, actions, rng):  # an agent ends its episode when it rotates left (action 1)
        new, outcome = sim.step(state, actions, rng)
        return new, StepOutcome(outcome.terminated, {"spun": np.asarray(actions) == 1})

    compiled = hivex_dsl.compile({"hivex": 1, "environment": "wind_farm_control", "agents": 3, "episode_length": 9})
    compiled = restepped(compiled, spins, {"spun": "rotated left"}, ("spun",))
    compiled = dataclasses.replace(compiled, entry=dataclasses.replace(compiled.entry, statistics=steps))
    env = BatchedEnv(compiled, batch=2)
    env.reset(seed=0)
    env.step(np.array([[0, 1, 0], [0, 0, 0]]))
    for _ in range(4):
        env.step(np.zeros((2, 3), np.int64))
    assert env.statistic_sums()["Steps"].tolist() == [[5, 1, 5], [5, 5, 5]]
    assert env.episode_summary(0, 1)["statistics"] == {"Steps": 1.0}
    env.reset_worlds(np.array([True, False]))
    assert env.statistic_sums()["Steps"].tolist() == [[0, 0, 0], [5, 5, 5]]


def test_episode_infos_carry_the_statistics_in_both_adapters():
    scenario = {"hivex": 1, "environment": "wind_farm_control", "agents": 2, "episode_length": 3}
    venv = hivex_dsl.vector_env(scenario, num_worlds=2)
    venv.reset(seed=1)
    for _ in range(3):
        *_, infos = venv.step(np.zeros(4, np.int64))
    episode = infos["hivex_episode"]
    np.testing.assert_allclose(episode["statistics"]["Individual Performance"], episode["return"])
    env = hivex_dsl.parallel_env(scenario)
    env.reset(seed=1)
    for _ in range(3):
        *_, infos = env.step({a: 0 for a in env.agents})
    summary = infos["turbine_0"]["hivex_episode"]
    assert summary["statistics"]["Individual Performance"] == pytest.approx(summary["return"])
    assert summary["statistics"]["Avoid Damage Reward"] == 0.0


def test_a_statistic_of_an_unknown_term_is_refused():
    stats = StatisticSet("wind_farm_control", "WindFarmControl")
    stats.mirror("Energy", "x", "no_such_term")
    assert stats.problems(("generate_energy",)) == ["wind_farm_control: a statistic refers to unknown reward term "
                                                     "'no_such_term'"]
    with pytest.raises(ValueError, match="declared twice"):
        stats.mirror("Energy", "again", "generate_energy")
    with pytest.raises(TypeError, match="must take"):
        stats.counter("Bad", "x")(lambda state: state)


def test_wrm_moving_resources_statistics_follow_the_task_weights():
    compiled = hivex_dsl.compile({"hivex": 1, "environment": "wildfire_resource_management", "task": "keep_all",
                                  "episode_length": 60})
    env, records = _roll(compiled)
    stats = env.statistic_sums()
    assert compiled.weights["watch_tower_performance"] == 10.0  # Keep All: the own tower x10
    np.testing.assert_allclose(stats["Reward for Moving Resources to Self"],
                               10.0 * env.term_sums["watch_tower_performance"])
    np.testing.assert_allclose(stats["Reward for Moving Resources to Neighbours"], env.term_sums["neighbour_performance"])
    performance = sum(np.where(live, state.sighting.performance, 0.0) for _, state, _, live in records)
    np.testing.assert_allclose(stats["Individual Performance"], performance)
