"""What the CLI prints: compiled scenario summaries, episode runs with per-term returns, GIF frames."""

from __future__ import annotations

import sys
import time
from typing import Any, Callable, Iterator, Optional, TextIO

import numpy as np

from ..compiler import CompiledScenario
from ..runtime.batched import BatchedEnv, Split
from ..sim.spaces import check_actions, describe_space
from .policies import make_policy
from .progress import EpisodeBar, bar, echo


def _fmt(value: object) -> str:
    return f"{value:g}" if isinstance(value, float) else str(value)


def _seeds(compiled: CompiledScenario) -> str:
    show = lambda s: _fmt(s) if isinstance(s, int) else "[" + ", ".join(map(str, s)) + "]"  # noqa: E731
    return f"train {show(compiled.seeds.train)} | test {show(compiled.seeds.test)}"


def describe_compiled(compiled: CompiledScenario) -> str:
    """A readable multi-line summary of one resolved scenario."""
    entry, info = compiled.entry, compiled.entry.info
    sim = entry.make_simulator(compiled)
    task = entry.reward_table.tasks[compiled.task_index]
    names = compiled.agent_names
    rows = [
        ("environment", f"{info.id} ({info.title})"),
        ("task", f"{task.index} {task.name} - {task.title}"),
    ]
    if info.level_field == "pattern":
        rows.append(("pattern", f"{compiled.level} {entry.level_names[compiled.level]}"))
    elif info.level_field:
        rows.append((info.level_field, str(compiled.level)))
    rows += [
        ("agents", f"{compiled.agents} ({names[0]} .. {names[-1]})" if len(names) > 1 else f"1 ({names[0]})"),
        ("episode_length", str(compiled.episode_length)),
        *([("decision_period", f"{compiled.decision_period} physics steps per decision "
                               f"({compiled.episode_decisions} decisions per episode)")]
          if compiled.decision_period != 1 else []),
        ("seeds", _seeds(compiled)),
        ("ends on", _endings(compiled)),
        ("observation", describe_space(sim.observation_space)),
        ("action", f"{describe_space(sim.action_space)}: {sim.action_meanings}"),
        ("fingerprint", compiled.fingerprint),
    ]
    width = max(len(k) for k, _ in rows)
    lines = [f"{compiled.name}  ({compiled.source})"] + [f"  {k:<{width}}  {v}" for k, v in rows]
    lines.append("  reward weights (task column with overrides), each term's range per step:")
    ranges = {c.name: f"[{c.low:g}, {c.high:g}]" for c in compiled.term_contracts}
    width = max(map(len, compiled.weights), default=0)
    lines += [f"    {w:>10g}  {term:<{width}}  {ranges.get(term, '')}" + _weight_note(compiled, term, w)
              for term, w in compiled.weights.items()]
    if compiled.expressions is not None and compiled.expressions.terms:
        lines.append("  expression terms:")
        lines += [f"    {t.contract.name} = {t.contract.equation}" for t in compiled.expressions.terms]
    lines.append("  params:")
    lines += [f"    {k} = {_fmt(v)}" for k, v in compiled.params.model_dump().items()]
    return "\n".join(lines)


def _endings(compiled: CompiledScenario) -> str:
    """Every ending: the task's and the scenario's events, then their expressions (each as written)."""
    expressions = compiled.expressions.endings if compiled.expressions is not None else ()
    endings = [*dict.fromkeys(compiled.ends_on), *(f"`{e.source}` ({'world' if e.per == 'world' else 'agent'})" for e in expressions)]
    return "; ".join(endings) + ("; the episode length" if endings else "the episode length only")


def weight_label(compiled: CompiledScenario, term: str) -> str:
    """A term's weight as a column header shows it: ``x0.5``, or a schedule as written, not the value it starts
    from: ``x0→-0.2 over 1e6`` (linear over 1,000,000 env steps), ``x0→-0.2 at 1e6`` (a step schedule)."""
    schedule = compiled.schedules.get(term)
    if schedule is None:
        return f"x{compiled.weights[term]:g}"
    when = "over" if schedule.kind == "linear" else "at"
    return f"x{schedule.start:g}→{schedule.end:g} {when} {_count(schedule.over_steps)}"


def _count(steps: int) -> str:
    """A step count, short where that is exact (``1e6``, ``2.5e5``), else in full (``1,234,567``)."""
    short = f"{steps:.3g}"
    if steps >= 10_000 and "e" in short and float(short) == steps:
        mantissa, exponent = short.split("e")
        return f"{mantissa}e{int(exponent)}"
    return f"{steps:,}"


def _weight_note(compiled: CompiledScenario, term: str, weight: float) -> str:
    schedule = compiled.schedules.get(term)
    if schedule is not None:
        return f"  (schedule: {schedule.start:g} -> {schedule.end:g} over {schedule.over_steps:,} env steps, {schedule.kind})"
    if term in compiled.unpaid:
        return "  (logged in the statistics, not paid: the reward table's unpaid)"
    return "" if weight else "  (inactive)"


