"""The opt-in approximate precision: off by default, recorded with the run, close to exact, and it still learns."""

from __future__ import annotations

import json

import numpy as np
import pytest
import torch
import yaml

from hivex_dsl.cli import main
from hivex_dsl.compiler import compile
from hivex_dsl.evaluation.rollout import rollout
from hivex_dsl.train.config import PPOConfig, TrainError, make_config
from hivex_dsl.train.curiosity import Curiosity
from hivex_dsl.train.evaluate import evaluate
from hivex_dsl.train.networks import ActorCritic
from hivex_dsl.train.ppo import make_env, make_optimizer, start_rollouts, collect, advantages_and_returns, update
from hivex_dsl.train.logs import EpisodeLog
from hivex_dsl.train.ppo import train

from .conftest import SCENARIOS, short_scenario


def test_exact_is_the_default_and_every_paper_config_keeps_it():
    assert PPOConfig().precision == "exact"
    for environment in ("wind_farm_control", "ocean_plastic_collection", "aerial_wildfire_suppression"):
        assert make_config(environment).precision == "exact"


def test_tf32_on_a_cpu_is_a_clear_error_where_it_was_written(capsys):
    with pytest.raises(TrainError, match="precision tf32 is a GPU mode .* but device is cpu: on a CPU use "
                                         "precision bf16"):
        make_config("wind_farm_control", {"precision": "tf32"})
    assert main(["train", "scenarios/wind_farm_control/main.yaml", "--set", "precision=tf32"]) == 2
    assert "--set: precision tf32 is a GPU mode" in capsys.readouterr().err
    with pytest.raises(TrainError, match="tf32 is a GPU mode"):
        train(compile(short_scenario("wind_farm_control")), PPOConfig(precision="tf32"), "unused", progress=False)
    with pytest.raises(TrainError):
        make_config("wind_farm_control", {"precision": "fp16"})


def first_update(environment: str, precision: str, curiosity: bool = False) -> dict[str, float]:
    """The losses of one rollout and update from the same seed and weights at ``precision``."""
    torch.manual_seed(0)
    layers = {"num_worlds": 1, "buffer_fill": "rollout", "buffer_size": 32, "batch_size": 16, "num_epoch": 1,
              "hidden_units": 16, "precision": precision, "curiosity_strength": 0.01 if curiosity else 0.0}
    cfg = make_config(environment, layers)
    env, obs, infos = make_env(compile(short_scenario(environment)), cfg.num_worlds, "train")
    agent = ActorCritic(env.single_observation_space, env.single_action_space, cfg)
    module = None
    if curiosity:
        module = Curiosity(env.single_observation_space, agent.layout, cfg)
        module = (module, make_optimizer(module, cfg.curiosity_learning_rate))
    state, buf = start_rollouts(obs, agent, cfg.rollout_length(env.num_envs), infos)
    next_value = collect(env, agent, buf, state, cfg, EpisodeLog())
    advantages, returns, _ = advantages_and_returns(buf, next_value, cfg, module and module[0])
    return update(agent, make_optimizer(agent, cfg.learning_rate), buf, advantages, returns, cfg, cfg.beta,
                  cfg.epsilon, np.random.default_rng(0), module)


@pytest.mark.parametrize("environment,curiosity", [("ocean_plastic_collection", True),
                                                   ("aerial_wildfire_suppression", False)])
def test_bf16_changes_the_first_update_only_by_rounding(environment, curiosity):
    """bf16 has an 8-bit mantissa: the losses move by rounding (so autocast is on) but stay within a few
    percent of exact float32; a camera environment's update (a ResNet and the curiosity module on OPC)."""
    exact = first_update(environment, "exact", curiosity)
    again = first_update(environment, "exact", curiosity)
    approximate = first_update(environment, "bf16", curiosity)
    assert exact == again  # the comparison is not noise: exact is exactly repeatable
    assert set(approximate) == set(exact) and all(np.isfinite(v) for v in approximate.values())
    assert approximate != exact
    for name in ("policy", "value", "entropy") + (("curiosity_forward", "curiosity_inverse") if curiosity else ()):
        assert approximate[name] == pytest.approx(exact[name], rel=0.05, abs=1e-3), name


def test_a_bf16_run_records_its_precision_and_still_learns_wind_farm_control(tmp_path):
    """300,000 agent-steps on 500-step episodes (about ten seconds): the trained policy must close at least half
    the gap between all-zeros and the scripted controller on the test episodes (exact float32 reaches 417 of
    zeros' 86 and scripted 453 in the same run; random earns 76)."""
    data = yaml.safe_load((SCENARIOS / "wind_farm_control" / "main.yaml").read_text()) | {"episode_length": 500}
    compiled = compile(data)
    # 32 worlds on a fixed rollout (the defaults this was measured with): WFC's one-world default updates on whole
    # trajectories, as the original did, and learns far less in this budget
    cfg = make_config("wind_farm_control", {"max_steps": 300_000, "precision": "bf16", "torch_threads": 1,
                                            "num_worlds": 32, "buffer_fill": "rollout"})
    train(compiled, cfg, tmp_path, progress=False)
    assert json.loads((tmp_path / "config.json").read_text())["hyperparameters"]["precision"] == "bf16"
    trained = evaluate(tmp_path / "checkpoint.pt", episodes=4)["return"]["mean"]
    zeros = rollout(compiled, "zeros", 4).returns.mean()
    scripted = rollout(compiled, "scripted", 4).returns.mean()
    assert trained > zeros + 0.5 * (scripted - zeros), (trained, zeros, scripted)
