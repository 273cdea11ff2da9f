"""The contract an environment fulfils, in one place: what its simulator must and may offer.

An environment is a registry entry (:class:`hivex_dsl.compiler.registry.EnvironmentEntry`, whose fields say what
each part is) and a batched simulator, which this module states as Protocols: :class:`Simulator` is what every
simulator must have, the others what one may add. Shapes: ``B`` worlds stepping in lockstep, ``A`` agents a world
(the scenario's ``agents``), observations and actions of every agent of every world in one array (or a dict of
arrays) with the leading axes ``(B, A)``. A simulator keeps no state of its own between calls: ``reset`` returns
the state (any object: a dataclass of arrays) and ``step`` takes it and returns the next one, so the runtime
(:class:`hivex_dsl.runtime.BatchedEnv`) can hold, copy and restore it. Every random draw comes from the
``np.random.Generator`` it is given, and ``step`` works on whole arrays, never a Python loop over worlds or agents.

The docs page "Adding an environment" (docs/adding_an_environment.md) is generated from this module and walks
through the example environment of the tests (tests/example_env/).
"""

from __future__ import annotations

from typing import Any, Mapping, NamedTuple, Protocol, runtime_checkable

import numpy as np
from gymnasium import spaces


class StepOutcome(NamedTuple):
    """What a simulator reports besides its new state: (batch, agents) bool arrays.

    ``terminated`` ends single agents' episodes (a crash, an empty battery); ``events`` are what
    happened this step, per agent. Whether an event is an agent's own or the whole world's (an event
    the registry lists in its entry's ``world_events``, true for every agent of a world) decides what
    a task's ``ends_on`` naming it ends: the agent's episode, or the world's (see :class:`BatchedEnv`).
    ``world_ended`` (optional, ``(batch,)`` bool) ends the episode of every agent of a world whatever the
    task, the simulator's own world-level ending (see :class:`HoldsEndings`).

    A named tuple rather than a frozen dataclass: it is built every step, and a frozen dataclass's
    ``__init__`` (one ``object.__setattr__`` per field) costs a visible share of a one-world step.
    """

    terminated: np.ndarray
    events: dict[str, np.ndarray]
    world_ended: np.ndarray | None = None



@runtime_checkable
class Simulator(Protocol):
    """The batched simulator every environment has: ``EnvironmentEntry.make_simulator(compiled)`` builds it."""

    @property
    def agents(self) -> int:
        """``A``, the agents of each world (the compiled scenario's ``agents``)."""

    @property
    def observation_space(self) -> spaces.Space:
        """One agent's observation space: a Box of its vector observation, or a Dict with a ``vector`` Box and
        image Boxes ``(H, W, C)`` uint8."""

    @property
    def action_space(self) -> spaces.Space:
        """One agent's action space: Discrete, MultiDiscrete, Box, or the hybrid Dict ``{"continuous": Box(-1, 1,
        (k,)), "discrete": MultiDiscrete}``."""

    @property
    def action_meanings(self) -> str:
        """The actions in words, for error messages and the docs' specification table."""

    @property
    def render_fps(self) -> int:
        """Frames per second of ``render``'s pictures, for ``render_mode="human"`` and videos."""

    @property
    def observation_labels(self) -> tuple[str, ...]:
        """A class attribute: one label per value of the vector observation (``"wind direction x"``, ...), in
        order, under the default params; the docs' specification table groups ``... x``/``... y`` runs and checks
        the count. A simulator whose params change what a value is relabels it on the instance."""

    def reset(self, rng: np.random.Generator, batch: int) -> Any:
        """The state of ``batch`` new worlds (``B = batch``), drawn from ``rng``."""

    def reset_where(self, state: Any, mask: np.ndarray, rng: np.random.Generator) -> Any:
        """``state`` with the worlds of ``mask`` ``(B,)`` bool started afresh (the others unchanged)."""

    def step(self, state: Any, actions: Any, rng: np.random.Generator) -> tuple[Any, StepOutcome]:
        """One physics step of every world: ``actions`` ``(B, A, ...)`` as the action space's arrays (a dict of
        them for a Dict space). Returns the new state and a :class:`~hivex_dsl.runtime.StepOutcome`:
        ``terminated`` ``(B, A)`` bool (agents whose episode the simulator itself ends) and ``events``, name ->
        ``(B, A)`` bool, one per event of the entry's ``events``."""

    def observe(self, state: Any) -> Any:
        """Every agent's observation: ``(B, A, D)`` float32 for a Box, a dict of such arrays for a Dict space."""

    def render(self, state: Any, index: int) -> np.ndarray:
        """A picture of world ``index``: ``(H, W, 3)`` uint8."""

    def state_components(self) -> tuple[Any, ...]:
        """The world facts of the global state no single agent observes: a tuple of
        :class:`~hivex_dsl.runtime.global_state.StateComponent`, named runs of values with their bounds; may be
        empty."""

    def world_state(self, state: Any) -> tuple[np.ndarray, np.ndarray]:
        """``(vectors (B, A, D) float32, world (B, W) float)``: every agent's vector observation and the world
        facts of ``state_components``, ``W`` their total size."""


