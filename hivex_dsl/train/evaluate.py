"""`hivex evaluate`: the paper's test protocol (the trained policy, frozen, on the test seeds), reported as
the mean and spread of the per-agent return, Episode Length and every published statistic, beside the published cell
(and the original's test Episode Length, which the paper did not publish, from its plot pages)."""

from __future__ import annotations

from contextlib import contextmanager
from pathlib import Path
from typing import Any, Callable, Iterator

import numpy as np
import torch

from ..adapters.gymnasium import flatten_slots, unflatten_slots
from ..compiler import CompiledScenario
from ..evaluation import published
from ..evaluation.audit import compared
from ..evaluation.original.compare import as_logged_there, original_test_average
from ..evaluation.original.evidence import EPISODE_LENGTH
from ..evaluation.progress import EpisodeBar, bar
from ..evaluation.rollout import rollout
from .checkpoint import load_checkpoint, policy_for
from .config import TrainError
from .kernels import cpu_kernels
from .networks import fixed_weights, to_tensors


def _spread(values: np.ndarray) -> dict[str, float]:
    return {"mean": float(values.mean()), "std": float(values.std())}


def published_result(compiled: CompiledScenario) -> dict[str, Any] | None:
    """The paper's PPO result for the cell the scenario reproduces (its return and statistics), or None."""
    cell = published.cell_for(compiled)
    if cell is None:
        return None
    return {"return": {"mean": cell.return_mean, "std": cell.return_std},
            "statistics": {name: {"mean": mean, "std": std} for name, (mean, std) in cell.statistics.items()}}


def _original_episode_length(compiled: CompiledScenario) -> float | None:
    """The original's Episode Length over the test runs of the published cell the scenario reproduces (its average
    sheet's value: the mean of the test curve); None where the scenario is no published cell or the sheet has none."""
    cell = published.cell_for(compiled)
    if cell is None:
        return None
    return original_test_average(cell.environment, cell.task_index, cell.level, f"Environment/{EPISODE_LENGTH}")


def network_policy(agent: torch.nn.Module, agents: int, deterministic: bool = False) -> Callable[[Any], Any]:
    """The network as a batched policy of one world: observations (1, agents, ...) and the action mask (1, agents, N)
    or None -> actions (1, agents, ...); it takes the mask where the network was trained to (``action_masks``)."""

    def ppo(observations: Any, action_mask: np.ndarray | None = None) -> Any:
        mask = None if action_mask is None else torch.as_tensor(action_mask.reshape(agents, -1), dtype=torch.bool)
        with torch.no_grad():
            cont, disc, _ = agent.act(to_tensors(flatten_slots(observations, agents)), deterministic=deterministic,
                                      mask=mask)
        return unflatten_slots(agent.layout.to_env(cont, disc), (1, agents))

    ppo.takes_action_mask = agent.takes_masks  # type: ignore[attr-defined]
    return ppo


@contextmanager
def limited_threads(count: int) -> Iterator[None]:
    """torch on ``count`` threads inside the block, its own count restored after."""
    threads = torch.get_num_threads()
    torch.set_num_threads(count)
    try:
        yield
    finally:
        torch.set_num_threads(threads)


def play(compiled: CompiledScenario, agent: torch.nn.Module, episodes: int, split: str = "test",
         deterministic: bool = False, seed: int = 0, torch_threads: int = 1, progress: bool = False
         ) -> dict[str, Any]:
    """The policy's first ``episodes`` episodes of ``split``, one after another in one world: the same episodes
    the random and scripted levels play (:func:`hivex_dsl.evaluation.rollout.rollout`), every one whole, however long.
    Each agent-episode's Episode Length is its decisions less one, as ML-Agents logs it
    (:func:`~hivex_dsl.evaluation.original.compare.as_logged_there`).

    (Counting the first episodes to end across parallel worlds would favour short ones: in WRM, where an
    episode ends when its fire goes out, that halved the measured return.) -> flat per-agent arrays.

    The network runs on ``torch_threads`` threads (torch's count is restored after): one world's few agents
    are batches too small to share, and on a machine busy with training torch's default of one thread per
    core made every step twenty times slower (threads spinning for cores they could not get). ``progress``
    shows a bar over the decisions on stderr where it is a terminal."""
    torch.manual_seed(seed)
    decisions = compiled.episode_decisions
    with limited_threads(torch_threads), fixed_weights(), bar(episodes * decisions, f"evaluate {compiled.name}",
                                                              unit="decision", enabled=progress) as shown:
        done = rollout(compiled, network_policy(agent, compiled.agents, deterministic), episodes, split,
                       progress=EpisodeBar(shown, decisions))
    return {"return": done.returns.reshape(-1),
            "episode_length": as_logged_there(EPISODE_LENGTH, done.decisions.reshape(-1).astype(float)),
            "reward_terms": {k: v.reshape(-1) for k, v in done.terms.items()},
            "weighted_reward_terms": {k: done.weighted(k).reshape(-1) for k in done.terms},
            "statistics": {k: v.reshape(-1) for k, v in done.statistics.items()}, "pooled": done.pooled()}


