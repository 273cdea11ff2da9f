"""The paper's hyperparameters ship as data and are the defaults; files and the command line override them."""

from __future__ import annotations

import pytest
import torch

from hivex_dsl.train.config import (PPOConfig, TrainError, appendix, make_config, paper_defaults, parse_assignments,
                                    read_overrides)

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
def test_the_appendix_values_are_the_defaults_but_where_its_block_says(environment):
    """The defaults are the configs that ran (tests/train/test_budgets.py); with each file's ``appendix:`` block
    laid over them they are the appendix's, read by hand."""
    cfg = make_config(environment, appendix(environment))
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
                      {"max_steps": 1000})
    assert (cfg.gamma, cfg.hidden_units, cfg.max_steps, cfg.seed, cfg.batch_size) == (0.97, 48, 1000, 0, 256)


@pytest.mark.parametrize("layer, words", [
    ({"gama": 0.9}, "gama"), ({"gamma": 1.5}, "gamma"), ({"batch_size": "big"}, "batch_size"),
    ({"vis_encode_type": "nature"}, "vis_encode_type"),
])
def test_bad_hyperparameters_are_named(layer, words):
    with pytest.raises(TrainError, match=words):
        make_config("wind_farm_control", layer)


def problems(*layers) -> list[str]:
    with pytest.raises(TrainError) as caught:
        make_config("wind_farm_control", *layers)
    heading, *lines = str(caught.value).splitlines()
    assert heading == "bad hyperparameters"
    return lines


def test_every_problem_is_reported_where_it_was_written_with_the_value(tmp_path):
    path = tmp_path / "hp.yaml"
    path.write_text("batch_size: 128\nlearning_rate: fast\ngama: 0.9\n")
    assert problems(read_overrides(path), parse_assignments(["hidden_units=-4"])) == [
        f"{path}:2:16: learning_rate: expected a number from 0.0 to 1.0, got 'fast' (a string)",
        f"{path}:3:1: unknown hyperparameter 'gama'; did you mean 'gamma'?; expected one of: "
        + ", ".join(PPOConfig.model_fields),
        "--set: hidden_units: -4 is out of range: expected an integer from 1 to 8192",
    ]


def test_nothing_written_is_dropped_a_null_is_an_error_not_the_default(tmp_path):
    path = tmp_path / "hp.yaml"
    path.write_text("# the paper's gamma, please\ngamma:\n")
    assert problems(read_overrides(path)) == [f"{path}:2:7: gamma: expected a number from 0.0 to 1.0, got null"]
    assert problems({"seed": None}) == ["seed: expected an integer from 0 to 4294967295, got null"]
    assert problems({"world_seed": None}) == [
        "world_seed: expected an integer from 0 to 4294967295, or scenario (the scenario's seeds.train), got null"]
    assert make_config("wind_farm_control").world_seed == "scenario"
    assert make_config("wind_farm_control", {"world_seed": 7}).own_worlds() == 7
    with pytest.raises(TrainError, match=r"^--set gamma=: expected a value after '='$"):
        parse_assignments(["gamma="])
    with pytest.raises(TrainError, match=r"^--set gamma is given twice \(gamma=0.9, then gamma=0.8\): give it once$"):
        parse_assignments(["gamma=0.9", "gamma=0.8"])


def test_set_values_read_as_the_scenario_loader_reads_them():
    # PyYAML alone reads 3e-4 as the string '3e-4' (YAML 1.1 wants a dot) and 'yes' as true
    assert parse_assignments(["learning_rate=3e-4"]).values == {"learning_rate": 3e-4}
    assert make_config("wind_farm_control", parse_assignments(["learning_rate=3e-4"])).learning_rate == 3e-4
    with pytest.raises(TrainError, match=r"^--set normalize=yes: yes is read by YAML 1.1 as the boolean true"):
        parse_assignments(["normalize=yes"])


def test_a_file_is_read_as_strictly_as_a_scenario(tmp_path):
    path = tmp_path / "hp.yaml"
    path.write_text("gamma: 0.9\ngamma: 0.8\n")
    with pytest.raises(TrainError, match=r":2:1: duplicate key 'gamma'"):
        read_overrides(path)
    path.write_text("gamma: 0.9\n---\nbeta: 0.01\n")
    with pytest.raises(TrainError, match=r":2:1: a file holds one set of hyperparameters; found a second YAML document"):
        read_overrides(path)
    path.write_text("# every override commented out\n# gamma: 0.9\n")
    assert make_config("wind_farm_control", read_overrides(path)) == make_config("wind_farm_control")


