"""Shared space helpers: readable descriptions and batched action checks that name the culprit."""

from __future__ import annotations

import operator
from typing import Any, Mapping, Sequence

import numpy as np
from gymnasium import spaces

from .errors import ActionError


def describe_space(space: spaces.Space) -> str:
    """A compact, stable description, e.g. ``Box(-1.0, 1.0, (6,), float32)`` or ``Discrete(3)``."""
    if isinstance(space, spaces.Box):
        low, high = np.min(space.low), np.max(space.high)
        return f"Box({float(low)}, {float(high)}, {tuple(space.shape)}, {space.dtype})"
    if isinstance(space, spaces.Discrete):
        return f"Discrete({int(space.n)})" if int(space.start) == 0 else f"Discrete({int(space.n)}, start={int(space.start)})"
    if isinstance(space, spaces.MultiDiscrete):
        return f"MultiDiscrete({space.nvec.tolist()})"
    if isinstance(space, spaces.Dict):
        inner = ", ".join(f"{k}={describe_space(v)}" for k, v in space.spaces.items())
        return f"Dict({inner})"
    return repr(space)


def flat_size(space: spaces.Space) -> int:
    """Number of scalars in one sample (Dict spaces summed over their parts)."""
    if isinstance(space, spaces.Dict):
        return sum(flat_size(s) for s in space.spaces.values())
    if isinstance(space, spaces.Discrete):
        return 1
    return int(np.prod(space.shape))


def placeholder_action(space: spaces.Space) -> np.ndarray:
    """A valid do-nothing-like action of a Box/Discrete/MultiDiscrete space (0 clipped into it)."""
    if isinstance(space, spaces.Box):
        return np.clip(np.zeros(space.shape, space.dtype), space.low, space.high)
    if isinstance(space, (spaces.Discrete, spaces.MultiDiscrete)):
        return np.asarray(space.start, dtype=space.dtype)
    raise TypeError(f"no placeholder action for {describe_space(space)}")


def placeholder_actions(space: spaces.Space) -> Any:
    """:func:`placeholder_action` of the space, or of each part of a Dict space ({part: action}), as
    read-only copies (a caller keeps them for every step)."""
    if isinstance(space, spaces.Dict):
        return {key: placeholder_actions(sub) for key, sub in space.spaces.items()}
    placeholder = np.array(placeholder_action(space))
    placeholder.flags.writeable = False
    return placeholder


def hold_inactive(actions: Any, active: np.ndarray, placeholder: Any) -> Any:
    """Batched actions (batch, agents, ...) with ``placeholder`` (from :func:`placeholder_actions`, computed
    once per space) wherever ``active`` (batch, agents) is false."""
    if isinstance(placeholder, dict):
        return {key: hold_inactive(actions[key], active, sample) for key, sample in placeholder.items()}
    mask = active.reshape(active.shape + (1,) * placeholder.ndim)
    return np.where(mask, actions, placeholder).astype(np.asarray(actions).dtype, copy=False)


def stack_agent_actions(space: spaces.Space, actions: dict[str, Any], agents: Sequence[str]) -> Any:
    """Per-agent actions (PettingZoo style) -> one batched array shaped (1, agents, ...).

    Valid actions cost a set of their types, one ``np.asarray`` and a dtype and shape comparison per
    part; only when those fail (or the types are mixed) does a per-agent pass look for the culprit.
    """
    try:
        values = [actions[a] for a in agents]
    except (KeyError, TypeError):
        values = None
    if values is None or len(actions) != len(agents):  # equal sizes and every agent found: no extra keys
        _raise_not_one_per_agent(actions, agents)
    if isinstance(space, spaces.Dict):
        keys = space.spaces
        try:
            parts = {key: [action[key] for action in values] for key in keys}
            exact = sum(map(len, values)) == len(keys) * len(values)  # every key found, so no extra ones
        except (KeyError, TypeError, IndexError):
            exact = False
        if not exact:
            _raise_not_a_dict_action(values, agents, space)
        stacked = {}
        for key, sub in keys.items():
            try:
                stacked[key] = _stacked(parts[key], sub, agents)
            except ActionError as exc:
                raise _in_part(exc, space, key) from None
        return stacked
    return _stacked(values, space, agents)


