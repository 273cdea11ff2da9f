"""Small scenarios and configs for training tests: a few hundred agent-steps each."""

from __future__ import annotations

from pathlib import Path

import pytest
import yaml

import hivex_dsl
from ..benchmark_scripts import benchmark_script  # noqa: F401  (re-exported for the tests here)

pytest.importorskip("torch")

SCENARIOS = Path(__file__).resolve().parents[2] / "scenarios"
ENVIRONMENTS = ("wind_farm_control", "wildfire_resource_management", "drone_based_reforestation",
                "ocean_plastic_collection", "aerial_wildfire_suppression")
# buffer_fill rollout: the tests' counts of updates, checkpoints and curve points are derived from a fixed rollout of
# buffer_size // slots steps (Wind Farm Control's own default updates on finished trajectories instead)
TINY = {"num_worlds": 1, "buffer_fill": "rollout", "buffer_size": 64, "batch_size": 32, "num_epoch": 2,
        "hidden_units": 16,
        "max_steps": 192, "checkpoint_every": 128, "keep_checkpoints": 1, "summary_freq": 1}


# a turbine turning 0.1 degrees a step (the default) cannot face the wind within a short episode: a fast turn keeps
# the scripted controller ahead of random play there
SHORT_EPISODE_PARAMS = {"wind_farm_control": {"params": {"rotation_speed_deg": 30.0}}}


def short_scenario(environment: str, episode_length: int = 24) -> dict:
    """The environment's main scenario with short episodes (so evaluation ends quickly), ``episode_length``
    rounded up to whole decisions of the environment's default decision period (5 in OPC and DBR)."""
    data = yaml.safe_load((SCENARIOS / environment / "main.yaml").read_text())
    period = hivex_dsl.compile({"hivex": 1, "environment": environment}).decision_period
    return data | {"episode_length": -(-episode_length // period) * period} | SHORT_EPISODE_PARAMS.get(environment, {})


@pytest.fixture
def tiny():
    return dict(TINY)


def weights_under_each(compiled, settings: dict, key: str, choices: tuple, tmp_path: Path) -> dict:
    """Train ``compiled`` once per choice of the hyperparameter ``key`` (``settings`` the rest) -> the final
    weights of each run (state dicts), by choice."""
    import torch

    from hivex_dsl.train.config import make_config
    from hivex_dsl.train.ppo import train

    weights = {}
    for choice in choices:
        train(compiled, make_config(compiled.environment, settings | {key: choice}), tmp_path / choice,
              progress=False)
        weights[choice] = torch.load(tmp_path / choice / "checkpoint.pt", weights_only=True)["model"]
    return weights


def record_baseline_script():
    """benchmarks/record_baseline.py as a module."""
    return benchmark_script("record_baseline")


@pytest.fixture(scope="module")
def as_if_reproduced():
    """The module's short test scenarios (a dozen steps) reproduce no published cell; records and pages are
    tested as if each reproduced its task's and level's (hivex_dsl.evaluation.published.paper_cell)."""
    from hivex_dsl.evaluation import published

    with pytest.MonkeyPatch.context() as patch:
        patch.setattr(published, "cell_for", published.paper_cell)
        yield