def checkpoint_policies(checkpoint: str | Path, deterministic: bool = False, seed: int = 0
                        ) -> Callable[[CompiledScenario], Callable[[Any], Any]]:
    """The checkpoint (read and checked once) as a maker of batched policies, one per scenario it plays: each
    scenario must be of the environment it trained on (:func:`policy_for` says why not otherwise). Making one
    seeds torch's action sampling with ``seed``, so a scenario's episodes do not depend on those played before."""
    loaded = load_checkpoint(checkpoint)

    def for_scenario(compiled: CompiledScenario) -> Callable[[Any], Any]:
        agent = policy_for(loaded, compiled)
        torch.manual_seed(seed)
        return network_policy(agent, compiled.agents, deterministic)

    return for_scenario


def level_checkpoint(sweep: Path, level: int) -> Path:
    """The checkpoint.pt of a level sweep's one run at terrain level ``level`` (`hivex train` names a point's folder by
    its swept values, ending ``terrain_level=<level>``); a TrainError says what it found otherwise."""
    found = sorted(Path(sweep).glob(f"*level={level}/checkpoint.pt"))
    if len(found) != 1:
        raise TrainError(f"{sweep}: expected one run of terrain level {level} with a checkpoint.pt, found {len(found)}")
    return found[0]


def evaluate(checkpoint: str | Path, scenario: CompiledScenario | None = None, split: str = "test",
             episodes: int = 10, deterministic: bool = False, seed: int = 0, torch_threads: int = 1,
             progress: bool = False) -> dict[str, Any]:
    """The report of one checkpoint on its own scenario (or ``scenario``, whose spaces must match); ``progress``
    shows a bar on stderr where it is a terminal."""
    loaded = load_checkpoint(checkpoint)
    compiled = scenario if scenario is not None else loaded["compiled"]
    kernels = loaded["config"].cpu_kernels
    with cpu_kernels(kernels):  # as it trained: a portable run's test returns are then alike on other processors
        agent = policy_for(loaded, compiled)
        played = play(compiled, agent, episodes, split, deterministic, seed, torch_threads, progress)
    return {"checkpoint": str(checkpoint), "scenario": compiled.name, "environment": compiled.environment,
            "task_index": compiled.task_index, "level": compiled.level, "trained_agent_steps": loaded["agent_steps"],
            "trained_wall_s": loaded.get("wall_s"),
            "split": split, "seed": getattr(compiled.seeds, split), "episodes": episodes,
            "agent_episodes": int(played["return"].size), "actions": "mode" if deterministic else "sampled",
            "cpu_kernels": kernels,
            "return": _spread(played["return"]), "episode_length": _spread(played["episode_length"]),
            "statistics": {k: _spread(v) | ({"pooled": played["pooled"][k]} if k in played["pooled"] else {})
                           for k, v in played["statistics"].items()},
            "reward_terms": {k: _spread(v) for k, v in played["reward_terms"].items()},
            "weighted_reward_terms": {k: _spread(v) for k, v in played["weighted_reward_terms"].items()},
            "weights": {k: compiled.weights[k] for k in played["reward_terms"]},
            "published": published_result(compiled), "original_episode_length": _original_episode_length(compiled),
            "caveat": published.caveat(compiled)}


def format_report(report: dict[str, Any]) -> str:
    """A table: ours (mean, std) beside the published (mean, std) of the return and every statistic (a running
    mean's mean in its pooled form, :func:`hivex_dsl.evaluation.audit.compared`) and beside the original's test
    average of Episode Length, then each reward term's weighted episode sum (its weight times its sum, as `hivex
    audit` shows it; they add up to the return)."""
    cell = report["published"] or {"return": None, "statistics": {}}
    lines = [f"{report['scenario']}  {report['split']} seed {report['seed']}, {report['episodes']} episodes "
             f"({report['agent_episodes']} agent episodes), {report['actions']} actions, "
             f"policy trained {report['trained_agent_steps']} agent-steps",
             f"{'':36} {'mean':>12} {'std':>10}   {'published':>12} {'std':>10}"]

    def row(name: str, ours: dict[str, float], paper: dict[str, float] | None) -> str:
        if paper is None:
            theirs = f"{'-':>12} {'-':>10}"
        else:  # the original's test Episode Length is an average without a spread
            theirs = f"{paper['mean']:12.3f} " + (f"{paper['std']:10.3f}" if "std" in paper else f"{'-':>10}")
        return f"{name[:36]:36} {compared(ours):12.3f} {ours['std']:10.3f}   {theirs}"

    lines.append(row("return", report["return"], cell["return"]))
    original_length = report["original_episode_length"]
    lines.append(row(EPISODE_LENGTH, report["episode_length"],
                     None if original_length is None else {"mean": original_length}))
    for name, ours in report["statistics"].items():
        paper = next((v for k, v in cell["statistics"].items() if k.split("/", 1)[-1] == name), None)
        lines.append(row(name, ours, paper))
    for name, ours in report["weighted_reward_terms"].items():  # as `hivex audit` shows them: weight x episode sum
        lines.append(row(f"term {name} x{report['weights'][name]:g} (weighted)", ours, None))
    if original_length is not None:
        lines.append(f"({EPISODE_LENGTH}: decisions less one, as ML-Agents logs it; beside it the original's test "
                     "average from its plot pages, which the paper did not publish)")
    if report["published"] is None:
        lines.append(f"(no published result: {report['caveat']})" if report.get("caveat") else
                     "(the paper published no result for this task and level)")
    return "\n".join(lines)
