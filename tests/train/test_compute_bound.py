"""benchmarks/compute_bound.py: the FLOPs it counts for one training iteration match the networks' shapes."""

from __future__ import annotations

import pytest
from torch import nn

from .conftest import benchmark_script

TINY = {"num_worlds": 1, "buffer_fill": "rollout",
        "buffer_size": 64, "batch_size": 32, "num_epoch": 2, "hidden_units": 16}


@pytest.fixture(scope="module")
def benchmark():
    return benchmark_script("compute_bound")


def test_the_iteration_s_flops_are_the_dense_layers_shapes(benchmark):
    """Wind Farm Control's actor and critic are dense layers only, so the count follows from their shapes: a
    forward pass costs 2 x inputs x outputs FLOPs per layer and sample (a multiply and an add per weight) and
    a backward pass twice that (input and weight gradients), less the first layers' input gradients (nothing
    needs the observation's)."""
    row = benchmark.iteration_flops("wind_farm_control", TINY)
    layers = {name: m for name, m in row["_agent"].named_modules() if isinstance(m, nn.Linear)}
    cost = {name: 2 * m.in_features * m.out_features for name, m in layers.items()}
    forward = sum(cost.values())
    critic = sum(c for name, c in cost.items() if name.startswith("critic.") or name == "value")
    steps, slots = 64, 8  # 8 turbines x 8 steps; then the critic alone values the 8 slots' last observations
    assert row["agent_steps"] == steps
    assert row["rollout_flop_per_agent_step"] == (steps * forward + slots * critic) / steps
    first_layers = cost["actor.mlp.0"] + cost["critic.mlp.0"]
    assert row["update_flop_per_agent_step"] == TINY["num_epoch"] * (3 * forward - first_layers)


def test_the_bound_is_the_attained_rate_over_the_work(benchmark):
    row = benchmark.measure("wind_farm_control", TINY)
    assert row["attained_flop_per_s"] > 0
    assert row["compute_bound_agent_steps_per_s"] == pytest.approx(row["attained_flop_per_s"] / row["flop_per_agent_step"])
