"""A scenario's decision_period: one step is k physics steps with the action held (ML-Agents' DecisionRequester).

Every case is checked against a decision_period-1 env of the same scenario driven with each action repeated
k times from the same seed: observations at the decision boundaries are bit-identical, and a decision's
reward and term values are the left-to-right sums of its physics steps'.
"""

from __future__ import annotations

import numpy as np
import pytest

import hivex_dsl
from hivex_dsl.base.errors import ScenarioError
from hivex_dsl.runtime import BatchedEnv, StepOutcome

# generate energy and avoid damage both paid, a yaw term reading delta(), a schedule over env steps
WFC = {"hivex": 1, "environment": "wind_farm_control", "agents": 3, "episode_length": 20,
       "terms": {"yaw_change": {"expr": "where(abs(delta(heading_rad)) > 0.001, 1, 0)"}},
       "weights": {"avoid_damage": 1.0, "yaw_change": {"from": 0.0, "to": -1.0, "over_steps": 40}}}


def scenario(**fields):
    return hivex_dsl.compile(WFC | fields)


def actions_for(decisions: int, batch: int, agents: int = 3, seed: int = 0) -> np.ndarray:
    """(decisions, batch, agents) WFC actions (0 stay, 1 left, 2 right)."""
    return np.random.default_rng(seed).integers(0, 3, (decisions, batch, agents))


def physics_steps(env: BatchedEnv, actions: np.ndarray, k: int) -> tuple:
    """``actions`` repeated for k steps of a decision_period-1 env: (last transition, summed rewards, summed terms,
    OR-ed ended)."""
    steps = [env.step(actions) for _ in range(k)]
    rewards, terms, ended = steps[0].rewards, dict(steps[0].terms), steps[0].ended
    for step in steps[1:]:
        rewards = rewards + step.rewards
        terms = {name: value + step.terms[name] for name, value in terms.items()}
        ended = ended | step.ended
    return steps[-1], rewards, terms, ended


