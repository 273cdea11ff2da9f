"""Checkpoints: the network's weights with everything needed to rebuild it and replay its scenario."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import torch

from ..compiler import CompiledScenario, compile
from .config import PPOConfig, TrainError
from .networks import ActorCritic

FORMAT = "hivex-ppo/1"


def save_checkpoint(path: Path, agent: ActorCritic, cfg: PPOConfig, compiled: CompiledScenario,
                    agent_steps: int, wall_s: float | None = None) -> Path:
    """Write one checkpoint (weights, hyperparameters, the resolved scenario and its fingerprint, and the
    training's agent-steps and wall seconds when it was taken)."""
    path.parent.mkdir(parents=True, exist_ok=True)
    torch.save({"format": FORMAT, "model": agent.state_dict(), "config": cfg.model_dump(mode="json"),
                "scenario": compiled.resolved(), "fingerprint": compiled.fingerprint,
                "agent_steps": int(agent_steps), "wall_s": None if wall_s is None else round(float(wall_s), 3)}, path)
    return path


def load_checkpoint(path: str | Path) -> dict[str, Any]:
    """The checkpoint's content, with ``config`` as a PPOConfig and ``compiled`` the scenario it trained on."""
    try:
        data = torch.load(Path(path), map_location="cpu", weights_only=True)
    except FileNotFoundError:
        raise TrainError(f"no checkpoint at {path}") from None
    except Exception as exc:  # torch raises many kinds for a file that is not a checkpoint
        raise TrainError(f"{path} is not a hivex checkpoint: {exc}") from None
    if not isinstance(data, dict) or data.get("format") != FORMAT:
        raise TrainError(f"{path} is not a hivex checkpoint (format {FORMAT})")
    data["config"] = PPOConfig(**data["config"])
    data["compiled"] = compile(data["scenario"])
    return data


def policy_for(checkpoint: dict[str, Any], compiled: CompiledScenario, device: str = "cpu") -> ActorCritic:
    """The checkpoint's network, checked to fit ``compiled``'s spaces (an evaluation scenario may differ)."""
    from ..adapters.gymnasium import HivexVectorEnv

    env = HivexVectorEnv(compiled, num_worlds=1)
    agent = ActorCritic(env.single_observation_space, env.single_action_space, checkpoint["config"])
    try:
        agent.load_state_dict(checkpoint["model"])
    except RuntimeError as exc:
        raise TrainError(f"the checkpoint does not fit scenario {compiled.name!r}: its spaces differ ({exc})") from None
    from .ppo import torch_device

    return agent.to(torch_device(device)).eval()
