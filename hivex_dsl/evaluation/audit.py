"""`hivex audit`: the reward property tester a task author runs on a scenario (or every point of a sweep).

It rolls the all-zeros, random and scripted policies for a few episodes on the test seeds and reports,
per policy and per active term, what the term paid per agent and episode (mean, spread, share of the
return). It raises a :class:`Flag` for what usually means a reward bug:

- ``action_independent``: a term pays the same episode sums under all three policies (and is at least 5%
  of what the random or the scripted policy earns); for a global-scope term (a property of the whole world,
  which a task may mean the agents to be unable to change) this is a note, not a flag; a term paid only on
  the steps that end episodes, whose episodes last differently long under the policies, is neither (the
  actions decide when it is earned);
- ``first_step``: an event or terminal term pays on the first step after reset under the all-zeros policy;
- ``dominant``: one term pays at least 90% of what the scripted policy earns from the terms that can
  reward it (where at least two can);
- ``contract_range`` / ``contract_sign`` / ``contract_timing``: a per-step value outside the term's
  declared range or sign, a terminal term paid before the end, an event term paid on most steps;
- ``beats_published``: where the scenario is a published cell with a PPO return above 0.5, the all-zeros
  or random policy earns more than that return plus 10%;
- ``published_scale``: the all-zeros or random policy's mean return is more than 10 times the published one
  in size (a scripted policy may well outdo the paper's PPO);
- ``below_zeros``: with ``--checkpoint``, the trained policy earns less than the all-zeros policy.

With ``--checkpoint`` a policy trained by `hivex train` is rolled beside them (as 'trained'): its column shows what
the reward paid a learner, and the contract flags check its values too (the published ones concern only the
all-zeros and random policies).

Notes are findings that are not flags: they are printed and stored but do not fail ``--strict``.

With a ``decision_period`` k the policies act once per decision and a step's values are a decision's, the
sums of k physics steps: a term's declared range is read as that of such a sum (k times it, or one step's
where an agent ends early), and an event counts as paid on most steps only where even k physics steps per
paying decision could not make it the rest (paid on more than k times half the live decisions).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any, Callable, Optional, Sequence, TextIO, Union

import numpy as np

from ..compiler import CompiledScenario, registry
from . import published
from .policies import Policy
from .progress import EpisodeBar, bar
from .rollout import Rollout, rollout

AUDIT_POLICIES = ("zeros", "random", "scripted")
TRIVIAL = ("zeros", "random")  # the policies that should not beat the paper's trained PPO
TRAINED = "trained"  # the name of a checkpoint's policy (`hivex audit --checkpoint`)
ACTING = ("random", "scripted")  # under all-zeros actions any action-independent term is the whole return
MATTERS_SHARE = 0.05  # an action-independent term is flagged only if it is at least this share of a return
DOMINANT_SHARE = 0.9
EVENT_MOST_STEPS = 0.5  # an event term paid on more than this fraction of live agent-steps is not an event
PUBLISHED_MARGIN = 0.1
PUBLISHED_MIN = 0.5
SCALE_FACTOR = 10.0
TOLERANCE = 1e-9


@dataclass(frozen=True)
class Flag:
    """One finding: its kind (see the module doc), the term and policy it concerns (if any), and why."""

    kind: str
    message: str
    term: Optional[str] = None
    policy: Optional[str] = None
    note: bool = False  # a finding to read, not a flag (see the module doc)

    def as_dict(self) -> dict[str, Any]:
        return {"kind": self.kind, "term": self.term, "policy": self.policy, "message": self.message}


def spread(values: np.ndarray) -> dict[str, float]:
    """Mean and standard deviation of per-agent episode values, over every agent and episode."""
    return {"mean": float(np.mean(values)), "std": float(np.std(values))}


def compared(statistic: dict[str, float]) -> float:
    """The value of a reported statistic (:meth:`ScenarioAudit.as_dict`) that compares with a published one: a
    running mean's pooled form where it has one (``"pooled"``), else the mean of the per-episode values."""
    return statistic.get("pooled", statistic["mean"])


