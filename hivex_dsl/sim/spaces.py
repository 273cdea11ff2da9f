"""Shared space helpers: readable descriptions and batched action checks that name the culprit."""

from __future__ import annotations

import operator
from typing import Any, Callable, Mapping, Sequence

import numpy as np
from gymnasium import spaces

from ..base.errors import ActionError
from .action_arrays import NUMBER_KINDS, Unreadable, as_array, holds_a_boolean, short


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


def toggle_mask(open_: np.ndarray) -> np.ndarray:
    """The action mask (B, A, 2) bool of one two-choice branch {0 do nothing, 1 act} from where acting is open
    (B, A) bool: doing nothing is always open (see :class:`hivex_dsl.runtime.contract.MasksActions`)."""
    return np.stack([np.ones_like(open_, dtype=bool), open_.astype(bool, copy=False)], axis=-1)


def sampling_mask(space: spaces.Space, row: np.ndarray) -> Any:
    """One agent's action mask row (N,) int8 over the discrete branches (branch after branch) -> the mask
    ``space.sample(mask=...)`` takes, as PettingZoo's ``infos[agent]["action_mask"]`` holds it: the row for a
    Discrete space, a tuple of per-branch rows for a MultiDiscrete one, ``{"continuous": None, "discrete": ...}``
    for the hybrid Dict (rows are views of ``row``)."""
    if isinstance(space, spaces.Dict):
        return {key: sampling_mask(sub, row) if isinstance(sub, (spaces.Discrete, spaces.MultiDiscrete)) else None
                for key, sub in space.spaces.items()}
    if isinstance(space, spaces.MultiDiscrete):
        return tuple(np.split(row, np.cumsum(space.nvec)[:-1]))
    return row


def mask_row(mask: Any) -> np.ndarray:
    """:func:`sampling_mask`'s structure back to the row (N,) int8 it was made from."""
    if isinstance(mask, Mapping):
        return mask_row(next(part for part in mask.values() if part is not None))
    if isinstance(mask, tuple):
        return np.concatenate(mask).astype(np.int8, copy=False)
    return np.asarray(mask, np.int8)


def stack_agent_actions(space: spaces.Space, actions: Any, agents: Sequence[str], meanings: str = "") -> Any:
    """Per-agent actions (PettingZoo style) {agent: action} -> one checked array shaped (1, agents) +
    space.shape of the space's dtype, or {part: such an array} for a Dict space.

    Valid actions cost one :func:`~hivex_dsl.sim.action_arrays.as_array` and a dtype and shape comparison
    per part, then :func:`check_actions`' vectorised range check (``meanings`` is its hint); only when
    those fail does a per-agent pass look for the culprit, named in the :class:`ActionError`.
    """
    if not isinstance(actions, Mapping):
        raise ActionError(f"actions must be a dict {{agent: action}}, got {type(actions).__name__}")
    try:
        values = list(map(actions.__getitem__, agents))
    except KeyError:
        values = None
    if values is None or len(actions) != len(agents):  # equal sizes and every agent found: no extra keys
        _raise_not_one_per_agent(actions, agents)
    if isinstance(space, spaces.Dict):
        return check_actions(space, _stacked_parts(space, values, agents), agents, meanings)
    return check_actions(space, _stacked(values, space, agents), agents, meanings)


def _stacked_parts(space: spaces.Dict, values: list, agents: Sequence[str]) -> dict[str, np.ndarray]:
    """Per-agent {part: action} dicts -> {part: (1, agents) + part shape array}."""
    keys = space.spaces
    if not all(issubclass(kind, Mapping) for kind in set(map(type, values))):
        _raise_not_a_dict_action(values, agents, space)
    try:
        parts = {key: list(map(operator.itemgetter(key), values)) for key in keys}
    except KeyError:
        parts = None
    if parts is None or sum(map(len, values)) != len(keys) * len(values):  # every key found, so no extra ones
        _raise_not_a_dict_action(values, agents, space)
    stacked = {}
    for key, sub in keys.items():
        try:
            stacked[key] = _stacked(parts[key], sub, agents)
        except ActionError as exc:
            raise _in_part(exc, space, key) from None
    return stacked


def _in_part(exc: ActionError, space: spaces.Dict, key: str) -> ActionError:
    return ActionError(f"{exc} (part '{key}' of {describe_space(space)})")


def _stacked(values: list, space: spaces.Space, agents: Sequence[str]) -> np.ndarray:
    """One part's per-agent values -> a (1, agents) + space.shape array of numbers."""
    try:
        array = as_array(values)
    except Unreadable:
        array = None
    if array is None or array.dtype.kind not in NUMBER_KINDS or array.shape[1:] != space.shape:
        array = _stacked_one_by_one(space, values, agents)
    return array[None]


