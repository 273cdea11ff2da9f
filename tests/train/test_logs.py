"""Episode summaries are read under either key name, only for the slots that ended, never empty ones."""

from __future__ import annotations

import numpy as np
import pytest

from hivex_dsl.train.logs import EpisodeLog, episode_summaries


def _infos(key: str):
    return {key: {"return": np.array([5.0, 0.0, 7.0, 0.0]), "length": np.array([10, 0, 12, 0]),
                  "reward_terms": {"a": np.array([5.0, 0.0, 7.0, 0.0])},
                  "statistics": {"Water Pickup": np.array([1.0, 0.0, 3.0, 0.0])}},
            f"_{key}": np.array([True, True, True, False])}


@pytest.mark.parametrize("key", ["hivex_episode", "episode"])
def test_summaries_of_ended_slots_only(key):
    summary = episode_summaries(_infos(key))
    # slot 1 ended with an empty episode (it restarted on the step its world ended): no experience
    assert summary["return"].tolist() == [5.0, 7.0]
    assert summary["statistics"]["Water Pickup"].tolist() == [1.0, 3.0]
    assert episode_summaries({"reward_terms": {}}) is None


def test_the_log_drains_means():
    log = EpisodeLog()
    log.record(_infos("hivex_episode"))
    log.record({"reward_terms": {}})
    drained = log.drain()
    assert drained["return"] == 6.0 and drained["episodes"] == 2 and drained["length"] == 11.0
    assert drained["reward_terms"] == {"a": 6.0} and drained["statistics"] == {"Water Pickup": 2.0}
    assert log.drain() == {}


def test_the_losses_are_the_mean_over_the_updates_since_the_last_point():
    log = EpisodeLog()
    log.record_losses({"entropy": 4.0, "curiosity_forward": 0.5})
    log.record_losses({"entropy": 3.0, "curiosity_forward": 0.25})
    assert log.drain() == {}  # no episode ended: no point, and the updates' losses wait for the next one
    log.record_losses({"entropy": 2.0, "curiosity_forward": 0.0})
    log.record(_infos("hivex_episode"))
    assert log.drain()["losses"] == {"entropy": 3.0, "curiosity_forward": 0.25}
    log.record(_infos("hivex_episode"))
    assert log.drain()["losses"] == {}  # no update since


def test_a_running_mean_is_pooled_not_averaged_over_episodes():
    # two episodes of a running mean: totals added 6 over 3 changes (mean 2) and 5 over 1 (mean 5)
    infos = {"hivex_episode": {"return": np.array([1.0, 1.0]), "length": np.array([9, 9]),
                               "statistics": {"Local Reward": np.array([2.0, 5.0]), "Crashes": np.array([1.0, 0.0])},
                               "running": {"Local Reward": {"sums": np.array([6.0, 5.0]),
                                                            "counts": np.array([3, 1])}}},
             "_hivex_episode": np.array([True, True])}
    log = EpisodeLog()
    log.record(infos)
    # the original's summary point: every added value weighs the same, 11 / 4, not the episodes' mean 3.5
    assert log.drain()["statistics"] == {"Local Reward": 11 / 4, "Crashes": 0.5}


def test_training_logs_opc_global_reward_pooled_over_the_changes_of_its_running_total():
    import hivex_dsl
    from hivex_dsl.adapters.gymnasium import HivexVectorEnv

    compiled = hivex_dsl.compile({"hivex": 1, "environment": "ocean_plastic_collection", "agents": 3,
                                  "episode_length": 150, "seeds": {"train": 11, "test": 12},
                                  "decision_period": 1})  # the running total below moves per step() call
    env = HivexVectorEnv(compiled, num_worlds=2)
    env.reset(seed=3)
    env.action_space.seed(0)
    terms = env.core.statistics["Global Reward"].running_mean
    total, sums, counts = (np.zeros(env.num_envs) for _ in range(3))
    ended_sums, ended_counts, log = [], [], EpisodeLog()
    for _ in range(320):  # two whole episodes of every slot, and some respawns after crashes
        _, _, terminated, truncated, infos = env.step(env.action_space.sample())
        pay = sum(compiled.weights[t] * infos[f"reward_terms/{t}"] for t in terms if f"reward_terms/{t}" in infos)
        total += pay
        sums += np.where(pay != 0, total, 0.0)
        counts += pay != 0
        log.record(infos)
        done = terminated | truncated
        ended_sums.append(sums[done].copy())
        ended_counts.append(counts[done].copy())
        total[done] = sums[done] = counts[done] = 0.0
    drained = log.drain()
    expected_sums, expected_counts = np.concatenate(ended_sums), np.concatenate(ended_counts)
    assert drained["episodes"] == expected_sums.size > 2 * env.num_envs - 1
    assert expected_counts.sum() > 0
    assert drained["statistics"]["Global Reward"] == pytest.approx(expected_sums.sum() / expected_counts.sum())


