"""Expression terms, endings, shaping and schedules of a scenario behave like registered terms end to end."""

from __future__ import annotations

import numpy as np
import pytest

import hivex_dsl
from hivex_dsl.compiler import compile_loaded
from hivex_dsl.lang.loader import Loaded
from hivex_dsl.runtime import BatchedEnv

WFC = {"hivex": 1, "environment": "wind_farm_control", "agents": 3, "episode_length": 50}


def _scenario(**extra):
    return hivex_dsl.compile(WFC | extra)


def test_expression_terms_reach_the_lock_and_the_fingerprint():
    compiled = _scenario(terms={"facing": {"expr": "alignment", "title": "Facing"}},
                         weights={"facing": {"from": 1, "to": 0, "over_steps": 10, "kind": "step"}},
                         ends_on=["team_min(alignment) > 0.999"])
    lock = compiled.to_lock()
    assert lock["term_contracts"]["facing"]["equation"] == "alignment"
    assert lock["scenario"]["terms"] == {"facing": {"expr": "alignment", "title": "Facing"}}
    assert lock["scenario"]["ends_on"] == ["team_min(alignment) > 0.999"]
    again = compile_loaded(Loaded("<lock>", lock))[0]
    assert again.fingerprint == compiled.fingerprint
    assert again.schedules["facing"].at(10) == 0.0
    changed = _scenario(terms={"facing": {"expr": "alignment * 1", "title": "Facing"}},
                        weights={"facing": {"from": 1, "to": 0, "over_steps": 10, "kind": "step"}},
                        ends_on=["team_min(alignment) > 0.999"])
    assert changed.fingerprint != compiled.fingerprint


def test_parallel_env_reports_expression_terms_and_their_episode_sums():
    env = hivex_dsl.parallel_env(WFC | {"terms": {"facing": {"expr": "alignment"}}, "episode_length": 5})
    env.reset(seed=0)
    total = {agent: 0.0 for agent in env.agents}
    for _ in range(5):
        _, _, _, truncated, infos = env.step({agent: 0 for agent in env.agents})
        for agent, info in infos.items():
            assert set(info["reward_terms"]) == {"generate_energy", "facing"}
            total[agent] += info["reward_terms"]["facing"]
    assert all(truncated.values())
    for agent_index, agent in enumerate(env.possible_agents):
        summary = env.core.episode_summary(0, agent_index)
        assert summary["reward_terms"]["facing"] == pytest.approx(total[agent], abs=1e-12)


def test_an_expression_ending_ends_exactly_the_agents_it_holds_for():
    compiled = _scenario(ends_on=["x_m > 0"])
    env = BatchedEnv(compiled, batch=2)
    env.reset(seed=4)
    transition = env.step(np.zeros(env.shape, int))
    np.testing.assert_array_equal(transition.terminated, env.state.positions[..., 0] > 0)


def test_a_per_world_ending_ends_every_agent_of_its_world():
    env = BatchedEnv(_scenario(ends_on=["main_wind_direction_rad > -10"]), batch=2)
    env.reset(seed=4)
    assert env.step(np.zeros(env.shape, int)).terminated.all()


def test_shaping_with_gamma_one_telescopes_to_the_change_of_the_potential():
    compiled = _scenario(shaping={"potential": "alignment * 3", "gamma": 1.0})
    env = BatchedEnv(compiled, batch=2)
    env.reset(seed=9)
    start = 3 * env.feed.now["alignment"]
    rng = np.random.default_rng(0)
    total = np.zeros(env.shape)
    for _ in range(30):
        total += env.step(rng.integers(0, 3, env.shape)).terms["shaping"]
    np.testing.assert_allclose(total, 3 * env.feed.now["alignment"] - start, atol=1e-9)


