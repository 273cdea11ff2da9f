"""The paper's hyperparameters ship as data and are the defaults; files and the command line override them."""

from __future__ import annotations

import pytest

from hivex_dsl.train.config import PPOConfig, TrainError, make_config, paper_defaults, parse_assignments, read_overrides

from .conftest import ENVIRONMENTS

# Read by hand from the paper's appendix ("Train and Test Hyperparameters" per environment).
PAPER = {
    "wind_farm_control": dict(batch_size=256, buffer_size=2048, beta=0.005, gamma=0.9, hidden_units=64,
                              time_horizon=2048, max_steps=8_000_000),
    "wildfire_resource_management": dict(batch_size=128, buffer_size=2048, beta=0.01, gamma=0.99, hidden_units=512,
                                         time_horizon=2048, max_steps=4_500_000),
    "drone_based_reforestation": dict(batch_size=1024, buffer_size=10240, beta=0.005, gamma=0.99, hidden_units=128,
                                      vis_encode_type="resnet", reward_strength=0.9, max_steps=2_000_000),
    "ocean_plastic_collection": dict(batch_size=1024, buffer_size=10240, gamma=0.99, hidden_units=128,
                                     vis_encode_type="resnet", max_steps=3_000_000),
    "aerial_wildfire_suppression": dict(batch_size=256, buffer_size=4096, gamma=0.995, hidden_units=256,
                                        vis_encode_type="simple", time_horizon=4096, max_steps=1_800_000),
}


@pytest.mark.parametrize("environment", ENVIRONMENTS)
def test_the_paper_values_are_the_defaults(environment):
    cfg = make_config(environment)
    for key, value in PAPER[environment].items():
        assert getattr(cfg, key) == value, key
    assert (cfg.learning_rate, cfg.learning_rate_schedule, cfg.epsilon, cfg.lambd, cfg.num_epoch, cfg.num_layers) == \
        (0.0003, "linear", 0.2, 0.95, 3, 2)
    assert cfg.normalize is False
    # ML-Agents' PPO clips no gradient norm (ppo/optimizer_torch.py: backward, then step) and builds its layers
    # with its own linear_layer initialisation
    assert (cfg.max_grad_norm, cfg.weight_init) == (0.0, "ml_agents")


def test_a_file_then_the_command_line_override(tmp_path):
    path = tmp_path / "hp.yaml"
    path.write_text("gamma: 0.97\nhidden_units: 32\n")
    cfg = make_config("wind_farm_control", read_overrides(path), parse_assignments(["hidden_units=48"]),
                      {"max_steps": 1000, "seed": None})
    assert (cfg.gamma, cfg.hidden_units, cfg.max_steps, cfg.seed, cfg.batch_size) == (0.97, 48, 1000, 0, 256)


@pytest.mark.parametrize("layer, words", [
    ({"gama": 0.9}, "gama"), ({"gamma": 1.5}, "gamma"), ({"batch_size": "big"}, "batch_size"),
    ({"vis_encode_type": "nature"}, "vis_encode_type"),
])
def test_bad_hyperparameters_are_named(layer, words):
    with pytest.raises(TrainError, match=words):
        make_config("wind_farm_control", layer)


def test_bad_sources_are_clear_errors(tmp_path):
    with pytest.raises(TrainError, match="NAME=VALUE"):
        parse_assignments(["gamma"])
    (tmp_path / "list.yaml").write_text("- 1\n")
    with pytest.raises(TrainError, match="mapping"):
        read_overrides(tmp_path / "list.yaml")
    with pytest.raises(TrainError, match="cannot read"):
        read_overrides(tmp_path / "missing.yaml")
    with pytest.raises(TrainError, match="no paper hyperparameters"):
        paper_defaults("nowhere")


def test_buffer_size_counts_experiences_over_all_slots():
    cfg = PPOConfig(buffer_size=2048, time_horizon=2048)
    assert cfg.rollout_length(64) == 32  # 8 worlds x 8 turbines: 32 steps each fill 2048 experiences
    assert PPOConfig(buffer_size=2048, time_horizon=16).rollout_length(64) == 16  # never past time_horizon
    assert cfg.rollout_length(4096) == 1


def test_a_device_that_is_not_here_is_a_clear_error():
    from hivex_dsl.train.ppo import torch_device

    assert torch_device("cpu").type == "cpu"
    with pytest.raises(TrainError, match="unknown device"):
        torch_device("abacus")