@dataclass
class ScenarioAudit:
    """What the audit measured and flagged for one compiled scenario."""

    compiled: CompiledScenario
    rollouts: dict[str, Rollout]
    cell: Optional[published.PublishedCell]
    flags: list[Flag] = field(default_factory=list)
    notes: list[Flag] = field(default_factory=list)

    def shares(self, policy: str) -> dict[str, float]:
        """Each active term's mean weighted episode sum over the sum of their sizes (signed; sizes add to 1)."""
        done = self.rollouts[policy]
        means = {name: float(done.weighted(name).mean()) for name in done.terms}
        size = sum(abs(v) for v in means.values())
        return {name: (v / size if size else 0.0) for name, v in means.items()}

    def as_dict(self) -> dict[str, Any]:
        c = self.compiled
        out: dict[str, Any] = {
            "scenario": c.name, "source": c.source, "environment": c.environment, "task": c.task_name,
            "task_index": c.entry.reward_table.tasks[c.task_index].index, "level": c.level,
            "episodes": int(next(iter(self.rollouts.values())).returns.shape[0]), "policies": {},
            "published": None, "flags": [f.as_dict() for f in self.flags],
            "notes": [f.as_dict() for f in self.notes],
        }
        for policy, done in self.rollouts.items():
            shares, pooled = self.shares(policy), done.pooled()
            out["policies"][policy] = {
                "return": spread(done.returns),
                "terms": {name: spread(done.weighted(name)) | {"share": shares[name]} for name in done.terms},
                "statistics": {name: spread(values) | ({"pooled": pooled[name]} if name in pooled else {})
                               for name, values in done.statistics.items()},
            }
        if self.cell is not None:
            out["published"] = {"return": {"mean": self.cell.return_mean, "std": self.cell.return_std},
                                "statistics": {published.short_name(k): {"mean": m, "std": s}
                                               for k, (m, s) in self.cell.statistics.items() if k != published.RETURN}}
        caveat = published.caveat(c)
        if caveat:
            out["caveat"] = caveat
        return out


def audit_scenario(compiled: CompiledScenario, episodes: int = 2, progress=None, label: str = "",
                   trained: Optional[Callable[[CompiledScenario], Policy]] = None) -> ScenarioAudit:
    """Roll every audit policy for ``episodes`` test episodes and check the terms. ``trained`` (optional) makes a
    trained policy for the scenario, rolled too as policy 'trained'; ``progress`` (a bar of
    :func:`hivex_dsl.evaluation.progress.bar`, optional) advances over the decisions played."""
    rollouts = {}
    for name, policy in _policies(compiled, trained).items():
        tracker = None
        if progress is not None:
            progress.set_description(f"audit {label}{compiled.name}: {name}")
            tracker = EpisodeBar(progress, compiled.episode_decisions)
        rollouts[name] = rollout(compiled, policy, episodes, split="test", trace=True, progress=tracker)
    result = ScenarioAudit(compiled, rollouts, published.cell_for(compiled))
    found = find_flags(result)
    result.flags, result.notes = [f for f in found if not f.note], [f for f in found if f.note]
    return result


def _policies(compiled: CompiledScenario, trained) -> dict[str, Union[str, Policy]]:
    """The audit's policies by name: the trivial and scripted ones, then the trained one if given."""
    policies: dict[str, Union[str, Policy]] = {name: name for name in AUDIT_POLICIES}
    if trained is not None:
        policies[TRAINED] = trained(compiled)
    return policies


def find_flags(audit: ScenarioAudit) -> list[Flag]:
    return (_action_independent(audit) + _first_step(audit) + _dominant(audit) + _contracts(audit)
            + _against_published(audit) + _trained_below_zeros(audit))