def test_a_config_pasted_from_ml_agents_is_told_the_keys_are_flat(tmp_path):
    path = tmp_path / "hp.yaml"
    path.write_text("hyperparameters:\n  batch_size: 64\n")
    [line] = problems(read_overrides(path))
    assert line.startswith(f"{path}:1:1: unknown hyperparameter 'hyperparameters': ML-Agents nests its keys in sections")


def test_a_minibatch_larger_than_the_buffer_is_refused_where_it_was_set(tmp_path):
    # ML-Agents trains whole minibatches only, so it would silently never update; ours would silently train
    # full-buffer batches: neither is what was asked for
    assert problems(parse_assignments(["batch_size=4096"])) == [
        "--set: batch_size 4096 is larger than buffer_size 2048: a minibatch is drawn from one buffer; "
        "set batch_size to at most 2048 or buffer_size to at least 4096"]
    path = tmp_path / "hp.yaml"
    path.write_text("gamma: 0.9\nbuffer_size: 128\n")
    [line] = problems(read_overrides(path))
    assert line.startswith(f"{path}:2:14: batch_size 256 is larger than buffer_size 128")
    assert make_config("wind_farm_control", {"buffer_size": 256}).batch_size == 256  # equal is one minibatch


def test_bad_sources_are_clear_errors(tmp_path):
    with pytest.raises(TrainError, match="NAME=VALUE"):
        parse_assignments(["gamma"])
    (tmp_path / "list.yaml").write_text("- 1\n")
    with pytest.raises(TrainError, match=r"list.yaml:1:1: expected a mapping of hyperparameter: value .*, got a list"):
        read_overrides(tmp_path / "list.yaml")
    with pytest.raises(TrainError, match="no such file"):
        read_overrides(tmp_path / "missing.yaml")
    with pytest.raises(TrainError, match="no paper hyperparameters"):
        paper_defaults("nowhere")


def test_buffer_size_counts_experiences_over_all_slots():
    cfg = PPOConfig(buffer_size=2048, time_horizon=2048)
    assert cfg.rollout_length(64) == 32  # 8 worlds x 8 turbines: 32 steps each fill 2048 experiences
    assert PPOConfig(buffer_size=2048, time_horizon=16).rollout_length(64) == 16  # never past time_horizon
    assert cfg.rollout_length(4096) == 1


def test_a_device_that_is_not_here_is_a_clear_error():
    from hivex_dsl.train.devices import torch_device

    assert torch_device("cpu").type == "cpu"
    for name in ("abacus", "mps", "meta", "cuda:x"):  # torch's own messages list every backend it was built with
        with pytest.raises(TrainError) as refused:
            torch_device(name)
        assert str(refused.value) == f"unknown device {name!r}: expected cpu, cuda or cuda:N (one GPU of several)"


def test_a_gpu_index_past_the_last_gpu_is_a_clear_error(monkeypatch):
    from hivex_dsl.train.devices import torch_device

    monkeypatch.setattr(torch.cuda, "is_available", lambda: True)
    monkeypatch.setattr(torch.cuda, "device_count", lambda: 2)
    assert torch_device("cuda:1").index == 1
    with pytest.raises(TrainError) as refused:
        torch_device("cuda:2")
    assert str(refused.value) == "device cuda:2 was asked for, but torch sees 2 CUDA GPUs here (cuda:0 to cuda:1)"


@pytest.mark.parametrize("cores, machine, load, expected", [
    (2, 2, 0.2, 2),  # a quiet 2-core machine: both
    (2, 2, 7.5, 1),  # issue 54 item 16: four busy loops and more on 2 cores: one thread, not two fighting them
    (2, 2, 1.0, 1),  # one core busy
    (16, 16, 4.0, 8),  # 12 free, capped at MAX_AUTO_THREADS
    (16, 16, 12.2, 4),
    (4, 64, 32.0, 2),  # 4 cores of a 64-core host half busy: half of ours
])
def test_auto_torch_threads_are_the_free_cores(monkeypatch, cores, machine, load, expected):
    from hivex_dsl.train import config

    monkeypatch.setattr(config.os, "sched_getaffinity", lambda pid: set(range(cores)), raising=False)
    monkeypatch.setattr(config.os, "cpu_count", lambda: machine)
    monkeypatch.setattr(config.os, "getloadavg", lambda: (load, load, load))
    assert config.make_config("wind_farm_control").threads() == expected
    assert config.make_config("wind_farm_control", {"torch_threads": 3}).threads() == 3  # a number is kept