def _stacked_one_by_one(space: spaces.Space, values: Sequence, names: Sequence[str]) -> np.ndarray:
    """(len(values),) + space.shape numbers from values read one by one, for when NumPy cannot read them
    together (a foreign array-like among plain numbers); raises an ActionError naming the first culprit."""
    message = _first_culprit(space, values, names)
    if message:
        raise ActionError(message)
    return np.stack([as_array(value) for value in values])


def _first_culprit(space: spaces.Space, values: Sequence, names: Sequence[str]) -> str | None:
    """'action for <name> <why>' of the first value that is not an action of ``space``, or None."""
    for name, value in zip(names, values):
        why = culprit(space, value)
        if why:
            return f"action for {name} {why}"
    return None


def culprit(space: spaces.Space, value: Any) -> str | None:
    """Why one agent's ``value`` is not an action of ``space`` (``'is None; expected ...'``), or None."""
    expected = f"expected an action of {describe_space(space)}"
    if isinstance(value, np.ndarray) and value.dtype.kind == "O":  # judge what it holds, item by item
        value = value.tolist()
    if value is None:
        return f"is None; {expected}"
    if isinstance(value, (str, bytes)):
        plain = str(value) if isinstance(value, str) else bytes(value)  # np.str_ shown as a str
        return f"is {plain!r} (a string); {expected}"
    if isinstance(value, (bool, np.bool_)):
        return f"is {value} (a boolean); {expected}{_NOT_A_NUMBER}"
    try:
        array = as_array(value)
    except Unreadable as exc:
        return f"is {exc}; {expected}"
    if isinstance(value, int) and array.dtype.kind == "O":  # beyond 64 bits
        return f"is {short(value)}, not in {describe_space(space)}"
    if array.dtype.kind not in NUMBER_KINDS:
        holds, note = _not_numbers(array)
        return f"is {short(value)} ({holds}); {expected}{note}"
    if array.shape != space.shape:
        return f"has shape {array.shape}, but {describe_space(space)} takes shape {space.shape}"
    if np.count_nonzero(_outside_space(space, array[None, None])):
        return f"is {short(array.tolist())}, not in {describe_space(space)}"
    return None


_NOT_A_NUMBER = " (a boolean is not read as 0 or 1)"


def _not_numbers(array: np.ndarray) -> tuple[str, str]:
    """What an array that is not numbers holds ('booleans', 'holding a boolean', 'holding str320 values'),
    and the note for booleans, alone or hidden among numbers (an object array from a list like [True, 0])."""
    if array.dtype.kind == "b":
        return "booleans", _NOT_A_NUMBER
    if array.dtype.kind == "O" and holds_a_boolean(array.tolist()):
        return "holding a boolean", _NOT_A_NUMBER
    return f"holding {array.dtype.name} values", ""


def _raise_not_one_per_agent(actions: Mapping, agents: Sequence[str]) -> None:
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
                              f"got {short(action)}")
        extra = [key for key in action if key not in space.spaces]
        if extra:
            raise ActionError(f"action for {agent} has key {extra[0]!r}, which {describe_space(space)} does not have; "
                              f"expected exactly the keys {keys} (an extra key would be ignored)")
    raise ActionError(f"actions do not fit {describe_space(space)}")  # pragma: no cover - some agent is at fault


def _per_part(space: spaces.Dict, actions: Any, check: Callable[..., Any], *args: Any) -> dict[str, Any]:
    """``check(part space, actions[part], *args)`` for every part of a Dict space; the actions must be a
    dict with exactly its keys, and an error names the part."""
    if not isinstance(actions, Mapping) or actions.keys() != space.spaces.keys():
        got = list(actions) if isinstance(actions, Mapping) else type(actions).__name__
        raise ActionError(f"actions must be a dict with exactly the keys {list(space.spaces)} for "
                          f"{describe_space(space)}, got {got}")
    checked = {}
    for key, sub in space.spaces.items():
        try:
            checked[key] = check(sub, actions[key], *args)
        except ActionError as exc:
            raise _in_part(exc, space, key) from None
    return checked