def _trained_below_zeros(audit: ScenarioAudit) -> list[Flag]:
    """A trained policy (``--checkpoint``) that earns less than doing nothing learned the wrong thing, or too
    little: a reward, or a training, to look at."""
    if TRAINED not in audit.rollouts:
        return []
    ours, zeros = float(audit.rollouts[TRAINED].returns.mean()), float(audit.rollouts["zeros"].returns.mean())
    if ours >= zeros - TOLERANCE * max(1.0, abs(zeros)):
        return []
    return [Flag("below_zeros", policy=TRAINED, message=(
        f"the trained policy earns {ours:.4g} per agent and episode, less than the all-zeros policy ({zeros:.4g}): "
        "it learned to lose reward, or not enough; check the reward's signs and the training's length"))]


def _action_independent(audit: ScenarioAudit) -> list[Flag]:
    flags = []
    runs = [audit.rollouts[p] for p in AUDIT_POLICIES]
    for term in runs[0].terms:
        sums = [run.terms[term] for run in runs]
        if not any(np.any(s != 0) for s in sums):
            continue
        same = all(s.shape == sums[0].shape and np.allclose(s, sums[0], rtol=TOLERANCE, atol=TOLERANCE) for s in sums)
        matters = max(abs(audit.shares(p)[term]) for p in ACTING) >= MATTERS_SHARE
        if same and matters and not _paid_on_endings_the_actions_time(runs, term):
            world = _contracts_of(audit)[term].scope == "global"
            flags.append(Flag("action_independent", term=term, note=world, message=(
                f"{term} pays the same per-episode sums under the all-zeros, random and scripted policies "
                f"(mean {float(sums[0].mean()):.4g}): its value does not depend on the actions"
                + (" (a global-scope term: a property of the world)" if world else ""))))
    return flags


def _paid_on_endings_the_actions_time(runs: list[Rollout], term: str) -> bool:
    """Whether ``term`` paid only on steps that ended the agent's episode, under every policy, and the policies'
    episodes lasted differently long.

    Such a term (a task that ends on its event, such as Aerial Wildfire Suppression's Pick Up Water task) pays
    once per episode under every policy that triggers it, so equal episode sums say nothing: what the actions
    decide is when it is earned, which the episode lengths show.
    """
    only_at_endings = all(term in run.traces and run.traces[term].before_end == 0 for run in runs)
    lengths = [run.lengths for run in runs]
    differ = any(a.shape != lengths[0].shape or not np.array_equal(a, lengths[0]) for a in lengths)
    return only_at_endings and differ


def _first_step(audit: ScenarioAudit) -> list[Flag]:
    flags = []
    contracts, done = _contracts_of(audit), audit.rollouts["zeros"]
    for term, trace in done.traces.items():
        if contracts[term].timing == "dense" or not trace.first_step:
            continue
        first = np.stack(trace.first_step)
        if np.any(first != 0):
            flags.append(Flag("first_step", term=term, policy="zeros", message=(
                f"{term} ({contracts[term].timing}) pays {float(np.abs(first).max()):.4g} on the first "
                "step after reset under the all-zeros policy, before anything happened")))
    return flags


def _dominant(audit: ScenarioAudit) -> list[Flag]:
    """A term paying at least 90% of what the scripted policy earns from the terms that can pay it something.

    Only rewards count (positive weighted sums): a task whose one bonus is the task (Find Fire) has nothing
    to dominate, and penalties dominating a run that earns nothing say nothing about the reward's design.
    """
    done, contracts = audit.rollouts["scripted"], _contracts_of(audit)
    can_pay = [t for t in done.terms if _can_pay(contracts[t], audit.compiled.weights[t])]
    earned = {t: float(done.weighted(t).mean()) for t in can_pay}
    total = sum(v for v in earned.values() if v > 0)
    if len(can_pay) < 2 or total <= 0:
        return []
    return [Flag("dominant", term=term, policy="scripted", message=(
        f"{term} pays {value / total:.0%} of what the scripted policy earns from the {len(can_pay)} terms "
        "that reward it (the others hardly matter)"))
        for term, value in earned.items() if value >= DOMINANT_SHARE * total]