def _in_part(exc: ActionError, space: spaces.Dict, key: str) -> ActionError:
    return ActionError(f"{exc} (part '{key}' of {describe_space(space)})")


def _stacked(values: list, space: spaces.Space, agents: Sequence[str]) -> np.ndarray:
    """One part's per-agent values -> a (1, agents, ...) array of numbers shaped as the space says."""
    one_type = set(map(type, values))
    if len(one_type) != 1 or (np.ndarray in one_type and len(set(map(_dtype, values))) != 1):
        # mixed types hide a boolean or a string among numbers once NumPy promotes them: look at each
        message = _first_culprit(space, values, agents, "")
        if message:
            raise ActionError(message)
    try:
        array = np.asarray(values)
    except (ValueError, TypeError):  # ragged
        array = None
    if array is None or array.dtype.kind not in _KINDS or array.shape[1:] != space.shape:
        _raise_culprit(space, values, agents)
    return array[None]


_KINDS = "iuf"  # numbers; booleans, strings and objects are refused (a float for a Discrete space must be integral)
_dtype = operator.attrgetter("dtype")


def _raise_culprit(space: spaces.Space, values: Sequence, agents: Sequence[str], where: str = "") -> None:
    message = _first_culprit(space, values, agents, where)
    raise ActionError(message or f"actions do not fit {describe_space(space)}")


def _first_culprit(space: spaces.Space, values: Sequence, agents: Sequence[str], where: str) -> str | None:
    for agent, value in zip(agents, values):
        why = culprit(space, value)
        if why:
            return f"action for {agent}{where} {why}"
    return None


def culprit(space: spaces.Space, value: Any) -> str | None:
    """Why one agent's ``value`` is not an action of ``space`` (``'is None; expected ...'``), or None."""
    expected = f"expected an action of {describe_space(space)}"
    if value is None:
        return f"is None; {expected}"
    if isinstance(value, (str, bytes)):
        plain = str(value) if isinstance(value, str) else bytes(value)  # np.str_ shown as a str
        return f"is {plain!r} (a string); {expected}"
    if isinstance(value, (bool, np.bool_)):
        return f"is {value} (a boolean); {expected} (a boolean is not read as 0 or 1)"
    try:
        array = np.asarray(value)
    except (ValueError, TypeError):
        return f"is ragged ({_short(value)}); {expected}"
    if isinstance(value, int) and array.dtype.kind == "O":  # beyond 64 bits
        return f"is {_short(value)}, not in {describe_space(space)}"
    if array.dtype.kind not in _KINDS:
        kind = "booleans" if array.dtype.kind == "b" else f"holding {array.dtype.name} values"
        return f"is {_short(value)} ({kind}); {expected}"
    if array.shape != space.shape:
        return f"has shape {array.shape}, but {describe_space(space)} takes shape {space.shape}"
    if np.count_nonzero(_outside_space(space, array[None, None])):
        return f"is {_short(array.tolist())}, not in {describe_space(space)}"
    return None


def _short(value: Any) -> str:
    text = repr(value.tolist() if isinstance(value, np.ndarray) else value)
    return text if len(text) <= 60 else text[:57] + "..."


def _raise_not_one_per_agent(actions: Any, agents: Sequence[str]) -> None:
    if not isinstance(actions, dict):
        raise ActionError(f"actions must be a dict {{agent: action}}, got {type(actions).__name__}")
    missing = [a for a in agents if a not in actions]
    if missing:
        raise ActionError(f"no action for {', '.join(missing)}; every live agent needs one")
    extra = [a for a in actions if a not in agents]
    raise ActionError(f"action for {extra[0]!r}, which is not a live agent; live agents: {', '.join(agents)}")


def _raise_not_a_dict_action(values: list, agents: Sequence[str], space: spaces.Dict) -> None:
    keys = list(space.spaces)
    for agent, action in zip(agents, values):
        if not isinstance(action, Mapping) or any(key not in action for key in keys):
            raise ActionError(f"action for {agent} must be a dict with keys {keys} for {describe_space(space)}, "
                              f"got {_short(action)}")
        extra = [key for key in action if key not in space.spaces]
        if extra:
            raise ActionError(f"action for {agent} has key {extra[0]!r}, which {describe_space(space)} does not have; "
                              f"expected exactly the keys {keys} (an extra key would be ignored)")
    raise ActionError(f"actions do not fit {describe_space(space)}")  # pragma: no cover - some agent is at fault


