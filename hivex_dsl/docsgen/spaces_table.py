"""The paper-style specification table of an environment, from a simulator built for real."""

from __future__ import annotations

from typing import Any

from gymnasium import spaces

from ..lang.spec.catalogue import EnvironmentInfo
from ..sim.spaces import describe_space, flat_size
from .fields import num

VECTOR_COMPONENT_SUFFIXES = ("x", "y", "z")


def leaves(space: spaces.Space) -> list[spaces.Space]:
    """The non-Dict parts of a space, in key order."""
    if isinstance(space, spaces.Dict):
        return [leaf for sub in space.spaces.values() for leaf in leaves(sub)]
    return [space]


def is_visual(space: spaces.Space) -> bool:
    return isinstance(space, spaces.Box) and len(space.shape) == 3


def label_groups(labels: tuple[str, ...]) -> list[tuple[str, str]]:
    """Consecutive labels "wind direction x", "wind direction y" -> ("Wind direction (2)", "[4] x, [5] y")."""
    groups: list[tuple[str, list[tuple[int, str]]]] = []
    for index, label in enumerate(labels):
        head, _, tail = label.rpartition(" ")
        if not head or tail not in VECTOR_COMPONENT_SUFFIXES:
            head, tail = label, ""
        if groups and groups[-1][0] == head and tail:
            groups[-1][1].append((index, tail))
        else:
            groups.append((head, [(index, tail)]))
    rows = []
    for head, parts in groups:
        title = head[:1].upper() + head[1:]
        value = ", ".join(f"`[{i}]` {tail}".rstrip() for i, tail in parts)
        rows.append((f"{title} ({len(parts)})", value))
    return rows


def specification(info: EnvironmentInfo, compiled: Any, simulator: Any) -> list[dict[str, Any]]:
    """Groups of (parameter, value) rows mirroring the paper's environment specification tables.

    Raises if the simulator's ``observation_labels`` do not name every vector component, so the
    table can never drift from the observation space.
    """
    observation, action = simulator.observation_space, simulator.action_space
    obs_leaves = leaves(observation)
    vector = [s for s in obs_leaves if not is_visual(s)]
    visual = [s for s in obs_leaves if is_visual(s)]
    vector_size = sum(flat_size(s) for s in vector)
    labels = tuple(getattr(type(simulator), "observation_labels", ()))
    stacks = int(getattr(simulator, "observation_stacks", 1))
    if len(labels) * stacks != vector_size:
        raise RuntimeError(
            f"{info.id}: {type(simulator).__name__}.observation_labels names {len(labels)} components x {stacks} "
            f"stacks but the observation space {describe_space(observation)} has {vector_size}; update the labels")
    normalized = all(isinstance(s, spaces.Box) and float(s.low.min()) >= -1.0 and float(s.high.max()) <= 1.0
                     for s in vector)
    general = [
        ("Episode Length", num(compiled.episode_length)),
        ("Agent Count", f"{num(compiled.agents)} (a scenario may set {info.min_agents} to {info.max_agents})"),
        ("Neighbour Count", num(info.neighbour_count)),
    ]
    vector_rows = [("Space", f"`{' + '.join(describe_space(s) for s in vector)}`"), ("Stacks", str(stacks)),
                   ("Normalized", "True" if normalized else "False")] + label_groups(labels)
    visual_rows = [("Space", f"`{describe_space(s)}`") for s in visual] or [("-", "-")]

    act_leaves = leaves(action)
    continuous = [s for s in act_leaves if isinstance(s, spaces.Box)]
    discrete = [s for s in act_leaves if isinstance(s, (spaces.Discrete, spaces.MultiDiscrete))]
    branches = sum(1 if isinstance(s, spaces.Discrete) else len(s.nvec) for s in discrete)
    meanings = getattr(simulator, "action_meanings", "") or "-"
    continuous_rows = [(f"`{describe_space(s)}`", "-") for s in continuous] or [("-", "-")]
    discrete_rows = [(f"`{describe_space(s)}`", meanings) for s in discrete] or [("-", "-")]
    return [
        {"category": "General", "rows": general},
        {"category": f"Vector Observations ({vector_size})", "rows": vector_rows},
        {"category": f"Visual Observations ({len(visual)})", "rows": visual_rows},
        {"category": f"Continuous Actions ({sum(flat_size(s) for s in continuous)})", "rows": continuous_rows},
        {"category": f"Discrete Actions ({branches})", "rows": discrete_rows},
    ]


def global_state_table(compiled: Any, simulator: Any) -> dict[str, Any]:
    """The global state's components (hivex_dsl.runtime.global_state) for the default scenario: its size, and per
    component the indices it takes, whether it repeats per agent, its range and meaning."""
    from ..runtime.global_state import GlobalState

    state = GlobalState(simulator, compiled.agents, compiled.episode_length)
    rows = [{"name": row["name"], "indices": f"{row['first']}" if row["size"] == 1 else f"{row['first']}-{row['last']}",
             "per_agent": f"{row['size'] // compiled.agents} per agent" if row["per_agent"] else "world",
             "range": f"[{num(row['low'])}, {num(row['high'])}]", "description": row["description"]}
            for row in state.component_rows()]
    return {"size": state.size, "agents": compiled.agents, "rows": rows}