def _contracts_of(audit: ScenarioAudit) -> dict:
    """Every term's contract by name: the environment's and the scenario's expression terms."""
    return {contract.name: contract for contract in audit.compiled.term_contracts}


def _can_pay(contract, weight: float) -> bool:
    """Whether a term with this contract and weight can add to the return."""
    return contract.sign == "mixed" or (contract.sign == "bonus") == (weight > 0)


def _contracts(audit: ScenarioAudit) -> list[Flag]:
    flags = []
    for term in audit.rollouts["zeros"].traces:
        contract = _contracts_of(audit)[term]
        for policy, done in audit.rollouts.items():
            trace = done.traces[term]
            if trace.live == 0:
                continue
            flags += contract_flags(contract, trace, policy, audit.compiled.decision_period)
    return flags


def decision_range(contract, period: int) -> tuple[float, float]:
    """The values a term can pay over one decision of ``period`` physics steps: the sum of 1 to ``period`` values
    of its declared range (an agent may end inside the period)."""
    return min(contract.low, period * contract.low), max(contract.high, period * contract.high)


def contract_flags(contract, trace, policy: str, period: int = 1) -> list[Flag]:
    term, flags = contract.name, []
    low, high = decision_range(contract, period)
    if (contract.sign == "bonus" and trace.low < 0) or (contract.sign == "penalty" and trace.high > 0):
        flags.append(Flag("contract_sign", term=term, policy=policy, message=(
            f"{term} is declared a {contract.sign} but paid values in [{trace.low:.4g}, {trace.high:.4g}]")))
    elif trace.low < low - TOLERANCE or trace.high > high + TOLERANCE:
        allowed = (f"its declared [{low:g}, {high:g}]" if period == 1 else
                   f"[{low:g}, {high:g}], what its declared [{contract.low:g}, {contract.high:g}] allows over {period} steps")
        flags.append(Flag("contract_range", term=term, policy=policy, message=(
            f"{term} paid per-{'step' if period == 1 else 'decision'} values in [{trace.low:.4g}, {trace.high:.4g}] "
            f"outside {allowed}")))
    if contract.timing == "terminal" and trace.before_end:
        flags.append(Flag("contract_timing", term=term, policy=policy, message=(
            f"{term} is terminal but paid on {trace.before_end} agent-steps that did not end an episode")))
    if contract.timing == "event" and trace.nonzero > EVENT_MOST_STEPS * trace.live * period:
        flags.append(Flag("contract_timing", term=term, policy=policy, message=(
            f"{term} is an event but paid on {trace.nonzero / trace.live:.0%} of the agent-steps")))
    return flags


def _against_published(audit: ScenarioAudit) -> list[Flag]:
    cell, flags = audit.cell, []
    if cell is None:
        return flags
    target = cell.return_mean
    for policy, done in audit.rollouts.items():
        ours = float(done.returns.mean())
        if policy in TRIVIAL and target > PUBLISHED_MIN and ours > target + PUBLISHED_MARGIN * abs(target):
            flags.append(Flag("beats_published", policy=policy, message=(
                f"the {policy} policy earns {ours:.4g} per agent and episode, more than the paper's trained PPO "
                f"({target:.4g}): a reward bug until proven otherwise")))
        if policy in TRIVIAL and abs(target) >= PUBLISHED_MIN and abs(ours) > SCALE_FACTOR * abs(target):
            flags.append(Flag("published_scale", policy=policy, message=(
                f"the {policy} policy's return {ours:.4g} is {abs(ours / target):.0f} times the published "
                f"{target:.4g} in size: the reward scale differs from the paper's")))
    return flags


