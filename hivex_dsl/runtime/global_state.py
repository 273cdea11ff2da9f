"""The global state of a world, for centralised critics (MAPPO's value function in BenchMARL, TorchRL, EPyMARL).

One flat float32 vector of K values per world, in a Box whose bounds hold for every state (tested), made of
named components in this order:

1. ``agent observations``: every agent's *vector* observation (A, D), agent after agent (agent-major: values
   ``a * D : (a + 1) * D`` are agent ``a``'s), exactly as the agents observe them at this decision.
2. The environment's world facts (its simulator's :meth:`state_components`): what no single agent observes, such
   as the main wind, the fire front, the plastic left or the trees planted. A per-agent component holds A rows of
   ``size`` values, agent-major, as part 1 does; the others ``size`` values of the whole world.
3. ``episode progress``: the world's clock over the episode length (physics steps), in [0, 1].

Images are left out. The cameras of Ocean Plastic Collection (25 x 25 x 2 per vessel), Drone-Based Reforestation
(16 x 16) and Aerial Wildfire Suppression (42 x 42 x 3) would make the state 3,000 to 64,000 values for 12 agents,
nearly all pixels, which an MLP critic (BenchMARL's and EPyMARL's default) takes poorly and which bloats every
rollout buffer; and the pixels are A partial views of what the world facts summarise whole (the fire front, the
plastic left and where it lies). A critic that wants the pixels can read the agents' observations.

Agents out of their episode: an agent whose episode ended *before* this decision (it left PettingZoo's ``agents``)
holds zeros in every per-agent component; on the decision that ends it, its slot still holds its last observation
(the state a truncated episode bootstraps from). A respawned agent (``respawn=True``, the vector env) holds its new
first observation, the one the adapter returned.

The state is that of the decision: computed on demand from the world after the last ``reset`` or ``step`` (its
``decision_period`` physics steps all taken), as the observations are. Each simulator offers two methods:
``state_components() -> tuple[StateComponent, ...]`` (its world facts, part 2) and ``world_state(state) ->
(vectors (B, A, D) float32, world (B, W) float)``, the agents' vector observations and the world facts, W the
components' total size; :class:`GlobalState` puts them together for any environment.
"""

from __future__ import annotations

from dataclasses import dataclass
from itertools import accumulate
from typing import TYPE_CHECKING

import numpy as np
from gymnasium import spaces

from ..base.errors import ResetNeeded

if TYPE_CHECKING:
    from .batched import BatchedEnv

AGENT_OBSERVATIONS = "agent observations"
EPISODE_PROGRESS = "episode progress"


@dataclass(frozen=True)
class StateComponent:
    """A named run of ``size`` values of the global state (``size`` per agent when ``per_agent``), each in
    [``low``, ``high``]."""

    name: str
    size: int
    low: float
    high: float
    description: str
    per_agent: bool = False

    def width(self, agents: int) -> int:
        """Values the component takes in the state of a world of ``agents`` agents."""
        return self.size * agents if self.per_agent else self.size


def vector_space(space: spaces.Space) -> spaces.Box:
    """The vector part of an observation space: the ``vector`` Box of a Dict observation, else the space."""
    return space["vector"] if isinstance(space, spaces.Dict) else space


class GlobalState:
    """The global state of the worlds of a :class:`~hivex_dsl.runtime.BatchedEnv` (see the module).

    ``components`` lists every component in state order, ``space`` is the Box of one world's state (K,), and
    calling it with the env gives the (B, K) float32 states of its B worlds.
    """

    def __init__(self, sim, agents: int, episode_length: int):
        """The state of worlds of ``agents`` agents of the simulator ``sim``, episodes of ``episode_length``
        physics steps."""
        vector = vector_space(sim.observation_space)
        if len(vector.shape) != 1:
            raise ValueError(f"{type(sim).__name__}: the vector observation {vector} is not one-dimensional")
        self.components: tuple[StateComponent, ...] = (
            StateComponent(AGENT_OBSERVATIONS, vector.shape[0], min(0.0, float(vector.low.min())),
                           max(0.0, float(vector.high.max())),
                           "Every agent's vector observation, as it observes it (images left out).", per_agent=True),
            *sim.state_components(),
            StateComponent(EPISODE_PROGRESS, 1, 0.0, 1.0, "The world's clock over the episode length (physics steps)."),
        )
        widths = [c.width(agents) for c in self.components]
        low = np.concatenate([np.full(w, c.low) for c, w in zip(self.components, widths)]).astype(np.float32)
        high = np.concatenate([np.full(w, c.high) for c, w in zip(self.components, widths)]).astype(np.float32)
        vector_width = widths[0]  # the agents' part takes their vector's own bounds, widened to hold 0 (see above)
        low[:vector_width] = np.minimum(np.tile(vector.low, agents), 0.0)
        high[:vector_width] = np.maximum(np.tile(vector.high, agents), 0.0)
        self.space = spaces.Box(low, high, dtype=np.float32)
        self.size = int(sum(widths))
        self.agents = agents
        self.episode_length = float(episode_length)
        self.vector_size = vector_width
        # owner[k]: the agent whose value column k is, or ``agents`` for a value of the whole world
        owner = [np.repeat(np.arange(agents), c.size) if c.per_agent else np.full(c.size, agents)
                 for c in self.components]
        self.owner = np.concatenate(owner)
        starts = list(accumulate(widths, initial=0))
        self.slices = {c.name: slice(start, start + w) for c, start, w in zip(self.components, starts, widths)}

    @classmethod
    def of(cls, core: "BatchedEnv") -> "GlobalState":
        """The global state of the worlds of ``core``."""
        return cls(core.sim, core.agents, core.compiled.episode_length)

    def __call__(self, core: "BatchedEnv") -> np.ndarray:
        """(B, K) float32: the state of every world of ``core`` at its last decision."""
        if core.state is None:
            raise ResetNeeded("call reset() before state(): the environment has not been reset yet")
        vectors, world = core.sim.world_state(core.state)
        batch = len(vectors)
        out = np.empty((batch, self.size), np.float32)
        out[:, :self.vector_size] = vectors.reshape(batch, self.vector_size)
        out[:, self.vector_size:-1] = world
        out[:, -1] = np.minimum(core.clock / self.episode_length, 1.0)
        shown = core.alive | core.ended_last  # (B, A): playing, or ended on the last decision
        if not shown.all():
            keep = np.concatenate([shown, np.ones((batch, 1), bool)], axis=1)[:, self.owner]  # (B, K)
            out[~keep] = 0.0
        return out

    def component_rows(self) -> list[dict]:
        """One row per component (name, first and last index, size, bounds, per agent, description) for the docs."""
        rows = []
        for c in self.components:
            where = self.slices[c.name]
            rows.append({"name": c.name, "first": where.start, "last": where.stop - 1, "size": where.stop - where.start,
                         "low": c.low, "high": c.high, "per_agent": c.per_agent, "description": c.description})
        return rows
