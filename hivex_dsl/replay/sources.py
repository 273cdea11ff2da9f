"""What plays an episode of the page: a named policy, or a checkpoint (a ``.pt`` file, or the ``checkpoint.pt`` of a
training run's directory) on the scenario it trained on or, for a comparison, on another of its environment."""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import Any, Callable, Optional

from ..base.errors import HivexError
from ..compiler import CompiledScenario

CHECKPOINT_FILE = "checkpoint.pt"  # what `hivex train` keeps in its run directory


@dataclass
class Player:
    """One policy on one scenario: what an episode of the page is recorded from."""

    compiled: CompiledScenario
    policy: str | Callable[[Any], Any]  # 'scripted', 'random', 'zeros' or a batched policy
    info: dict[str, Any]  # the policy as the page shows it


def checkpoint_path(target: str | Path) -> Optional[Path]:
    """The checkpoint ``target`` names (a ``.pt`` file, or a run directory's ``checkpoint.pt``); None for anything
    else (a scenario). A directory without one is refused, with what it holds instead."""
    path = Path(target)
    if path.is_dir():
        found = path / CHECKPOINT_FILE
        if found.is_file():
            return found
        points = sorted(p.parent.name for p in path.glob(f"*/{CHECKPOINT_FILE}"))
        if points:
            raise HivexError(f"{path} is the run directory of a sweep: replay one point's run, e.g. "
                             f"`hivex replay {path / points[0]}` ({len(points)} points have a checkpoint)")
        raise HivexError(f"{path} is a directory without a {CHECKPOINT_FILE}: give a scenario file, a checkpoint or "
                         "the run directory of `hivex train`")
    return path if path.suffix == ".pt" else None


def checkpoint_player(path: Path, compiled: Optional[CompiledScenario] = None, own_scenario: bool = True) -> Player:
    """The policy of the checkpoint at ``path`` (its actions sampled, as `hivex evaluate` samples them) on
    ``compiled``, by default the scenario it trained on. With ``own_scenario`` a scenario other than that one (its
    fingerprint differs) is refused; without it any scenario of its environment is played (a comparison).
    Needs torch (the ``train`` extra)."""
    import torch

    from ..train.checkpoint import checksum, load_checkpoint, policy_for
    from ..train.evaluate import network_policy

    loaded = load_checkpoint(path)
    trained = loaded["compiled"]
    scenario = trained if compiled is None else compiled
    if own_scenario and loaded["fingerprint"] != scenario.fingerprint:
        raise HivexError(f"the checkpoint {path} trained on the scenario {trained.name!r} ({trained.environment}, "
                         f"fingerprint {loaded['fingerprint'][7:19]}), not on {scenario.name!r} (fingerprint "
                         f"{scenario.fingerprint[7:19]}): replay it on its own scenario with `hivex replay {path}`, "
                         f"or show it beside another reward table with --compare")
    agent = policy_for(loaded, scenario)
    torch.manual_seed(0)
    info = {"kind": "checkpoint", "checkpoint": str(path), "trained_on": trained.name,
            "trained_fingerprint": loaded["fingerprint"], "agent_steps": int(loaded["agent_steps"]),
            "weights_sha256": (loaded.get("checksums") or {}).get("model") or checksum(loaded["model"]),
            "actions": "sampled"}
    return Player(scenario, network_policy(agent, scenario.agents), info)


def same_policy(first: Player, compiled: CompiledScenario) -> Player:
    """``first``'s policy on another scenario of its environment and agent count (a comparison of reward tables)."""
    if (compiled.environment, compiled.agents) != (first.compiled.environment, first.compiled.agents):
        raise HivexError(f"--compare: its scenario {compiled.name!r} has {compiled.agents} agents of "
                         f"{compiled.environment}, the replayed one {first.compiled.agents} of "
                         f"{first.compiled.environment}: compare scenarios of one environment and agent count")
    if first.info["kind"] == "checkpoint":
        return checkpoint_player(Path(first.info["checkpoint"]), compiled, own_scenario=False)
    return Player(compiled, first.policy, dict(first.info))


__all__ = ["CHECKPOINT_FILE", "Player", "checkpoint_path", "checkpoint_player", "same_policy"]
