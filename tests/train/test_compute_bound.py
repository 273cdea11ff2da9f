"""benchmarks/compute_bound.py: the FLOPs it counts for one training iteration match the networks' shapes."""

from __future__ import annotations

import json

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


def test_writing_a_report_keeps_the_rows_not_measured_again(benchmark, tmp_path):
    """-o merges: measuring two environments must not drop the other environments' rows (it once did)."""
    path = tmp_path / "compute_bound.json"
    old = [{"machine": "m", "environment": env, "threads": 2, "bound": i} for i, env in enumerate(("a", "b", "c"))]
    path.write_text(json.dumps({"rows": old}))
    report = benchmark.merged(path, [{"machine": "m", "environment": "b", "threads": 2, "bound": 9},
                                     {"machine": "m", "environment": "b", "threads": 1, "bound": 7}])
    rows = {(r["environment"], r["threads"]): r["bound"] for r in report["rows"]}
    assert rows == {("a", 2): 0, ("b", 2): 9, ("c", 2): 2, ("b", 1): 7}
    other_machine = benchmark.merged(path, [{"machine": "n", "environment": "a", "threads": 2, "bound": 5}])
    assert len(other_machine["rows"]) == 4  # another machine's row is added, not swapped for this one's