@pytest.mark.parametrize("k", [2, 5])
def test_a_decision_sums_k_physics_steps_of_the_held_action(k):
    batch, length = 2, 20
    ref, env = BatchedEnv(scenario(), batch=batch), BatchedEnv(scenario(decision_period=k), batch=batch)
    np.testing.assert_array_equal(ref.reset(seed=11), env.reset(seed=11))
    paid = False
    for d, actions in enumerate(actions_for(length // k, batch)):
        last, rewards, terms, ended = physics_steps(ref, actions, k)
        result = env.step(actions)
        np.testing.assert_array_equal(result.observations, last.observations)
        np.testing.assert_array_equal(result.rewards, rewards)
        assert result.terms.keys() == terms.keys()
        for name in terms:
            np.testing.assert_array_equal(result.terms[name], terms[name])
        np.testing.assert_array_equal(result.ended, ended)
        paid |= bool(np.all([np.any(v != 0) for v in terms.values()]))
        assert env.clock.tolist() == [(d + 1) * k] * batch and env.env_steps == ref.env_steps == (d + 1) * k * batch
    assert paid, "every term paid something: the sums are not trivially zero"
    np.testing.assert_array_equal(env.returns, ref.returns)
    for name in ref.term_sums:
        np.testing.assert_array_equal(env.term_sums[name], ref.term_sums[name])
    for name in ref.counter_sums:
        np.testing.assert_array_equal(env.counter_sums[name], ref.counter_sums[name])
    np.testing.assert_array_equal(env.lengths, length)  # physics steps
    np.testing.assert_array_equal(env.decisions, length // k)
    assert ref.decisions is ref.lengths  # decision_period 1: a decision is a step


@pytest.mark.parametrize("k", [1, 4])
def test_truncation_falls_after_episode_length_over_k_decisions(k):
    env = BatchedEnv(scenario(episode_length=8, decision_period=k), batch=3)
    env.reset(seed=0)
    for d in range(8 // k):
        result = env.step(np.zeros((3, 3), np.int64))
        last = d == 8 // k - 1
        assert result.truncated.all() == last and result.ended.all() == last and not result.terminated.any()
        assert env.world_endings(result).all() == last
    assert env.clock.tolist() == [8, 8, 8] and not env.alive.any()
    summary = env.episode_summary(2, 1)
    assert summary["length"] == 8 and summary["decisions"] == 8 // k


def ends_agent_at(step_number: int, world: int, agent: int, seen: list):
    """A simulator step that terminates (world, agent) on its ``step_number``-th call; ``seen`` gets every call's
    actions."""
    calls = [0]

    def step(sim, state, actions, rng):
        calls[0] += 1
        seen.append(np.array(actions))
        new, outcome = sim.step(state, actions, rng)
        terminated = outcome.terminated.copy()
        if calls[0] == step_number:
            terminated[world, agent] = True
        return new, StepOutcome(terminated, outcome.events)

    return step


def test_an_agent_ending_inside_a_period_ends_on_that_decision_and_earns_nothing_after(restepped):
    k = 5
    ref_seen, seen = [], []
    ref = BatchedEnv(restepped(scenario(), ends_agent_at(3, 0, 1, ref_seen)), batch=2)
    env = BatchedEnv(restepped(scenario(decision_period=k), ends_agent_at(3, 0, 1, seen)), batch=2)
    ref.reset(seed=5)
    env.reset(seed=5)
    actions = np.full((2, 3), 2, np.int64)  # rotate right: the placeholder (stay) differs from it
    last, rewards, terms, _ = physics_steps(ref, actions, k)
    result = env.step(actions)
    assert result.terminated.tolist() == [[False, True, False], [False, False, False]]
    assert result.ended.tolist() == result.terminated.tolist() and not result.truncated.any()
    np.testing.assert_array_equal(result.observations, last.observations)
    np.testing.assert_array_equal(result.rewards, rewards)
    for name in terms:
        np.testing.assert_array_equal(result.terms[name], terms[name])
    assert [a[0, 1] for a in seen] == [2, 2, 2, 0, 0]  # held as the placeholder after its ending
    assert [a[0, 0] for a in seen] == [2] * k and all(a[1].tolist() == [2, 2, 2] for a in seen)
    assert np.abs(ref.returns[0, 1]) > 0 and env.returns[0, 1] == ref.returns[0, 1]
    assert env.lengths[0].tolist() == [5, 3, 5] and env.decisions[0].tolist() == [1, 1, 1]
    assert env.alive.tolist() == [[True, False, True], [True, True, True]]
    after = env.step(actions)  # the ended agent earns nothing and ends nothing again
    assert after.rewards[0, 1] == 0 and not after.ended.any() and env.decisions[0].tolist() == [2, 1, 2]


def test_the_parallel_env_steps_decisions():
    k, length = 2, 8
    ref, env = hivex_dsl.parallel_env(scenario(episode_length=length)), hivex_dsl.parallel_env(
        scenario(episode_length=length, decision_period=k))
    ref_obs, _ = ref.reset(seed=3)
    obs, _ = env.reset(seed=3)
    for d, actions in enumerate(actions_for(length // k, 1)):
        act = {a: int(actions[0, i]) for i, a in enumerate(env.possible_agents)}
        totals = dict.fromkeys(act, 0.0)
        for _ in range(k):
            ref_obs, ref_rewards, _, ref_truncated, ref_infos = ref.step(act)
            totals = {a: totals[a] + ref_rewards[a] for a in act}
        obs, rewards, terminated, truncated, infos = env.step(act)
        assert rewards == totals and truncated == ref_truncated and not any(terminated.values())
        assert all(np.array_equal(obs[a], ref_obs[a]) for a in act)
        assert all(truncated.values()) == (d == length // k - 1)
    assert env.agents == [] and ref.agents == []
    for a in env.possible_agents:
        assert infos[a]["hivex_episode"]["length"] == length and infos[a]["hivex_episode"]["decisions"] == length // k
        assert infos[a]["hivex_episode"]["return"] == ref_infos[a]["hivex_episode"]["return"]


def test_the_vector_env_steps_decisions_and_restarts_after_the_last():
    k, length, worlds = 4, 8, 2
    ref = hivex_dsl.vector_env(scenario(episode_length=length), num_worlds=worlds)
    env = hivex_dsl.vector_env(scenario(episode_length=length, decision_period=k), num_worlds=worlds)
    np.testing.assert_array_equal(ref.reset(seed=9)[0], env.reset(seed=9)[0])
    for d, actions in enumerate(actions_for(length // k + 1, worlds * 3, agents=1)[..., 0]):
        steps = [ref.step(actions) for _ in range(k if d < length // k else 1)]
        obs, rewards, terminated, truncated, infos = env.step(actions)
        np.testing.assert_array_equal(obs, steps[-1][0])
        summed = steps[0][1]
        for step in steps[1:]:
            summed = summed + step[1]
        np.testing.assert_array_equal(rewards, summed)
        assert truncated.all() == (d == length // k - 1) and not terminated.any()
        if d == length // k - 1:
            np.testing.assert_array_equal(infos["hivex_episode"]["length"], length)
            np.testing.assert_array_equal(infos["hivex_episode"]["decisions"], length // k)  # step() calls
            np.testing.assert_array_equal(infos["hivex_episode"]["return"], steps[-1][4]["hivex_episode"]["return"])
    assert env.core.clock.tolist() == [0, 0]  # the fifth step restarted both worlds (NEXT_STEP) without stepping


def test_pettingzoo_s_max_cycles_counts_step_calls_which_are_decisions():
    from hivex_dsl.zoo import wind_farm_control_v0

    env = wind_farm_control_v0.parallel_env(max_cycles=5, decision_period=4)
    assert env.core.compiled.episode_length == 20  # 5 cycles of 4 physics steps
    env.reset(seed=0)
    for cycle in range(5):
        _, _, _, truncations, _ = env.step({agent: 0 for agent in env.agents})
    assert all(truncations.values()) and not env.agents
    with pytest.raises(ValueError, match=r"a compiled scenario cannot take \['max_cycles'\]"):
        wind_farm_control_v0.parallel_env(scenario(), max_cycles=5)


def test_a_period_that_does_not_divide_the_episode_length_is_a_located_error(tmp_path):
    path = tmp_path / "s.yaml"
    path.write_text("hivex: 1\nenvironment: wind_farm_control\nepisode_length: 12\ndecision_period: 5\n")
    with pytest.raises(ScenarioError) as caught:
        hivex_dsl.compile(path)
    (problem,) = caught.value.problems
    assert (problem.location.line, problem.location.col) == (4, 18)
    assert problem.message.startswith("decision_period: episode_length 12 is not a multiple of decision_period 5: ")
    assert "10 or 15" in problem.message
    for bad in (0, 101, 2.5, True):
        with pytest.raises(ScenarioError, match="decision_period"):
            hivex_dsl.compile({"hivex": 1, "environment": "wind_farm_control", "decision_period": bad})


def test_decision_period_sweeps_and_a_bad_point_is_located_at_its_value(tmp_path):
    compiled = hivex_dsl.compile_all({"hivex": 1, "environment": "wind_farm_control", "episode_length": 10,
                                      "sweep": {"decision_period": [1, 2, 5]}})
    assert [sc.decision_period for sc in compiled] == [1, 2, 5]
    assert [sc.episode_decisions for sc in compiled] == [10, 5, 2]
    assert compiled[0].name == "scenario[decision_period=1]" and len({sc.fingerprint for sc in compiled}) == 3
    path = tmp_path / "sweep.yaml"
    path.write_text("hivex: 1\nenvironment: wind_farm_control\nepisode_length: 10\n"
                    "sweep:\n  decision_period: [2, 3]\n")
    with pytest.raises(ScenarioError) as caught:
        hivex_dsl.compile_all(path)
    (problem,) = caught.value.problems
    assert (problem.location.line, problem.location.col) == (5, 24)
    assert "episode_length 10 is not a multiple of decision_period 3" in problem.message


def test_a_period_of_one_leaves_the_resolved_scenario_and_fingerprint_as_they_were():
    plain = hivex_dsl.compile({"hivex": 1, "environment": "wind_farm_control"})
    explicit = hivex_dsl.compile({"hivex": 1, "environment": "wind_farm_control", "decision_period": 1})
    assert "decision_period" not in plain.resolved() and plain.resolved() == explicit.resolved()
    assert plain.fingerprint == explicit.fingerprint and plain.to_lock() == explicit.to_lock()
    five = hivex_dsl.compile({"hivex": 1, "environment": "wind_farm_control", "decision_period": 5})
    assert five.resolved()["decision_period"] == 5 and five.fingerprint != plain.fingerprint
    relocked = hivex_dsl.compile(five.to_lock())
    assert relocked.decision_period == 5 and relocked.fingerprint == five.fingerprint


def test_an_environment_whose_default_period_is_not_one_writes_its_period_whatever_it_is():
    """DBR decides every 5th step by default: its resolved scenario says so, and one set to 1 says 1, so that a lock
    of either compiles back to its own period (an omitted period would read as the default)."""
    default = hivex_dsl.compile({"hivex": 1, "environment": "drone_based_reforestation"})
    one = hivex_dsl.compile({"hivex": 1, "environment": "drone_based_reforestation", "decision_period": 1})
    assert default.decision_period == 5 and default.resolved()["decision_period"] == 5
    assert one.resolved()["decision_period"] == 1 and one.fingerprint != default.fingerprint
    for compiled in (default, one):
        relocked = hivex_dsl.compile(compiled.to_lock())
        assert relocked.decision_period == compiled.decision_period and relocked.fingerprint == compiled.fingerprint


def test_max_cycles_counts_decisions_of_the_environment_s_default_period():
    from hivex_dsl.zoo import ocean_plastic_collection_v0

    env = ocean_plastic_collection_v0.parallel_env(max_cycles=7)
    assert env.core.compiled.decision_period == 5 and env.core.compiled.episode_length == 35


def test_the_trainer_counts_decisions(tmp_path, monkeypatch):
    pytest.importorskip("torch")
    from hivex_dsl.adapters.gymnasium import HivexVectorEnv
    from hivex_dsl.train.config import make_config
    from hivex_dsl.train.ppo import train

    calls, episodes = [0], []
    real_step = HivexVectorEnv.step

    def counting(self, actions):
        out = real_step(self, actions)
        calls[0] += 1
        done = out[2] | out[3]
        episodes.extend(zip(self.core.decisions.reshape(-1)[done].tolist(), self.core.lengths.reshape(-1)[done].tolist()))
        return out

    monkeypatch.setattr(HivexVectorEnv, "step", counting)
    compiled = scenario(agents=2, episode_length=8, decision_period=2)
    cfg = make_config("wind_farm_control", {"num_worlds": 1, "buffer_size": 16, "batch_size": 16, "num_epoch": 1,
                                            "hidden_units": 8, "max_steps": 48, "checkpoint_every": 48,
                                            "torch_threads": 1})
    summary = train(compiled, cfg, tmp_path, progress=False)
    assert summary["agent_steps"] == 48 == calls[0] * 2  # env.step calls (decisions) x slots
    assert episodes and set(episodes) == {(4, 8)}  # 4-decision episodes of 8 physics steps


def test_the_audit_reads_a_terms_range_as_that_of_a_decisions_sum():
    from hivex_dsl.evaluation.audit import audit_scenario, contract_flags, decision_range

    # a fast turn, so that the scripted turbines face the wind and sum more than 1 a decision within 100 steps
    audit = audit_scenario(scenario(episode_length=100, decision_period=5, params={"rotation_speed_deg": 5.0}),
                           episodes=1)
    assert not audit.flags
    trace = audit.rollouts["scripted"].traces["generate_energy"]
    contract = next(c for c in audit.compiled.term_contracts if c.name == "generate_energy")
    assert trace.high > contract.high  # five steps of up to 1 each: read per step, the range would be broken
    assert [f.kind for f in contract_flags(contract, trace, "scripted", 1)] == ["contract_range"]
    assert decision_range(contract, 5) == (0.0, 5.0)


def test_the_training_log_counts_episode_lengths_in_decisions_where_a_summary_has_them():
    from hivex_dsl.train.logs import episode_summaries

    summary = {"return": np.array([1.0, 0.0, 2.0]), "length": np.array([10, 0, 20]), "decisions": np.array([2, 0, 4])}
    infos = {"hivex_episode": summary, "_hivex_episode": np.array([True, True, True])}
    assert episode_summaries(infos)["length"].tolist() == [2, 4]  # the empty episode (0 decisions) left out
    del summary["decisions"]  # a summary of before decision periods: its steps were its decisions
    assert episode_summaries(infos)["length"].tolist() == [10, 20]


def test_a_rollout_counts_each_agents_decisions_an_ending_inside_a_period_included():
    """Random vessels (period 5) crash between decisions: a vessel-episode of n physics steps lasted ceil(n / 5)
    decisions, which the rollout keeps beside the physics steps (`hivex evaluate`'s Episode Length reads them)."""
    from hivex_dsl.evaluation.rollout import rollout

    compiled = hivex_dsl.compile({"hivex": 1, "environment": "ocean_plastic_collection"})
    played = rollout(compiled, "random", 4)
    assert compiled.decision_period == 5
    np.testing.assert_array_equal(played.decisions, -(-played.lengths // 5))
    assert (played.lengths % 5 != 0).any()  # some ended inside a period
    assert (played.decisions < compiled.episode_decisions).all()
