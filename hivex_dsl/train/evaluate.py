"""`hivex evaluate`: the paper's test protocol (the trained policy, frozen, on the test seeds), reported as
the mean and spread of the per-agent return and of every published statistic, beside the published cell."""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any

import numpy as np
import torch

from ..compiler import CompiledScenario
from .checkpoint import load_checkpoint, policy_for
from .config import TrainError
from .logs import EpisodeLog
from .networks import to_tensors
from .ppo import make_env

MAX_WORLDS = 16


def _spread(values: np.ndarray) -> dict[str, float]:
    return {"mean": float(values.mean()), "std": float(values.std())}


def _published(compiled: CompiledScenario) -> dict[str, Any] | None:
    from ..published import cell_for

    cell = cell_for(compiled)
    if cell is None:
        return None
    return {"return": {"mean": cell.return_mean, "std": cell.return_std},
            "statistics": {name: {"mean": mean, "std": std} for name, (mean, std) in cell.statistics.items()}}


def play(compiled: CompiledScenario, agent: torch.nn.Module, episodes: int, split: str = "test",
         deterministic: bool = False, seed: int = 0) -> dict[str, Any]:
    """Run the policy until ``episodes * agents`` per-agent episodes ended; -> their concatenated summaries."""
    torch.manual_seed(seed)
    wanted = episodes * compiled.agents
    env, obs = make_env(compiled, min(episodes, MAX_WORLDS), split)
    rounds = math.ceil(episodes / env.num_worlds) + 1
    log = EpisodeLog()
    for _ in range(rounds * (compiled.episode_length + 1)):
        with torch.no_grad():
            cont, disc, _ = agent.act(to_tensors(obs), deterministic=deterministic)
        obs, _, _, _, infos = env.step(agent.layout.to_env(cont, disc))
        log.record(infos)
        values = log.values()
        if values and values["return"].size >= wanted:
            break
    values = log.values()
    if not values or values["return"].size < wanted:
        raise TrainError(f"only {0 if not values else values['return'].size} of {wanted} agent episodes ended")
    return {"return": values["return"][:wanted], "reward_terms": {k: v[:wanted] for k, v in values["reward_terms"].items()},
            "statistics": {k: v[:wanted] for k, v in values["statistics"].items()}}


def evaluate(checkpoint: str | Path, scenario: CompiledScenario | None = None, split: str = "test",
             episodes: int = 10, deterministic: bool = False, seed: int = 0) -> dict[str, Any]:
    """The report of one checkpoint on its own scenario (or ``scenario``, whose spaces must match)."""
    loaded = load_checkpoint(checkpoint)
    compiled = scenario if scenario is not None else loaded["compiled"]
    agent = policy_for(loaded, compiled)
    played = play(compiled, agent, episodes, split, deterministic, seed)
    return {"checkpoint": str(checkpoint), "scenario": compiled.name, "environment": compiled.environment,
            "task_index": compiled.task_index, "level": compiled.level, "trained_agent_steps": loaded["agent_steps"],
            "split": split, "seed": getattr(compiled.seeds, split), "episodes": episodes,
            "agent_episodes": int(played["return"].size), "actions": "mode" if deterministic else "sampled",
            "return": _spread(played["return"]),
            "statistics": {k: _spread(v) for k, v in played["statistics"].items()},
            "reward_terms": {k: _spread(v) for k, v in played["reward_terms"].items()},
            "published": _published(compiled)}


def format_report(report: dict[str, Any]) -> str:
    """A table: ours (mean, std) beside the published (mean, std) of the return and every statistic."""
    published = report["published"] or {"return": None, "statistics": {}}
    lines = [f"{report['scenario']}  {report['split']} seed {report['seed']}, {report['episodes']} episodes "
             f"({report['agent_episodes']} agent episodes), {report['actions']} actions, "
             f"policy trained {report['trained_agent_steps']} agent-steps",
             f"{'':36} {'mean':>12} {'std':>10}   {'published':>12} {'std':>10}"]

    def row(name: str, ours: dict[str, float], paper: dict[str, float] | None) -> str:
        theirs = f"{paper['mean']:12.3f} {paper['std']:10.3f}" if paper else f"{'-':>12} {'-':>10}"
        return f"{name[:36]:36} {ours['mean']:12.3f} {ours['std']:10.3f}   {theirs}"

    lines.append(row("return", report["return"], published["return"]))
    for name, ours in report["statistics"].items():
        paper = next((v for k, v in published["statistics"].items() if k.split("/", 1)[-1] == name), None)
        lines.append(row(name, ours, paper))
    for name, ours in report["reward_terms"].items():
        lines.append(row(f"term {name}", ours, None))
    if report["published"] is None:
        lines.append("(the paper published no result for this task and level)")
    return "\n".join(lines)