def describe_sweep(compiled: list[CompiledScenario]) -> str:
    """One line per grid point, then the full summary of the first point."""
    first = compiled[0]
    axes = list(first.sweep_point)
    header = ["#"] + axes + ["task name", "fingerprint"]
    rows = [[str(i)] + [str(sc.sweep_point[a]) for a in axes] + [sc.task_name, sc.fingerprint[7:19]]
            for i, sc in enumerate(compiled)]
    widths = [max(len(r[c]) for r in rows + [header]) for c in range(len(header))]
    table = ["  ".join(cell.ljust(w) for cell, w in zip(row, widths)) for row in [header] + rows]
    return "\n".join([f"{first.source}: {len(compiled)} scenarios over {' x '.join(axes)}", *table, "",
                      "first point:", describe_compiled(first)])


class Progress(EpisodeBar):
    """Progress of `hivex run` on stderr: the shared bar over the episodes' decisions on a terminal, and a line per
    finished episode (its steps and mean return) in any case."""

    def __init__(self, total_episodes: int, decisions: int, stream: Optional[TextIO] = None):
        self.total, self.stream = total_episodes, stream or sys.stderr
        self.started = time.monotonic()
        super().__init__(bar(total_episodes * decisions, "run", unit="decision", stream=self.stream), decisions,
                         say=self._line)

    def _line(self, episode: int, mean_return: float, steps: int) -> None:
        echo(f"  episode {episode + 1}/{self.total}: {steps} steps, mean return per agent {mean_return:.2f} "
             f"({time.monotonic() - self.started:.1f} s)", self.stream)


def run_episodes(compiled: CompiledScenario, policy_name: str, episodes: int, split: Split = "train",
                 seed: Optional[int] = None, progress: Optional[Progress] = None) -> str:
    """Run whole episodes in one world; returns the per-agent table of returns and term sums."""
    shown = progress or Progress(episodes, compiled.episode_decisions)
    try:
        returns, sums = collect_returns(compiled, policy_name, episodes, split, seed, shown)
    finally:
        if progress is None:  # a caller's own progress stays the caller's to close
            shown.close()
    terms = list(sums)
    header = ["agent", "return"] + [f"{t} ({weight_label(compiled, t)})" for t in terms]
    rows = [[name, returns[:, i].mean()] + [sums[t][:, i].mean() for t in terms]
            for i, name in enumerate(compiled.agent_names)]
    rows.append(["mean", returns.mean()] + [sums[t].mean() for t in terms])
    cells = [header] + [[r[0]] + [f"{v:.2f}" for v in r[1:]] for r in rows]
    widths = [max(len(row[c]) for row in cells) for c in range(len(header))]
    lines = [f"{compiled.name}: {episodes} episode(s), policy {policy_name}, split {split}; "
             "returns are per agent per episode (term columns unweighted)"]
    for k, row in enumerate(cells):
        lines.append("  ".join(row[0].ljust(widths[0]) if c == 0 else row[c].rjust(widths[c]) for c in range(len(row))))
        if k == 0 or k == len(cells) - 2:
            lines.append("  ".join("-" * w for w in widths))
    return "\n".join(lines)


def collect_returns(compiled: CompiledScenario, policy_name: str, episodes: int, split: Split = "train",
                    seed: Optional[int] = None, progress: Optional[Progress] = None
                    ) -> tuple[np.ndarray, dict[str, np.ndarray]]:
    """(episodes, agents) returns and unweighted per-term sums of whole episodes (see :func:`hivex_dsl.evaluation.rollout.rollout`)."""
    from .rollout import rollout

    done = rollout(compiled, policy_name, episodes, split, seed, progress)
    return done.returns, done.terms


def episode_frames(compiled: CompiledScenario, policy_name: str | Callable[[Any], Any], steps: int, every: int,
                   seed: Optional[int] = None, progress=None) -> Iterator[np.ndarray]:
    """Frames of one world every ``every`` steps for up to ``steps`` steps (stops when the episode ends);
    ``policy_name`` is 'scripted', 'random', 'zeros' or a batched policy (a trained network's, say);
    ``progress`` (a tqdm bar, optional) advances one per step."""
    core = BatchedEnv(compiled, batch=1)
    space = core.sim.action_space
    policy = policy_name if callable(policy_name) else make_policy(
        policy_name, compiled, space, core.shape, seed=0 if seed is None else seed)
    observations = core.reset(seed)
    yield core.render(0)
    for step in range(1, steps + 1):
        actions = check_actions(space, policy(observations), compiled.agent_names, core.sim.action_meanings)
        observations = core.step(actions).observations
        if progress is not None:
            progress.update(1)
        if step % every == 0:
            yield core.render(0)
        if not core.alive.any():
            break
