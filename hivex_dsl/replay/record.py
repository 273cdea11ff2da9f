"""One episode recorded decision by decision: every agent's reward split into its weighted terms, its action and
observation, the environment's statistics, the events, and the rendered frames every ``frame_step`` decisions.

The episode is rolled as :func:`hivex_dsl.evaluation.rollout.rollout` rolls one (one world, the split's seeds, the
same policies), through :class:`hivex_dsl.runtime.BatchedEnv`. Two taps watch it without changing it: one stands in
for the reward composer and adds up each term's *weighted* value over a decision's physics steps (with the weight
of each physics step, so a scheduled weight is exact too), the other keeps the simulator's events.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any, Callable, Optional

import numpy as np

from ..compiler import CompiledScenario
from ..runtime.batched import BatchedEnv, Split
from ..sim.spaces import check_actions
from ..evaluation.policies import Policy, decide, make_policy

DEFAULT_SPLIT: Split = "test"  # a replay plays the seeds `hivex evaluate` plays


@dataclass
class Episode:
    """One recorded episode of one world. Per-decision arrays have T rows, one per decision (the policy's step),
    and A columns, one per agent; decision t's observation is what the agent saw before acting, its reward what
    the decision paid (0 once the agent's episode has ended)."""

    compiled: CompiledScenario
    policy: dict[str, Any]  # what played: {"kind": "scripted" | "random" | "zeros" | "checkpoint", ...}
    seed: Optional[int]
    split: str
    terms: dict[str, np.ndarray]  # term -> (T, A) unweighted values
    weighted: dict[str, np.ndarray]  # term -> (T, A) weighted values; they add up to ``reward``
    weights: dict[str, np.ndarray]  # term -> (T,) the weight at the decision's last physics step
    reward: np.ndarray  # (T, A) what the environment returned
    playing: np.ndarray  # (T, A) bool: the agent was in its episode when the decision began
    actions: np.ndarray  # (T, A, K) every action component, flattened (a Dict space's parts in key order)
    observations: np.ndarray  # (T, A, D) the vector observation before the decision (no camera)
    statistics: dict[str, np.ndarray]  # logged name -> (T, A) its value over the episode so far
    events: list[dict[str, Any]] = field(default_factory=list)  # {"decision", "agent" (None: world), "kind", "name"}
    frames: list[Any] = field(default_factory=list)  # renders, (H, W, 3) uint8, or what record's keep_frame made
    frame_decisions: list[int] = field(default_factory=list)  # decisions taken before each frame (0: the start)
    frame_step: int = 1  # a frame every frame_step decisions (and one after the last)
    observation_labels: tuple[str, ...] = ()  # the simulator's names of one stack of the vector observation
    action_meanings: str = ""  # the simulator's description of the action components

    @property
    def decisions(self) -> int:
        return int(self.reward.shape[0])


class _WeightedTap:
    """Stands in for a BatchedEnv's RewardComposer: calls it, and adds each term's weighted value of the physics
    step to ``weighted`` for the agents then playing (the env zeroes the others' pay the same way)."""

    def __init__(self, core: BatchedEnv):
        self.inner, self.core = core.composer, core
        self.weighted: dict[str, np.ndarray] = {}

    def __getattr__(self, name: str) -> Any:
        return getattr(self.inner, name)

    def __call__(self, prev: Any, state: Any, actions: Any, params: Any, shape: tuple[int, int]):
        rewards, values = self.inner(prev, state, actions, params, shape)
        live = self.core.alive
        for name, value in values.items():
            paid = np.where(live, self.inner.paid(name) * value, 0.0)
            self.weighted[name] = self.weighted[name] + paid if name in self.weighted else paid
        return rewards, values

    def take(self) -> dict[str, np.ndarray]:
        taken, self.weighted = self.weighted, {}
        return taken


class _EventTap:
    """Wraps a simulator's ``step`` to keep, OR-ed over a decision's physics steps, the events it reports."""

    def __init__(self, sim: Any):
        self.step = sim.step
        self.seen: dict[str, np.ndarray] = {}
        sim.step = self._step

    def _step(self, state: Any, actions: Any, rng: np.random.Generator):
        state, outcome = self.step(state, actions, rng)
        for name, hit in outcome.events.items():
            self.seen[name] = self.seen[name] | hit if name in self.seen else np.array(hit, bool)
        return state, outcome

    def take(self) -> dict[str, np.ndarray]:
        taken, self.seen = self.seen, {}
        return taken


def flat_per_agent(tree: Any, agents: int) -> np.ndarray:
    """One world's (1, A, ...) array, or a dict of them, as (A, K) float64: a dict's parts in key order."""
    if isinstance(tree, dict):
        return np.concatenate([flat_per_agent(tree[key], agents) for key in sorted(tree)], axis=1)
    return np.asarray(tree, np.float64).reshape(agents, -1)


def vector_part(observations: Any) -> Any:
    """The vector observation of a simulator's observations (a dict's ``vector``; the camera is left out)."""
    return observations["vector"] if isinstance(observations, dict) else observations


def record(compiled: CompiledScenario, policy: str | Policy, policy_info: dict[str, Any], frame_step: int,
           seed: Optional[int] = None, split: Split = DEFAULT_SPLIT, steps: Optional[int] = None,
           progress: Optional[Callable[[int], None]] = None,
           keep_frame: Callable[[np.ndarray], Any] = np.copy) -> Episode:
    """Play one episode of ``compiled`` (up to ``steps`` decisions; the whole episode by default) and record it.

    ``policy`` is 'scripted', 'random', 'zeros' or a batched policy, observations (1, A, ...) -> actions (1, A, ...);
    ``policy_info`` describes it for the page. A frame is rendered at the start, after every ``frame_step``-th
    decision and after the last one, and ``keep_frame`` (an encoder, say) turns it into what ``frames`` keeps.
    ``progress`` is called with 1 after each decision."""
    core = BatchedEnv(compiled, batch=1, split=split)
    weighted_tap = _WeightedTap(core)
    core.composer = weighted_tap
    event_tap = _EventTap(core.sim)
    space, agents = core.sim.action_space, compiled.agents
    act = policy if callable(policy) else make_policy(policy, compiled, space, core.shape,
                                                      seed=0 if seed is None else seed)
    observations = core.reset(seed)
    rows: dict[str, list] = {key: [] for key in ("reward", "playing", "actions", "observations")}
    terms: dict[str, list] = {name: [] for name in core.composer.active}
    paid: dict[str, list] = {name: [] for name in terms}
    weights: dict[str, list] = {name: [] for name in terms}
    statistics: dict[str, list] = {name: [] for name in core.statistics.names}
    episode = Episode(compiled, policy_info, seed, split, {}, {}, {}, np.zeros(0), np.zeros(0), np.zeros(0),
                      np.zeros(0), {}, frames=[keep_frame(core.render(0))], frame_decisions=[0], frame_step=frame_step,
                      observation_labels=tuple(getattr(core.sim, "observation_labels", ())),
                      action_meanings=str(getattr(core.sim, "action_meanings", "") or ""))
    limit = compiled.episode_decisions if steps is None else steps
    decision = 0
    while core.alive.any() and decision < limit:
        rows["playing"].append(core.alive[0].copy())
        rows["observations"].append(flat_per_agent(vector_part(observations), agents))
        actions = check_actions(space, decide(act, observations, core), compiled.agent_names, core.sim.action_meanings)
        result = core.step(actions)
        observations = result.observations
        decision += 1
        rows["reward"].append(result.rewards[0].copy())
        rows["actions"].append(flat_per_agent(actions, agents))
        taken = weighted_tap.take()
        for name in terms:
            terms[name].append(np.array(result.terms[name][0], np.float64))
            paid[name].append(taken[name][0])
            weights[name].append(core.composer.weights.get(name, 0.0))
        for name, value in core.statistic_sums().items():
            statistics[name].append(value[0].copy())
        episode.events += _events(compiled, decision, event_tap.take(), result)
        if decision % frame_step == 0 or not core.alive.any() or decision == limit:
            episode.frames.append(keep_frame(core.render(0)))
            episode.frame_decisions.append(decision)
        if progress is not None:
            progress(1)
    episode.reward, episode.playing = np.array(rows["reward"]), np.array(rows["playing"])
    episode.actions, episode.observations = np.array(rows["actions"]), np.array(rows["observations"])
    episode.terms = {name: np.array(values) for name, values in terms.items()}
    episode.weighted = {name: np.array(values) for name, values in paid.items()}
    episode.weights = {name: np.array(values) for name, values in weights.items()}
    episode.statistics = {name: np.array(values) for name, values in statistics.items()}
    episode.events += _schedule_events(compiled, episode.weights)
    episode.events.sort(key=lambda event: event["decision"])
    return episode


def _schedule_events(compiled: CompiledScenario, weights: dict[str, np.ndarray]) -> list[dict[str, Any]]:
    """Where a scheduled weight starts to move away from its ``from`` and where it reaches its ``to``."""
    found = []
    for name, schedule in compiled.schedules.items():
        values = weights.get(name)
        if values is None or not values.size:
            continue
        moved = np.flatnonzero(values != schedule.start)
        reached = np.flatnonzero(values == schedule.end)
        if moved.size:
            found.append({"decision": int(moved[0]) + 1, "agent": None, "kind": "schedule",
                          "name": f"{name} weight leaves {schedule.start:g}"})
        if reached.size and schedule.end != schedule.start:
            found.append({"decision": int(reached[0]) + 1, "agent": None, "kind": "schedule",
                          "name": f"{name} weight reaches {schedule.end:g}"})
    return found


def _events(compiled: CompiledScenario, decision: int, seen: dict[str, np.ndarray], result: Any
            ) -> list[dict[str, Any]]:
    """The decision's events: the simulator's (a world event once, with agent None), and the agents' endings."""
    world_events = compiled.entry.world_events
    found = []
    for name, hit in seen.items():
        row = hit[0]
        if name in world_events:
            if row.any():
                found.append({"decision": decision, "agent": None, "kind": "event", "name": name})
            continue
        found += [{"decision": decision, "agent": int(a), "kind": "event", "name": name} for a in np.flatnonzero(row)]
    if result.world_terminated[0]:
        found.append({"decision": decision, "agent": None, "kind": "world ended", "name": "world ending"})
    for kind, mask in (("terminated", result.terminated[0]), ("truncated", result.truncated[0] & ~result.terminated[0])):
        found += [{"decision": decision, "agent": int(a), "kind": kind,
                   "name": "ended its episode (a crash or the task's ending)" if kind == "terminated" else
                   "reached the time limit"} for a in np.flatnonzero(mask)]
    return found


__all__ = ["Episode", "flat_per_agent", "record", "vector_part"]