@runtime_checkable
class Respawns(Protocol):
    """May: agents that end their episode while their world goes on (a crash) start again in it."""

    def respawn_where(self, state: Any, mask: np.ndarray, rng: np.random.Generator) -> Any:
        """``state`` with the agents of ``mask`` ``(B, A)`` bool started afresh in their running worlds (ML-Agents'
        agent reset); their next observation is a first one."""


@runtime_checkable
class HoldsEndings(Protocol):
    """May: agents that finish without ending their episode. An agent meeting one of ``held_events`` (events a
    task's ``ends_on`` names) stops acting but plays on, paid what its world still pays it, until the simulator
    ends its world's episode (``StepOutcome.world_ended``), as ML-Agents agents that a scene freezes until all are
    done (Aerial Wildfire Suppression under ``finished_planes: wait``)."""

    @property
    def held_events(self) -> tuple[str, ...]:
        """The ``ends_on`` events that the runtime does not end an agent's episode on (the simulator holds it)."""


@runtime_checkable
class ReportsStepInfo(Protocol):
    """May: extra per-agent facts of the last step, which the adapters put in ``infos["env"]``."""

    def step_info(self, state: Any) -> Mapping[str, np.ndarray]:
        """name -> ``(B, A)`` array (e.g. WRM's impossible resource moves)."""


@runtime_checkable
class MasksActions(Protocol):
    """May: which choices of the discrete action branches can do anything at this decision, as the original's agents
    wrote them for ML-Agents (``WriteDiscreteActionMask``): a drop with nothing to drop, or where it cannot land. A
    policy that reads the mask never picks a closed choice (``hivex train``'s categorical, as ML-Agents' does); the
    simulator still accepts one and does nothing with it, as the original's scene did. The adapters hand it on as
    ``infos["action_mask"]``."""

    def action_mask(self, state: Any) -> np.ndarray:
        """``(B, A, N)`` bool, ``N`` the discrete branches' sizes summed, branch after branch (ML-Agents' layout):
        true where the choice is open. Every branch keeps at least one open choice."""


@runtime_checkable
class StacksObservations(Protocol):
    """May: a vector observation of several stacked frames."""

    @property
    def observation_stacks(self) -> int:
        """How many copies of ``observation_labels`` the vector observation holds (1 without the attribute)."""

    @property
    def stacked_fields(self) -> tuple[str, ...]:
        """The state fields holding stacked observations, each stacked newest first on its last axis and shifted
        every physics step; at a decision period above 1 the runtime puts the previous decision's newest stacks
        behind each decision's newest, as ML-Agents' stacking sensors hold them (:mod:`hivex_dsl.sim.stacking`)."""


REQUIRED = (Simulator,)
OPTIONAL = (Respawns, HoldsEndings, ReportsStepInfo, MasksActions, StacksObservations)


def members(protocol: type) -> list[tuple[str, str, str]]:
    """``(name, signature, first docstring paragraph)`` of each member a protocol declares, in order."""
    import inspect

    out = []
    for name, value in vars(protocol).items():
        if name.startswith("_"):
            continue
        if isinstance(value, property):
            hints = inspect.signature(value.fget).return_annotation
            out.append((name, f"{name}: {_annotation(hints)}", inspect.getdoc(value) or ""))
        elif inspect.isfunction(value):
            signature = str(inspect.signature(value)).replace("self, ", "").replace("(self)", "()")
            out.append((name, f"{name}{signature}", inspect.getdoc(value) or ""))
    return out


def _annotation(value: Any) -> str:
    return value if isinstance(value, str) else getattr(value, "__name__", str(value))


def missing_members(simulator: Any) -> list[str]:
    """The members of :class:`Simulator` that ``simulator`` lacks (empty when it fulfils the contract)."""
    return [name for name, _, _ in members(Simulator) if not hasattr(simulator, name)]


__all__ = ["StepOutcome", "Simulator", "Respawns", "HoldsEndings", "ReportsStepInfo", "MasksActions",
           "StacksObservations", "REQUIRED", "OPTIONAL", "members", "missing_members"]
