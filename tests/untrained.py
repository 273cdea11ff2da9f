"""An untrained checkpoint as `hivex train` writes one, for tests that read checkpoints without training."""

from __future__ import annotations

from pathlib import Path

import pytest


def untrained_checkpoint(path: Path, compiled, agent_steps: int = 0) -> Path:
    """``path``, now a checkpoint of an untrained small network (8 hidden units, the paper's other hyperparameters)
    for the compiled scenario ``compiled``, saying it trained ``agent_steps`` (skips the test where torch is
    missing)."""
    pytest.importorskip("torch")
    from hivex_dsl.adapters.gymnasium import HivexVectorEnv
    from hivex_dsl.train.checkpoint import save_checkpoint
    from hivex_dsl.train.config import make_config
    from hivex_dsl.train.networks import ActorCritic

    cfg = make_config(compiled.environment, {"hidden_units": 8})
    env = HivexVectorEnv(compiled, num_worlds=1)
    network = ActorCritic(env.single_observation_space, env.single_action_space, cfg)
    return save_checkpoint(path, network, cfg, compiled, agent_steps=agent_steps)