def test_a_step_schedule_switches_at_over_steps_on_the_env_step_clock():
    compiled = _scenario(terms={"facing": {"expr": "alignment"}},
                         weights={"generate_energy": 0, "facing": {"from": 0, "to": 2, "over_steps": 6, "kind": "step"}})
    env = BatchedEnv(compiled, batch=3)
    env.reset(seed=1)
    first = env.step(np.zeros(env.shape, int))  # clock 0
    second = env.step(np.zeros(env.shape, int))  # clock 3
    third = env.step(np.zeros(env.shape, int))  # clock 6: switched
    assert env.env_steps == 9
    np.testing.assert_array_equal(first.rewards, 0.0 * first.terms["facing"])
    np.testing.assert_array_equal(second.rewards, 0.0 * second.terms["facing"])
    np.testing.assert_allclose(third.rewards, 2.0 * third.terms["facing"], atol=0)


def test_a_term_reading_nothing_the_simulator_changes_is_still_evaluated_every_step():
    env = BatchedEnv(_scenario(terms={"where_am_i": {"expr": "x_m / 600"}}), batch=1)
    env.reset(seed=0)
    value = env.step(np.zeros(env.shape, int)).terms["where_am_i"]
    np.testing.assert_allclose(value, env.state.positions[..., 0] / 600)


def test_a_sweep_may_range_over_the_weight_of_a_declared_term():
    compiled = hivex_dsl.compile_all(WFC | {"terms": {"facing": {"expr": "alignment"}},
                                            "sweep": {"weights.facing": [0.5, 2.0]}})
    assert [c.weights["facing"] for c in compiled] == [0.5, 2.0]


def test_a_bare_expression_is_short_for_a_term_with_only_expr():
    short = _scenario(terms={"facing": "alignment"})
    long = _scenario(terms={"facing": {"expr": "alignment"}})
    assert short.fingerprint == long.fingerprint
    assert short.resolved()["terms"] == {"facing": {"expr": "alignment"}}


def test_a_respawned_agent_starts_its_prev_from_where_it_respawned():
    compiled = hivex_dsl.compile({"hivex": 1, "environment": "ocean_plastic_collection", "agents": 2,
                                  "episode_length": 50, "terms": {"moved": "abs(delta(x_m)) + abs(delta(y_m))"}})
    env = BatchedEnv(compiled, batch=1)
    env.reset(seed=3)
    env.step(np.tile([1, 0], (1, 2, 1)))
    before = env.state.position.copy()
    env.respawn_agents(np.array([[True, False]]))
    np.testing.assert_array_equal(env.feed.now["x_m"][0], [env.state.position[0, 0, 0], before[0, 1, 0]])
    respawned_at = env.state.position[0, 0].copy()
    assert np.abs(respawned_at - before[0, 0]).sum() > 1.0  # the respawn moved the vessel away
    moved = env.step(np.tile([0, 0], (1, 2, 1))).terms["moved"]
    top_speed = compiled.params.acceleration / compiled.params.drag
    assert moved[0, 0] <= 2 * top_speed  # one coasting step from the respawn point, no jump from the old place
    np.testing.assert_allclose(moved[0, 0], np.abs(env.state.position[0, 0] - respawned_at).sum(), atol=1e-9)


def test_an_expression_written_from_the_prose_pays_what_nearby_trash_count_delta_pays():
    """Nearby Trash Count Delta rewritten in the language, as the paper's prose states it (the rise of the
    nearby count above the highest it has been), pays every vessel the built-in term's episode sum."""
    scenario = {"hivex": 1, "environment": "ocean_plastic_collection", "task": "find_highest_polluted_area",
                "episode_length": 60, "terms": {"rise": {"expr": "max(0, pebbles_nearby - prev(pebbles_nearby_best))"}},
                "weights": {"rise": 1}}
    env = hivex_dsl.parallel_env(scenario)
    env.reset(seed=3)
    rng = np.random.default_rng(3)
    while env.agents:
        env.step({agent: rng.integers(0, [2, 3]) for agent in env.agents})
    sums = [env.core.episode_summary(0, a)["reward_terms"] for a in range(len(env.possible_agents))]
    assert all(s["nearby_trash_count_delta"] > 0 for s in sums)
    for s in sums:
        assert s["rise"] == pytest.approx(s["nearby_trash_count_delta"], abs=1e-9)