def check_actions(space: spaces.Space, actions: Any, agent_names: Sequence[str], meanings: str = "") -> Any:
    """Validate batched actions shaped (batch, agents, ...) against one agent's space.

    Returns the actions as arrays of the space's dtype; raises :class:`ActionError` naming the
    first offending agent, its value and the space. Integral floats are accepted for discrete
    spaces (their value is kept); booleans, strings, None and fractional values are refused.
    """
    if isinstance(space, spaces.Dict):
        if not isinstance(actions, dict) or actions.keys() != space.spaces.keys():
            got = list(actions) if isinstance(actions, dict) else type(actions).__name__
            raise ActionError(f"actions must be a dict with exactly the keys {list(space.spaces)} for "
                              f"{describe_space(space)}, got {got}")
        checked = {}
        for key, sub in space.spaces.items():
            try:
                checked[key] = check_actions(sub, actions[key], agent_names, meanings)
            except ActionError as exc:
                raise _in_part(exc, space, key) from None
        return checked
    try:
        array = np.asarray(actions)
    except (ValueError, TypeError):
        raise ActionError(f"actions are ragged; expected an array (batch, {len(agent_names)}) + {space.shape} "
                          f"for {describe_space(space)}") from None
    batch_agents = array.shape[:2]
    if array.ndim != 2 + len(space.shape) or array.shape[2:] != space.shape or batch_agents[1] != len(agent_names):
        raise ActionError(f"actions have shape {array.shape}; expected (batch, {len(agent_names)}) + {space.shape} "
                          f"for {describe_space(space)}")
    if array.dtype.kind not in _KINDS:
        _raise_batched_culprit(space, array, agent_names)
    outside = _outside_space(space, array)
    if np.count_nonzero(outside):  # not .any(): a quarter of the cost on the few values of a step
        reduce_axes = tuple(range(2, outside.ndim))
        b, a = np.argwhere(outside.any(axis=reduce_axes) if reduce_axes else outside)[0]
        where = f" in env {b}" if batch_agents[0] > 1 else ""
        value = array[b, a]
        hint = f" ({meanings})" if meanings else ""
        raise ActionError(f"action for {agent_names[a]}{where} is {value.tolist()!r}, not in {describe_space(space)}{hint}")
    return array.astype(space.dtype, copy=False)


def _raise_batched_culprit(space: spaces.Space, array: np.ndarray, agent_names: Sequence[str]) -> None:
    """Name the first (env, agent) whose value is not a number (in an object, string or boolean array)."""
    for b in range(array.shape[0]):
        where = f" in env {b}" if array.shape[0] > 1 else ""
        message = _first_culprit(space, list(array[b]), agent_names, where)
        if message:
            raise ActionError(message)
    raise ActionError(f"actions have dtype {array.dtype}; {describe_space(space)} takes numbers")


def _outside_space(space: spaces.Space, array: np.ndarray) -> np.ndarray:
    """Bool array shaped like ``array`` (batch, agents, ...): which values lie outside the space."""
    if isinstance(space, (spaces.Discrete, spaces.MultiDiscrete)):
        if array.dtype.kind not in "iu":
            integral = np.isfinite(array) & (array == np.round(array)) if array.dtype.kind == "f" else np.zeros(array.shape, bool)
            if array.dtype.kind != "f" or not integral.all():
                return ~integral
            array = array.astype(np.int64)
        low = space.start
        high = low + (space.n if isinstance(space, spaces.Discrete) else space.nvec)
        return (array < low) | (array >= high)
    if isinstance(space, spaces.Box):
        if array.dtype.kind not in "fiu":
            return np.ones(array.shape, bool)
        return ~np.isfinite(array) | (array < space.low) | (array > space.high)
    raise TypeError(f"unsupported action space {describe_space(space)}")

