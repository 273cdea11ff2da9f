"""Per-episode statistics under the published names: coverage of the published file, sums, infos."""

from __future__ import annotations

import dataclasses
import itertools

import numpy as np
import pytest

import hivex_dsl
from hivex_dsl.evaluation import published
from hivex_dsl.evaluation.original.curves import original_cells
from hivex_dsl.compiler import registry
from hivex_dsl.evaluation.policies import make_policy
from hivex_dsl.runtime import BatchedEnv
from hivex_dsl.sim.statistics import RunningMeans, StatisticSet, episode_mean, pooled


@pytest.mark.parametrize("env_id", published.environments())
def test_every_published_statistic_is_computed_or_listed_as_not_computable(env_id):
    statistics = registry.get(env_id).statistics
    logged = {name for c in published.cells(env_id) for name in c.statistics if name != published.RETURN}
    declared = {statistics.logged_name(n) for n in statistics.names + tuple(statistics.not_computed)}
    assert logged <= declared
    # beyond the published ones: statistics the original's own pages plot (its curves, not its test results)
    plotted = {panel for cell in original_cells(env_id) for panel in cell.panels}
    assert {name.split("/", 1)[1] for name in declared - logged} <= plotted
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


def test_opc_local_is_collect_trash_s_episode_sum_and_global_a_running_mean_of_the_shared_terms():
    """Local Reward is a mirror of Collect Trash alone, its episode sum (the original adds it once per vessel-episode
    and leaves the crash out: tests/fidelity/test_opc_local.py); Global Reward the running mean of the shared terms'
    pay (the original adds that running total each time it changes; see the reward table's notes)."""
    compiled = hivex_dsl.compile({"hivex": 1, "environment": "ocean_plastic_collection", "agents": 3,
                                  "episode_length": 150, "decision_period": 1})  # a step() call is a physics step
    statistics = compiled.entry.statistics
    assert statistics["Local Reward"].kind == "mirror" and statistics["Local Reward"].mirror == ("collect_trash",)
    shared = statistics["Global Reward"].running_mean
    assert shared == ("lowest_collected_trash_count",)
    env, records = _roll(compiled, policy="scripted")
    stats = env.statistic_sums()
    pay = np.array([sum(compiled.weights[t] * values[t] for t in shared if t in values)
                    for _, _, values, _ in records])  # (T, batch, agents)
    totals = np.cumsum(pay, axis=0)
    changed = pay != 0
    expected = np.divide((totals * changed).sum(axis=0), changed.sum(axis=0),
                         out=np.zeros(env.shape), where=changed.any(axis=0))
    np.testing.assert_allclose(stats["Global Reward"], expected)
    collected = np.array([values["collect_trash"] for _, _, values, _ in records]).sum(axis=0)
    np.testing.assert_allclose(stats["Local Reward"], compiled.weights["collect_trash"] * collected)
    assert np.any(stats["Local Reward"] > 1) and np.any(stats["Global Reward"] > 0)


def _running(*terms: str) -> RunningMeans:
    stats = StatisticSet("ocean_plastic_collection", "OceanPlasticCollector")
    stats.running_mean("Total", "a running total's mean", *terms)
    return RunningMeans(stats, ("collect_trash", "collide_with_trash"), (1, 2))


def _steps(running: RunningMeans, pays: list[tuple[float, float]], weights=None) -> None:
    """Add one step per entry: (collect_trash, collide_with_trash) values of both agents of one world."""
    weights = weights or {"collect_trash": 1.0, "collide_with_trash": 1.0}
    for collect, collide in pays:
        running.add(weights, {"collect_trash": np.full((1, 2), collect), "collide_with_trash": np.full((1, 2), collide)})


def test_a_running_mean_averages_the_running_total_over_the_steps_it_changed_on():
    running = _running("collect_trash")
    _steps(running, [(0, 0), (1, 0), (0, 0), (0, 0), (1, 0), (1, 0), (0, 0)])  # pay 1 at steps 2, 5 and 6
    assert running.values()["Total"].tolist() == [[2.0, 2.0]]  # totals 1, 2, 3 -> 2
    assert running.counts["Total"].tolist() == [[3, 3]]
    nothing = _running("collect_trash")
    _steps(nothing, [(0, 0)] * 5)
    assert nothing.values()["Total"].tolist() == [[0.0, 0.0]]  # no change: 0, not a division by zero


def test_a_running_mean_of_a_penalty_and_of_two_terms_firing_together():
    penalty = _running("collect_trash")
    _steps(penalty, [(1, 0), (0, 0), (1, 0)], weights={"collect_trash": -1.0, "collide_with_trash": 1.0})
    assert penalty.values()["Total"].tolist() == [[-1.5, -1.5]]  # totals -1, -2
    both = _running("collect_trash", "collide_with_trash")
    _steps(both, [(1, 1), (0, 0), (1, 1), (1, 0)])  # pay 2, 2, then 1
    assert both.values()["Total"].tolist() == [[(2 + 4 + 5) / 3] * 2]
    inactive = _running("collide_with_trash", "crossed_border")  # only active terms are read
    assert inactive.terms["Total"] == ("collide_with_trash",)


