"""``buffer_fill: trajectories``: updates when ML-Agents' trainer would, against hand-derived steps and the dates
of the original Wind Farm Control run's updates, read from its logged clip epsilon."""

from __future__ import annotations

import tempfile
from pathlib import Path

import numpy as np
import pytest

import hivex_dsl
from hivex_dsl.adapters.gymnasium import HivexVectorEnv
from hivex_dsl.train.buffer import FinishedTrajectories
from hivex_dsl.train.config import PPOConfig, make_config
from hivex_dsl.train.ppo import train

ROOT = Path(__file__).resolve().parents[2]


def wfc_update_experiences(cfg: PPOConfig, episodes: int) -> list[int]:
    """The experiences (valid agent-steps, as ML-Agents counts them) at which WFC's main scenario, played at random
    in ``cfg.num_worlds`` worlds, is due an update under ``cfg``: the trigger as `hivex train` runs it."""
    compiled = hivex_dsl.compile(ROOT / "scenarios" / "wind_farm_control" / "main.yaml")
    env = HivexVectorEnv(compiled, num_worlds=cfg.num_worlds)
    env.reset(seed=0)
    rng = np.random.default_rng(0)
    done, experiences, due = np.zeros(env.num_envs, bool), 0, []
    trigger = FinishedTrajectories(env.num_envs, cfg.time_horizon, cfg.buffer_size)
    while len(due) < 3 * episodes:
        valid = ~done
        _, _, terminated, truncated, _ = env.step(rng.integers(0, 3, env.num_envs))
        done = terminated | truncated
        experiences += int(valid.sum())
        if trigger.step(valid, done):
            due.append(experiences)
            trigger = FinishedTrajectories(env.num_envs, cfg.time_horizon, cfg.buffer_size)
    return due


def test_wind_farm_controls_defaults_update_when_the_original_run_did(wfc_event_runs):
    """ML-Agents decays epsilon linearly from 0.2 to 0.1 over max_steps and logs its mean over a summary point's
    updates, so eps = 0.1 + 0.1 (1 - s / 8M) dates them: s, their mean agent-step, to within 40 (eps is logged to
    6 decimals). Hand-derived from one environment of 8 turbines, time_horizon 2,048 and 5,000-step episodes: each
    episode updates after 2,048, 4,096 and 5,000 steps (16,384, 32,768 and 40,000 experiences), the last written
    with the next point, so point k > 0 dates 40,000 k + (0 + 16,384 + 32,768) / 3. Updating every 2,048 experiences
    instead (`buffer_fill: rollout`) would date the points thousands of agent-steps away (up to 4,096)."""
    cfg = make_config("wind_farm_control")
    assert cfg.buffer_fill == "trajectories" and cfg.num_worlds == 1
    due = wfc_update_experiences(cfg, episodes=2)
    assert due == [16_384, 32_768, 40_000, 56_384, 72_768, 80_000]
    per_episode = np.array(due[:3])
    for run in (wfc_event_runs[f"train_run_{i}"]["Policy/Epsilon"] for i in range(3)):
        for k, (step, epsilon) in enumerate(run):
            assert step == 40_000 * (k + 1)
            dated = 8_000_000 * (1 - (epsilon - 0.1) / 0.1)
            ours = np.concatenate([[0] if k else [], per_episode[:2]]).mean() + 40_000 * k
            assert dated == pytest.approx(ours, abs=40)


def test_the_fixed_rollout_updates_every_buffer_size_experiences():
    """The choice every other record trained with: 2,048 experiences of 8 turbines every 256 steps."""
    cfg = make_config("wind_farm_control", {"buffer_fill": "rollout"})
    assert cfg.rollout_length(8) == 256


def test_training_updates_on_finished_trajectories():
    """Two turbines, 50-step episodes, time_horizon 8, buffer 20. Hand-derived: the trajectories finish after 8 and
    16 steps (16, then 32 experiences > 20: an update at 32 agent-steps), again at 64 and 96 (48 steps); then the
    episode ends at step 50 (2 more each: 4 experiences), step 51 is the masked restart (counted as agent-steps,
    no experience), steps 52-59 finish 16 more (20, not over 20) and 60-67 16 more: an update after 19 steps, 134."""
    compiled = hivex_dsl.compile({"hivex": 1, "environment": "wind_farm_control", "agents": 2, "episode_length": 50,
                                  "seeds": {"train": 1, "test": 2}})
    cfg = make_config("wind_farm_control", {"num_worlds": 1, "buffer_fill": "trajectories", "time_horizon": 8,
                                            "buffer_size": 20, "batch_size": 8, "max_steps": 134, "torch_threads": 1})
    updates: list[int] = []
    with tempfile.TemporaryDirectory() as folder:
        train(compiled, cfg, Path(folder) / "run", progress=False,
              on_update=lambda info: updates.append(info["agent_steps"]))
    assert updates == [32, 64, 96, 134]


def test_a_trajectory_finishes_at_the_time_horizon_or_the_episodes_end():
    trigger = FinishedTrajectories(slots=3, time_horizon=4, buffer_size=6)
    on = np.ones(3, bool)
    assert not any(trigger.step(on, np.array([False, False, i == 1])) for i in range(3))
    assert trigger.finished == 2  # slot 2's episode ended after 2 experiences; slots 0 and 1 hold 3 each
    assert trigger.step(on, np.zeros(3, bool))  # slots 0 and 1 reach 4: 2 + 8 = 10 > 6
    assert trigger.open.tolist() == [0, 0, 2]
