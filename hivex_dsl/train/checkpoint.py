"""Checkpoints: the network's weights with everything needed to rebuild it and replay its scenario."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import torch

from ..compiler import CompiledScenario, compile
from .config import PPOConfig, TrainError
from .devices import torch_device
from .networks import ActionLayout, ActorCritic

FORMAT = "hivex-ppo/1"


def save_checkpoint(path: Path, agent: ActorCritic, cfg: PPOConfig, compiled: CompiledScenario,
                    agent_steps: int, wall_s: float | None = None, training: dict[str, Any] | None = None) -> Path:
    """Write one checkpoint (weights, hyperparameters, the resolved scenario and its fingerprint, and the
    training's agent-steps and wall seconds when it was taken). ``training`` (optimizer states, the curiosity
    module, the learning curve so far) makes it resumable: the run directory's ``checkpoint.pt`` carries it.

    The file is written beside and then renamed over ``path``, so a run killed mid-write leaves the previous
    checkpoint whole."""
    path.parent.mkdir(parents=True, exist_ok=True)
    data = {"format": FORMAT, "model": agent.state_dict(), "config": cfg.model_dump(mode="json"),
            "scenario": compiled.resolved(), "fingerprint": compiled.fingerprint,
            "agent_steps": int(agent_steps), "wall_s": None if wall_s is None else round(float(wall_s), 3)}
    if training is not None:
        data["training"] = training
    partial = path.with_name(path.name + ".partial")
    torch.save(data, partial)
    partial.replace(path)
    return path


def save_numbered_checkpoint(run_dir: Path, agent: ActorCritic, cfg: PPOConfig, compiled: CompiledScenario,
                             steps: int, wall: float) -> None:
    """Save ``run_dir/checkpoints/step_N.pt`` and keep only the newest ``cfg.keep_checkpoints``."""
    folder = run_dir / "checkpoints"
    save_checkpoint(folder / f"step_{steps:012d}.pt", agent, cfg, compiled, steps, wall)
    for old in sorted(folder.glob("step_*.pt"))[:-cfg.keep_checkpoints]:
        old.unlink()


def load_checkpoint(path: str | Path) -> dict[str, Any]:
    """The checkpoint's content, with ``config`` as a PPOConfig and ``compiled`` the scenario it trained on."""
    try:
        data = torch.load(Path(path), map_location="cpu", weights_only=True)
    except FileNotFoundError:
        raise TrainError(f"no checkpoint at {path}") from None
    except IsADirectoryError:
        raise TrainError(f"{path} is a directory: give the checkpoint file in it "
                         f"({Path(path) / 'checkpoint.pt'})") from None
    except Exception:  # torch raises many kinds for a file that is not a checkpoint
        # not torch's own advice (load with weights_only=False), which would run whatever code the file holds
        raise TrainError(f"{path} is not a hivex checkpoint: torch.load(weights_only=True) cannot read it, and a "
                         "hivex checkpoint holds tensors and plain data only") from None
    written = data.get("format") if isinstance(data, dict) else None
    if written != FORMAT:
        also = (f" (it says format {written!r}: written by another version of hivex?)"
                if isinstance(written, str) else "")
        raise TrainError(f"{path} is not a hivex checkpoint of format {FORMAT!r}{also}")
    data["compiled"] = compile(data["scenario"])
    data["config"] = PPOConfig(**older_defaults(data["config"], action_space_of(data["compiled"])))
    return data


def older_defaults(config: dict[str, Any], action_space: Any) -> dict[str, Any]:
    """The hyperparameters ``config`` of a checkpoint (or record) of a policy over ``action_space``, with what a
    key added since meant when they were written, where it changes anything for this policy: every policy from
    before ``weight_init`` started from ``cleanrl`` weights, a curiosity module from before ``curiosity_module``
    is ``hivex_v1``, continuous actions from before ``continuous_actions`` were clipped, and more than one action
    dimension from before ``policy_loss`` shared one ``joint`` ratio. (``max_grad_norm`` was always written.)"""
    layout = ActionLayout.of(action_space)
    then: dict[str, Any] = {"weight_init": "cleanrl"}
    if config.get("curiosity_strength", 0) > 0:
        then["curiosity_module"] = "hivex_v1"
    if layout.continuous:
        then["continuous_actions"] = "clip"
    if layout.continuous + len(layout.nvec) > 1:
        then["policy_loss"] = "joint"
    return then | config


def action_space_of(compiled: CompiledScenario) -> Any:
    """The single-agent action space of ``compiled`` (one world built, not reset)."""
    from ..adapters.gymnasium import HivexVectorEnv

    return HivexVectorEnv(compiled, num_worlds=1).single_action_space


def policy_for(checkpoint: dict[str, Any], compiled: CompiledScenario, device: str = "cpu") -> ActorCritic:
    """The checkpoint's network, to play ``compiled``: another scenario of the environment it trained on (another
    task, level or seeds), never another environment."""
    from ..adapters.gymnasium import HivexVectorEnv

    trained = checkpoint["compiled"]
    if trained.environment != compiled.environment:
        raise TrainError(f"the checkpoint trained on {trained.environment} (scenario {trained.name!r}) and cannot play "
                         f"{compiled.environment} (scenario {compiled.name!r}): a policy plays the environment it "
                         "trained on")
    env = HivexVectorEnv(compiled, num_worlds=1)
    agent = ActorCritic(env.single_observation_space, env.single_action_space, checkpoint["config"])
    try:
        agent.load_state_dict(checkpoint["model"])
    except RuntimeError as exc:  # the same environment, so the file's weights were changed after training
        first = str(exc).splitlines()[0]
        raise TrainError("the checkpoint's weights do not fit the network its own hyperparameters build: "
                         f"{first}") from None
    return agent.to(torch_device(device)).eval()


# what may change when a run goes on: how long it trains and where and how it runs, not what it learns
RESUMABLE_CHANGES = frozenset({"max_steps", "device", "torch_threads", "checkpoint_every", "keep_checkpoints"})


def resume_state(path: Path, compiled: CompiledScenario, cfg: PPOConfig) -> dict[str, Any]:
    """The checkpoint a run goes on from, checked to be resumable with ``compiled`` and ``cfg``: the same
    scenario (fingerprint) and the same hyperparameters but for :data:`RESUMABLE_CHANGES`."""
    if not path.is_file():
        raise TrainError(f"cannot resume: no checkpoint at {path} (train without --resume first)")
    data = load_checkpoint(path)
    if "training" not in data:
        raise TrainError(f"cannot resume from {path}: it holds weights only, not the optimizer state")
    if data["fingerprint"] != compiled.fingerprint:
        raise TrainError(f"cannot resume from {path}: it trained scenario {data['compiled'].name!r}, which differs "
                         f"from {compiled.name!r} (fingerprint {data['fingerprint']} != {compiled.fingerprint})")
    before, now = data["config"].model_dump(), cfg.model_dump()
    changed = sorted(k for k in now if before[k] != now[k] and k not in RESUMABLE_CHANGES)
    if changed:
        listing = ", ".join(f"{k}: {before[k]!r} -> {now[k]!r}" for k in changed)
        raise TrainError(f"cannot resume from {path}: hyperparameters differ from the run's ({listing}); "
                         f"only {', '.join(sorted(RESUMABLE_CHANGES))} may change")
    return data