def test_a_running_mean_restarts_with_an_agent_episode_and_pools_over_episodes():
    running = _running("collect_trash")
    _steps(running, [(1, 0), (1, 0), (1, 0)])  # totals 1, 2, 3 for both agents
    first = (running.sums["Total"][0, 1], running.counts["Total"][0, 1])
    assert first == (6.0, 3)
    running.clear(np.array([[False, True]]))  # agent 1's episode ends alone; agent 0 plays on
    assert running.values()["Total"].tolist() == [[2.0, 0.0]]
    _steps(running, [(0, 0), (5, 0)])  # agent 0: totals 1, 2, 3, 8; agent 1 anew: 5
    assert running.values()["Total"].tolist() == [[3.5, 5.0]]
    # pooled over agent 1's two episodes (counts 3 and 1): (6 + 5) / 4, not the mean of 2 and 5
    sums = np.array([first[0], running.sums["Total"][0, 1]])
    counts = np.array([first[1], running.counts["Total"][0, 1]])
    assert pooled(sums, counts) == 11 / 4
    assert episode_mean(sums, counts).tolist() == [2.0, 5.0]
    assert pooled(np.zeros(3), np.zeros(3, np.int64)) == 0.0


def test_the_runtime_clears_a_running_mean_where_an_agent_or_a_world_starts_again():
    """BatchedEnv accumulates the running means per physics step and restarts them with a respawned vessel (its
    episode ended alone) and a reset world, like the episode sums; checked against the terms' pay after it."""
    compiled = hivex_dsl.compile({"hivex": 1, "environment": "ocean_plastic_collection", "agents": 3,
                                  "episode_length": 300, "decision_period": 1})  # a step() call is a physics step
    terms = compiled.entry.statistics["Global Reward"].running_mean
    env = BatchedEnv(compiled, batch=2, split="test")
    observations = env.reset()
    act = make_policy("scripted", compiled, env.sim.action_space, env.shape, seed=3)
    pays = []
    for step in range(300):
        if step == 120:
            env.respawn_agents(np.array([[False, True, False], [False, False, False]]))
        if step == 150:
            env.reset_worlds(np.array([False, True]))
        result = env.step(act(observations))
        observations = result.observations
        pays.append((step, sum(compiled.weights[t] * result.terms[t] for t in terms if t in result.terms)))
    started = np.zeros(env.shape, np.int64)
    started[0, 1], started[1, :] = 120, 150
    expected = np.zeros(env.shape)
    for world, agent in np.ndindex(env.shape):
        pay = np.array([p[world, agent] for step, p in pays if step >= started[world, agent]])
        totals = np.cumsum(pay)[pay != 0]
        expected[world, agent] = totals.mean() if totals.size else 0.0
    np.testing.assert_allclose(env.statistic_sums()["Global Reward"], expected)
    assert np.count_nonzero(expected) == 6


def _spinning_env(restepped, statistics: StatisticSet) -> BatchedEnv:
    """Two worlds of three turbines logging ``statistics``, where an agent ends its episode when it rotates left
    (action 1), reset with seed 0."""
    from hivex_dsl.runtime import StepOutcome

    def spins(sim, state, actions, rng):
        new, outcome = sim.step(state, actions, rng)
        return new, StepOutcome(outcome.terminated, {"spun": np.asarray(actions) == 1})

    compiled = hivex_dsl.compile({"hivex": 1, "environment": "wind_farm_control", "agents": 3, "episode_length": 9})
    compiled = restepped(compiled, spins, {"spun": "rotated left"}, ("spun",))
    compiled = dataclasses.replace(compiled, entry=dataclasses.replace(compiled.entry, statistics=statistics))
    env = BatchedEnv(compiled, batch=2)
    env.reset(seed=0)
    return env


def test_counters_add_nothing_for_ended_agents_and_reset_clears_them(restepped):
    steps = StatisticSet("wind_farm_control", "WindFarmControl")
    steps.counter("Steps", "1 every step")(lambda prev, state, actions, params: np.ones(np.shape(actions)))
    env = _spinning_env(restepped, steps)
    env.step(np.array([[0, 1, 0], [0, 0, 0]]))
    for _ in range(4):
        env.step(np.zeros((2, 3), np.int64))
    assert env.statistic_sums()["Steps"].tolist() == [[5, 1, 5], [5, 5, 5]]
    assert env.episode_summary(0, 1)["statistics"] == {"Steps": 1.0}
    env.reset_worlds(np.array([True, False]))
    assert env.statistic_sums()["Steps"].tolist() == [[0, 0, 0], [5, 5, 5]]


def test_an_at_end_statistic_keeps_the_last_live_step_s_value_and_reset_clears_it(restepped):
    calls = itertools.count(1)  # the runtime reads its statistics once a step: the k-th step reads k
    clock = StatisticSet("wind_farm_control", "WindFarmControl")
    clock.at_end("Last Step", "the step the agent's episode ended on")(
        lambda prev, state, actions, params: np.full(np.shape(actions), float(next(calls))))
    env = _spinning_env(restepped, clock)
    for step in range(5):  # agent 1 of world 0 spins on the third step and ends there; the others play on
        env.step(np.array([[0, int(step == 2), 0], [0, 0, 0]]))
    assert env.statistic_sums()["Last Step"].tolist() == [[5, 3, 5], [5, 5, 5]]  # kept, not summed (1+2+3+4+5)
    env.reset_worlds(np.array([True, False]))
    assert (env.statistic_sums()["Last Step"][0]).tolist() == [0, 0, 0]


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
    held = sum(np.where(live, state.sighting.performance * state.support / 10, 0.0) for _, state, _, live in records)
    np.testing.assert_allclose(stats["Individual Performance"], held)  # P times the tower's resources