def audit_all(compiled: Sequence[CompiledScenario], episodes: int = 2, stream: Optional[TextIO] = None,
              quiet: bool = False, trained: Optional[Callable[[CompiledScenario], Policy]] = None
              ) -> list[ScenarioAudit]:
    """Audit every scenario (every point of a sweep), with a progress bar on ``stream`` (stderr) where it is a
    terminal and not ``quiet``; ``trained`` as in :func:`audit_scenario`."""
    total = len(compiled)
    policies = len(AUDIT_POLICIES) + (trained is not None)
    decisions = sum(sc.episode_decisions for sc in compiled) * episodes * policies
    label = lambda i: f"[{i + 1}/{total}] " if total > 1 else ""  # noqa: E731
    with bar(decisions, "audit", unit="decision", enabled=not quiet, stream=stream) as shown:
        return [audit_scenario(sc, episodes, shown, label(i), trained) for i, sc in enumerate(compiled)]


def _pm(value: dict[str, float]) -> str:
    return f"{value['mean']:.4g} ± {value['std']:.3g}"


def _table(rows: list[list[str]]) -> list[str]:
    widths = [max(len(row[c]) for row in rows) for c in range(len(rows[0]))]
    return ["  " + "  ".join(cell.ljust(w) if c == 0 else cell.rjust(w) for c, (cell, w) in enumerate(zip(row, widths)))
            for row in rows]


def _ratio(ours: float, theirs: float) -> str:
    return f" ({ours / theirs:.2f}x)" if theirs else ""


def describe(audit: dict[str, Any]) -> str:
    """The text report of one scenario's audit (from :meth:`ScenarioAudit.as_dict`)."""
    entry = registry.environments().get(audit["environment"])
    field = entry.info.level_field if entry else None
    level = "" if audit["level"] is None else f", {(field or 'level').replace('_', ' ')} {audit['level']}"
    lines = [f"{audit['scenario']} ({audit['source']}): {audit['environment']} task {audit['task_index']} "
             f"{audit['task']}{level}; {audit['episodes']} test episode(s) per policy",
             "  per agent and episode: mean ± std over agents and episodes (share of what the terms paid)"]
    runs = audit["policies"]
    if audit.get("checkpoint"):
        lines.append(f"  trained: the policy of {audit['checkpoint']}")
    rows = [["term (weighted)"] + list(runs), ["return"] + [_pm(run["return"]) for run in runs.values()]]
    for term in next(iter(runs.values()))["terms"]:
        rows.append([term] + [f"{_pm(run['terms'][term])} ({run['terms'][term]['share']:+.0%})" for run in runs.values()])
    lines += _table(rows)
    cell = audit["published"]
    if cell is not None:
        theirs = cell["return"]["mean"]
        lines.append(f"  published PPO (test seeds): return {_pm(cell['return'])}")
        rows = [["statistic", "published"] + list(runs),
                ["return", f"{theirs:.4g}"] + [f"{run['return']['mean']:.4g}{_ratio(run['return']['mean'], theirs)}"
                                              for run in runs.values()]]
        for name, value in cell["statistics"].items():
            ours = [run["statistics"].get(name) for run in runs.values()]
            rows.append([name, f"{value['mean']:.4g}"] + ["not computed" if v is None else
                                                         f"{compared(v):.4g}{_ratio(compared(v), value['mean'])}"
                                                         for v in ours])
        lines += _table(rows)
        if any("pooled" in v for run in runs.values() for v in run["statistics"].values()):
            lines.append("  (a running mean shows its pooled form: its added values' mean over every agent-episode)")
    else:
        lines.append(f"  no published result: {audit['caveat']}" if audit.get("caveat") else
                     "  no published result for this environment, task and level")
    flags = audit["flags"]
    lines += [f"  note {f['kind']}: {f['message']}" for f in audit.get("notes", [])]
    lines += [f"  FLAG {f['kind']}: {f['message']}" + (f" [{f['policy']}]" if f["policy"] else "") for f in flags]
    lines.append(f"  {len(flags)} flag(s)")
    return "\n".join(lines)


__all__ = ["AUDIT_POLICIES", "Flag", "ScenarioAudit", "audit_all", "audit_scenario", "compared", "describe", "find_flags",
           "spread"]
