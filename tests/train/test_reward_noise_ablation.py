"""benchmarks/reward_noise_ablation.py: the noise is zero-mean with the stated spread on experiences only, a
sigma of 0 leaves `hivex train`'s run as it was, and the trainer is left unpatched after."""

from __future__ import annotations

import json

import numpy as np
import pytest
import torch

from hivex_dsl.compiler import compile
from hivex_dsl.train import ppo
from hivex_dsl.train.config import make_config

from .conftest import benchmark_script, short_scenario


@pytest.fixture(scope="module")
def script():
    return benchmark_script("reward_noise_ablation")


def test_noise_is_zero_mean_with_sigma_on_experiences_only(script):
    rewards = torch.full((2000, 4), 0.5)
    valid = torch.ones(2000, 4)
    valid[:, 3] = 0.0  # a slot whose steps were no experience (an ended agent waiting)
    script.add_noise(rewards, valid, 0.2, np.random.default_rng(0))
    noise = rewards[:, :3] - 0.5
    assert abs(float(noise.mean())) < 0.01  # 6,000 draws: standard error 0.0026
    assert float(noise.std()) == pytest.approx(0.2, rel=0.05)
    assert torch.equal(rewards[:, 3], torch.full((2000,), 0.5))


def _curve(run_dir):
    return [(p["agent_steps"], p["return"]) for p in json.loads((run_dir / "curve.json").read_text())]


def test_sigma_zero_is_the_plain_trainer_and_noise_changes_the_run(script, tiny, tmp_path):
    compiled = compile(short_scenario("wind_farm_control"))
    cfg = make_config("wind_farm_control", tiny)
    ppo.train(compiled, cfg, tmp_path / "plain", progress=False)
    script.train_with_noise(compiled, cfg, tmp_path / "zero", 0.0)
    assert ppo.advantages_and_returns.__name__ == "advantages_and_returns"  # restored
    script.train_with_noise(compiled, cfg, tmp_path / "noisy", 5.0)
    plain = torch.load(tmp_path / "plain" / "checkpoint.pt", weights_only=False)["model"]
    zero = torch.load(tmp_path / "zero" / "checkpoint.pt", weights_only=False)["model"]
    noisy = torch.load(tmp_path / "noisy" / "checkpoint.pt", weights_only=False)["model"]
    assert all(torch.equal(plain[k], zero[k]) for k in plain)
    assert not all(torch.equal(plain[k], noisy[k]) for k in plain)
    # the logged returns are the environment's: the noise never reaches them. The one logged episode (192
    # agent-steps, 8 turbines x 24 steps) is played by the same sampled actions in both runs (one torch seed, the
    # policies a few small updates apart), so sigma 5 over its 24 rewards would show in its return if it leaked
    assert _curve(tmp_path / "plain")[0] == _curve(tmp_path / "noisy")[0]


def test_report_reads_the_runs_scalars(script, tiny, tmp_path):
    compiled = compile(short_scenario("wind_farm_control"))
    script.train_with_noise(compiled, make_config("wind_farm_control", tiny), tmp_path, 0.1)
    text = script.report(tmp_path, budget=tiny["max_steps"])
    # 192 agent-steps in rollouts of 64 experiences (8 turbines x 8 steps): 3 updates
    assert text.splitlines()[0] == f"{tmp_path}: 3 updates to 192 agent-steps"
    assert "entropy at 10/25/50/100%" in text and "value loss at 10/25/50/100%" in text