def test_a_signal_s_episode_sums_run_across_rollouts_and_restart_at_each_end():
    log = EpisodeLog()
    # two slots; slot 0's episode ends on the second step, slot 1's runs on into the next rollout
    log.record_signal("curiosity", np.array([[0.5, 1.0], [0.25, 2.0], [1.0, 0.0]]),
                      np.array([[False, False], [True, False], [False, False]]))
    log.record_signal("curiosity", np.array([[0.5, 0.5]]), np.array([[True, True]]))
    log.record(_infos("hivex_episode"))
    # ended: slot 0's 0.5 + 0.25, then its 1.0 + 0.5; slot 1's 1.0 + 2.0 + 0.0 + 0.5
    assert log.drain()["signals"] == {"curiosity": (0.75 + 1.5 + 3.5) / 3}
    # a drain keeps the sums of episodes still running, and reports none twice
    log.record_signal("curiosity", np.array([[2.0, 4.0]]), np.array([[True, False]]))
    log.record(_infos("hivex_episode"))
    assert log.drain()["signals"] == {"curiosity": 2.0}
    log.record_signal("curiosity", np.array([[0.0, 1.0]]), np.array([[False, True]]))
    log.record(_infos("hivex_episode"))
    assert log.drain()["signals"] == {"curiosity": 5.0}
    log.record(_infos("hivex_episode"))
    assert log.drain()["signals"] == {}


def test_value_estimates_are_averaged_per_trajectory_cut_at_episode_ends_and_the_time_horizon():
    """Two slots, two heads, time horizon 3, over two rollouts (ML-Agents' AgentProcessor cuts a trajectory there).
    Slot 0: experiences valued 1, 2 (episode ends), then 4, 5, 6 (three: cut by the horizon), then 8 (open).
    Slot 1: 10, an idle step (not an experience: its value is ignored), 20, then 30 (episode ends) in rollout two."""
    log = EpisodeLog()
    values = np.array([[1.0, 10.0], [2.0, 99.0], [4.0, 20.0]])
    valid = np.array([[True, True], [True, False], [True, True]])
    done = np.array([[False, False], [True, False], [False, False]])
    heads = np.stack([values, values / 10], axis=-1)  # the second head reads a tenth of the first
    log.record_estimates(("extrinsic", "curiosity"), heads, valid, done, time_horizon=3)
    values = np.array([[5.0, 30.0], [6.0, 0.0], [8.0, 0.0]])
    valid = np.array([[True, True], [True, False], [True, False]])
    done = np.array([[False, True], [False, False], [False, False]])
    log.record_estimates(("extrinsic", "curiosity"), np.stack([values, values / 10], axis=-1), valid, done, 3)
    log.record(_infos("hivex_episode"))
    # trajectories cut: slot 0 (1, 2) -> 1.5 and (4, 5, 6) -> 5; slot 1 (10, 20, 30) -> 20, at its episode's end
    # and at the horizon alike; the open (8) waits for the next drain
    drained = log.drain()
    assert drained["estimates"]["extrinsic"] == pytest.approx((1.5 + 5.0 + 20.0) / 3)
    assert drained["estimates"]["curiosity"] == pytest.approx((0.15 + 0.5 + 2.0) / 3)
    log.record_estimates(("extrinsic", "curiosity"), np.array([[[9.0, 0.9], [0.0, 0.0]]]), np.array([[True, False]]),
                         np.array([[True, False]]), 3)
    log.record(_infos("hivex_episode"))
    assert log.drain()["estimates"] == {"extrinsic": pytest.approx(8.5), "curiosity": pytest.approx(0.85)}


def test_value_estimates_wait_for_a_point_with_an_ended_episode():
    log = EpisodeLog()
    log.record_estimates(("extrinsic",), np.array([[[3.0]]]), np.array([[True]]), np.array([[True]]), 10)
    assert log.drain() == {}  # no episode summary yet: no point, and the estimate is kept
    log.record(_infos("hivex_episode"))
    assert log.drain()["estimates"] == {"extrinsic": 3.0}
