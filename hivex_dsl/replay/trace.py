"""The trace: a recorded episode as plain JSON data, what `hivex replay --trace FILE` writes and the page embeds.

Format ``hivex-replay-trace/1`` (documented in docs/replay.md): a JSON object with ``episodes``, one per played
episode (two with ``--compare``). Per-decision values are lists indexed ``[decision - 1][agent]``, numbers rounded
to :data:`DIGITS` significant digits (a decision's weighted terms add up to its reward to that precision).
"""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any, Sequence

import numpy as np

from ..evaluation import published
from .record import Episode

FORMAT = "hivex-replay-trace/1"
DIGITS = 6
# every field of an episode in the trace, with what it holds: docs/replay.md's table (nested lists of T decisions,
# A agents, K action and D observation components)
FIELDS = {
    "scenario": "the scenario: name, environment, task, level_name and level, sweep_point, fingerprint (of the lock), "
                "source, episode_decisions, decision_period",
    "policy": "what played: kind (scripted, random, zeros or checkpoint); a checkpoint's path, trained_on (its "
              "scenario), trained_fingerprint, agent_steps, weights_sha256 and actions (sampled)",
    "seed": "the environment seed given (null: the split's own seed stream)",
    "split": "the seed split, train or test",
    "decisions": "T, the decisions played (the episode's, or fewer with --steps)",
    "agents": "the A agents' names; an agent's index is its place here",
    "terms": "the active reward terms (those whose weight is not 0), in the composer's order",
    "term_titles": "term -> its title as the docs write it",
    "statistics": "the environment's logged statistics (as the original logs them, without its prefix)",
    "published_statistics": "those of them the paper publishes for this task and level",
    "statistic_descriptions": "statistic -> what it counts",
    "observation_labels": "a name per component of the vector observation (older stacks marked \"(previous)\")",
    "action_meanings": "the simulator's description of the action components",
    "reward": "(T, A) the reward the environment returned for each decision (0 once the agent's episode ended)",
    "playing": "(T, A) true while the agent was in its episode when the decision began",
    "raw": "term -> (T, A) the term's unweighted value, summed over the decision's physics steps",
    "weighted": "term -> (T, A) what the term paid: its weight times its value at each physics step, summed; the "
                "terms' weighted values of a decision add up to its reward",
    "weights": "term -> (T,) the term's weight at the decision's last physics step (it moves only under a schedule)",
    "actions": "(T, A, K) the action's components, a Dict space's parts in key order (continuous, then discrete)",
    "observations": "(T, A, D) the vector observation the agent acted on (the camera is left out)",
    "statistics_so_far": "statistic -> (T, A) its value over the episode up to and including the decision",
    "events": "[{decision, agent, kind, name}] what happened: the simulator's events (kind event; agent null for a "
              "world event such as fire_out), endings (terminated: a crash or a task's ending; truncated: the time "
              "limit; world ended) and schedule changes (kind schedule)",
    "frame_decisions": "the decisions taken before each of the page's frames (0: the start)",
    "frame_step": "a frame every frame_step decisions (--frame-step), and one after the last decision",
}


def significant(values: np.ndarray, digits: int = DIGITS) -> list:
    """``values`` rounded to ``digits`` significant digits, as nested lists of floats (bools stay bools)."""
    array = np.asarray(values)
    if array.dtype == bool:
        return array.tolist()
    array = array.astype(np.float64)
    magnitude = np.floor(np.log10(np.abs(np.where(array == 0.0, 1.0, array))))
    scale = 10.0 ** (digits - 1 - magnitude)
    return (np.round(array * scale) / scale).tolist()


def episode_data(episode: Episode) -> dict[str, Any]:
    """The episode as JSON data (see the module and docs/replay.md)."""
    compiled = episode.compiled
    core_statistics = compiled.entry.statistics
    cell = published.cell_for(compiled)
    return {
        "scenario": {"name": compiled.name, "environment": compiled.environment, "task": compiled.task_name,
                     "level_name": compiled.entry.info.level_field, "level": compiled.level, "sweep_point": dict(compiled.sweep_point),
                     "fingerprint": compiled.fingerprint, "source": compiled.source,
                     "episode_decisions": compiled.episode_decisions, "decision_period": compiled.decision_period},
        "policy": episode.policy,
        "seed": episode.seed,
        "split": episode.split,
        "decisions": episode.decisions,
        "agents": list(compiled.agent_names),
        "terms": list(episode.terms),
        "term_titles": _term_titles(compiled, episode.terms),
        "statistics": list(episode.statistics),
        "published_statistics": sorted(name for name in episode.statistics
                                       if cell is not None and cell.statistic(name) is not None),
        "statistic_descriptions": {name: core_statistics[name].description for name in episode.statistics}
        if core_statistics is not None else {},
        "observation_labels": observation_labels(episode.observation_labels, episode.observations.shape[-1]),
        "action_meanings": episode.action_meanings,
        "reward": significant(episode.reward),
        "playing": significant(episode.playing),
        "raw": {name: significant(values) for name, values in episode.terms.items()},
        "weighted": {name: significant(values) for name, values in episode.weighted.items()},
        "weights": {name: significant(values) for name, values in episode.weights.items()},
        "actions": significant(episode.actions),
        "observations": significant(episode.observations),
        "statistics_so_far": {name: significant(values) for name, values in episode.statistics.items()},
        "events": episode.events,
        "frame_decisions": list(episode.frame_decisions),
        "frame_step": episode.frame_step,
    }


def trace_data(episodes: Sequence[Episode]) -> dict[str, Any]:
    """Every episode's data under one ``format`` (two episodes: ``--compare``, the first the one asked for)."""
    return {"format": FORMAT, "digits": DIGITS, "episodes": [episode_data(e) for e in episodes]}


def write_trace(data: dict[str, Any], path: Path) -> None:
    """Write ``data`` (:func:`trace_data`) as JSON to ``path``."""
    path.write_text(json.dumps(data, separators=(",", ":")) + "\n", encoding="utf-8")


def observation_labels(labels: Sequence[str], size: int) -> list[str]:
    """A name for each of the ``size`` vector observation components from the simulator's ``labels`` of one stack
    (stacks newest first, the older marked "(previous)", "(2 before)", ...); ``[i]`` where they do not fit."""
    if not labels or size % len(labels):
        return [f"[{i}]" for i in range(size)]
    older = ["", " (previous)"] + [f" ({k} before)" for k in range(2, size // len(labels))]
    return [f"{label}{older[i // len(labels)]}" for i, label in enumerate(labels * (size // len(labels)))]


def _term_titles(compiled: Any, terms: dict[str, np.ndarray]) -> dict[str, str]:
    """Each term's title as the docs write it (its contract's), the name where there is none."""
    titles = {contract.name: contract.title for contract in compiled.term_contracts}
    return {name: titles.get(name) or name for name in terms}


__all__ = ["DIGITS", "FIELDS", "FORMAT", "episode_data", "observation_labels", "significant", "trace_data", "write_trace"]