def check_slot_actions(space: spaces.Space, actions: Any, shape: tuple[int, int], agent_names: Sequence[str],
                       meanings: str = "") -> Any:
    """Validate a vector env's actions: (slots, ...) with slot = world * agents + agent, where ``shape`` is
    (worlds, agents); or, for a Dict space, a dict of such arrays.

    Returns :func:`check_actions`' (worlds, agents) + space.shape arrays of the space's dtype. Anything
    that is not such actions raises :class:`ActionError` naming the space and, where one slot is at
    fault, its agent (and world, when there are several).
    """
    if isinstance(space, spaces.Dict):
        return _per_part(space, actions, check_slot_actions, shape, agent_names, meanings)
    try:
        array, unreadable = as_array(actions), None
    except Unreadable as exc:
        array, unreadable = None, exc
    if (array is None or array.dtype.kind not in NUMBER_KINDS) and _one_per_slot(actions, shape):
        # judge the list's items, not NumPy's promotion of them ([0, 'a'] -> strings)
        array = _stacked_one_by_one(space, actions, _slot_names(shape, agent_names))
    if array is None:
        raise ActionError(f"actions are {unreadable}; {_expected_slots(space, shape)}")
    if array.shape[:1] != (shape[0] * shape[1],):
        got = f"; got {short(actions)} ({type(actions).__name__})" if array.ndim == 0 else ""
        raise ActionError(f"actions have leading size {array.shape[:1]}; {_expected_slots(space, shape)}{got}")
    return check_actions(space, array.reshape(shape + array.shape[1:]), agent_names, meanings)


def _expected_slots(space: spaces.Space, shape: tuple[int, int]) -> str:
    worlds, agents = shape
    return (f"expected {worlds * agents} slots ({worlds} worlds x {agents} agents), each an action of "
            f"{describe_space(space)}")


def _one_per_slot(actions: Any, shape: tuple[int, int]) -> bool:
    """Whether ``actions`` is a list or tuple of one item per slot."""
    return type(actions) in (list, tuple) and len(actions) == shape[0] * shape[1]


def _slot_names(shape: tuple[int, int], agent_names: Sequence[str]) -> list[str]:
    """Each slot's name in messages: its agent, and its world ('turbine_1 in env 2') when there are several."""
    worlds, agents = shape
    if worlds == 1:
        return list(agent_names)
    return [f"{agent_names[s % agents]} in env {s // agents}" for s in range(worlds * agents)]


def check_actions(space: spaces.Space, actions: Any, agent_names: Sequence[str], meanings: str = "") -> Any:
    """Validate batched actions shaped (batch, agents) + space.shape against one agent's space.

    Returns the actions as arrays of the space's dtype; raises :class:`ActionError` naming the
    first offending agent, its value and the space. Integral floats are accepted for discrete
    spaces (their value is kept); booleans, strings, None, fractional and non-finite values are refused,
    and so is anything NumPy cannot read (a torch tensor that requires grad: call ``.detach()``).
    """
    if isinstance(space, spaces.Dict):
        return _per_part(space, actions, check_actions, agent_names, meanings)
    try:
        array = as_array(actions)
    except Unreadable as exc:
        raise ActionError(f"actions are {exc}; expected an array (batch, {len(agent_names)}) + {space.shape} "
                          f"for {describe_space(space)}") from None
    batch_agents = array.shape[:2]
    if array.ndim != 2 + len(space.shape) or array.shape[2:] != space.shape or batch_agents[1] != len(agent_names):
        raise ActionError(f"actions have shape {array.shape}; expected (batch, {len(agent_names)}) + {space.shape} "
                          f"for {describe_space(space)}")
    if array.dtype.kind not in NUMBER_KINDS:
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
        names = [f"{a} in env {b}" for a in agent_names] if array.shape[0] > 1 else agent_names
        message = _first_culprit(space, list(array[b]), names)
        if message:
            raise ActionError(message)
    raise ActionError(f"actions have dtype {array.dtype}; {describe_space(space)} takes numbers")


def _outside_space(space: spaces.Space, array: np.ndarray) -> np.ndarray:
    """Bool array shaped like ``array`` (batch, agents, ...) of numbers: which values lie outside the space
    (for a discrete space: also every fractional, NaN or infinite value)."""
    if isinstance(space, (spaces.Discrete, spaces.MultiDiscrete)):
        low = space.start
        high = low + (space.n if isinstance(space, spaces.Discrete) else space.nvec)
        outside = (array < low) | (array >= high)
        if array.dtype.kind == "f":  # compared as floats: no cast of NaN or 1e300 to an integer
            outside |= ~np.isfinite(array) | (array != np.floor(array))
        return outside
    if isinstance(space, spaces.Box):
        return ~np.isfinite(array) | (array < space.low) | (array > space.high)
    raise TypeError(f"unsupported action space {describe_space(space)}")
