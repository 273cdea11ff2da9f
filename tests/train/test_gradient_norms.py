"""benchmarks/gradient_norms.py: the actor/critic split covers every parameter once, and its two norms make up
the norm that clipping sees."""

from __future__ import annotations

import math
import sys

import pytest
import torch
from torch import nn

from hivex_dsl.adapters.gymnasium import HivexVectorEnv
from hivex_dsl.compiler import compile
from hivex_dsl.train.config import make_config
from hivex_dsl.train.networks import ActorCritic, to_tensors
from hivex_dsl.train.ppo import train

from .conftest import benchmark_script, short_scenario


@pytest.fixture(scope="module")
def script():
    return benchmark_script("gradient_norms")


def test_actor_and_critic_norms_make_up_the_clipped_norm(script, tiny):
    # DBR: hybrid actions, so the actor owns a Gaussian head and the log-std as well as the logits
    compiled = compile(short_scenario("drone_based_reforestation"))
    env = HivexVectorEnv(compiled, num_worlds=1)
    torch.manual_seed(0)
    agent = ActorCritic(env.single_observation_space, env.single_action_space,
                        make_config("drone_based_reforestation", tiny))
    actor, critic = script.actor_and_critic(agent)
    assert sorted(map(id, actor + critic)) == sorted(map(id, agent.parameters()))
    assert any(p is agent.log_std for p in actor) and any(p is agent.value.weight for p in critic)
    obs = to_tensors(env.reset(seed=0)[0])
    cont, disc, _ = agent.act(obs)
    logp, entropy, value = agent.evaluate(obs, cont, disc)
    (logp.mean() + value.square().mean() - entropy.mean()).backward()
    total = nn.utils.clip_grad_norm_(agent.parameters(), math.inf)
    assert math.hypot(script.grad_norm(actor), script.grad_norm(critic)) == pytest.approx(float(total), rel=1e-5)


def test_it_reports_a_trained_checkpoint(script, tiny, tmp_path, monkeypatch, capsys):
    compiled = compile(short_scenario("wind_farm_control"))
    train(compiled, make_config("wind_farm_control", tiny, {"max_grad_norm": 0.5}), tmp_path, progress=False)
    monkeypatch.setattr(sys, "argv", ["gradient_norms.py", str(tmp_path / "checkpoint.pt"), "--rollouts", "2"])
    script.main()
    out = capsys.readouterr().out
    assert "4 minibatches of 32; max_grad_norm 0.5" in out  # 2 rollouts of 64 experiences, minibatches of 32
    assert "critic gradient norm" in out and "clip factor" in out
