"""Actions for the action fuzzer (test_action_fuzz.py), each valid or invalid by construction.

A *leaf* space is a Box, Discrete or MultiDiscrete space (a hybrid Dict space's parts are leaves).
Every draw takes a seeded ``np.random.Generator``; ``torch`` is the torch module, or None to draw no
tensors.
"""

from __future__ import annotations

import dataclasses
from typing import Any, Callable, Optional

import numpy as np
from gymnasium import spaces


@dataclasses.dataclass
class Case:
    """Actions for one step; an invalid case's ActionError must name ``culprit`` ('drone_1' or 'drone_1 in env
    1', unless None) and, when ``names_space``, the agent's action space."""

    label: str
    actions: Any
    valid: bool
    culprit: Optional[str] = None
    names_space: bool = True


class ArrayLike:
    """A foreign array NumPy reads through ``__array__``, as it reads a JAX array or a CPU tensor."""

    def __init__(self, array: np.ndarray):
        self.array = array

    def __array__(self, dtype=None, copy=None) -> np.ndarray:
        return np.asarray(self.array, dtype)


class FailingArray:
    """An object whose conversion raises something that is neither a ValueError nor a TypeError."""

    def __array__(self, dtype=None, copy=None) -> np.ndarray:
        raise IndexError("this array cannot be read")

    def __repr__(self) -> str:
        return "FailingArray()"


# --- one agent's action of a leaf space ----------------------------------------------------------------

def valid_numbers(space: spaces.Space, rng: np.random.Generator) -> np.ndarray:
    """A random action of a leaf space as an array of the space's dtype and shape."""
    if isinstance(space, spaces.Box):
        return rng.uniform(space.low, space.high).astype(space.dtype).reshape(space.shape)
    if isinstance(space, spaces.Discrete):
        return np.asarray(space.start + rng.integers(space.n), space.dtype)
    return (space.start + rng.integers(0, space.nvec)).astype(space.dtype)


def _is_discrete(space: spaces.Space) -> bool:
    return isinstance(space, (spaces.Discrete, spaces.MultiDiscrete))


def _small_integers(space: spaces.Space, array: np.ndarray, rng: np.random.Generator) -> Any:
    if _is_discrete(space):
        return array.astype(rng.choice([np.int8, np.uint8, np.int32, np.uint16]))
    low, high = np.ceil(space.low).astype(np.int64), np.floor(space.high).astype(np.int64)
    return rng.integers(low, high + 1).reshape(space.shape) if np.all(low <= high) else None  # ints in the box


# name -> (space, valid array, rng, torch) -> a valid action in that form, or None where the form does not apply
VALID_FORMS: dict[str, Callable[..., Any]] = {
    "array": lambda space, a, rng, torch: a,
    "python": lambda space, a, rng, torch: a.tolist(),
    "float64": lambda space, a, rng, torch: a.astype(np.float64),  # integral floats for a discrete space
    "small integers": lambda space, a, rng, torch: _small_integers(space, a, rng),
    "numpy scalar": lambda space, a, rng, torch: a[()] if a.ndim == 0 else None,
    "tuple": lambda space, a, rng, torch: tuple(a.tolist()) if a.ndim == 1 else None,
    "array-like": lambda space, a, rng, torch: ArrayLike(a),
    "tensor": lambda space, a, rng, torch: None if torch is None else torch.as_tensor(a),
}


def valid_leaf(space: spaces.Space, rng: np.random.Generator, torch: Any) -> tuple[str, Any]:
    array = valid_numbers(space, rng)
    while True:
        name = str(rng.choice(list(VALID_FORMS)))
        value = VALID_FORMS[name](space, array, rng, torch)
        if value is not None:
            return name, value


def _one_replaced(array: np.ndarray, rng: np.random.Generator, value: Any) -> np.ndarray:
    """A float64 copy of ``array`` with one element (chosen by ``rng``) set to ``value``."""
    out = array.astype(np.float64).reshape(-1)
    out[rng.integers(out.size)] = value
    return out.reshape(array.shape)


def _out_of_range(space: spaces.Space, array: np.ndarray, rng: np.random.Generator) -> np.ndarray:
    flat = array.astype(np.float64).reshape(-1)
    i = rng.integers(flat.size)
    if isinstance(space, spaces.Box):
        low, high = (np.broadcast_to(bound, space.shape).reshape(-1) for bound in (space.low, space.high))
        flat[i] = high[i] + 0.5 + rng.integers(3) if rng.random() < 0.5 else low[i] - 0.5 - rng.integers(3)
    else:
        nvec = np.broadcast_to(space.n if isinstance(space, spaces.Discrete) else space.nvec, space.shape).reshape(-1)
        start = np.broadcast_to(space.start, space.shape).reshape(-1)
        flat[i] = start[i] + nvec[i] + rng.integers(3) if rng.random() < 0.5 else start[i] - 1 - rng.integers(3)
    values = flat.reshape(array.shape)
    return values.astype(np.int64) if _is_discrete(space) and rng.random() < 0.5 else values


def _hidden_bool(array: np.ndarray, rng: np.random.Generator) -> Any:
    if array.ndim == 0:
        return None
    values = array.tolist()
    values[rng.integers(len(values))] = bool(rng.integers(2))
    return values


def _wrong_shape(array: np.ndarray, rng: np.random.Generator) -> Any:
    flat = array.reshape(-1)
    shapes = [array[None], np.append(flat, flat[:1]), flat[:-1] if array.ndim else flat[None]]
    if array.ndim:
        shapes.append(flat[0])  # a scalar where a vector belongs
    return shapes[rng.integers(len(shapes))]


def _string(array: np.ndarray, rng: np.random.Generator) -> Any:
    return [str(rng.integers(3)), np.str_("0"), array.astype(str), array.astype(str).tolist()][rng.integers(4)]


def _object_array(array: np.ndarray, rng: np.random.Generator) -> np.ndarray:
    out = array.astype(object).reshape(-1)
    out[rng.integers(out.size)] = None
    return out.reshape(array.shape)


def _big_int(array: np.ndarray, rng: np.random.Generator) -> Any:
    if array.ndim == 0:
        return 2 ** 70
    values = array.astype(np.int64).tolist()
    values[rng.integers(len(values))] = -(2 ** 70)
    return values


def _tensor(torch: Any, make: Callable[[], Any]) -> Any:
    return None if torch is None else make()


# name -> (space, valid array, rng, torch) -> an invalid action, or None where the kind does not apply
BAD_LEAVES: dict[str, Callable[..., Any]] = {
    "nan": lambda space, a, rng, torch: _one_replaced(a, rng, np.nan),
    "inf": lambda space, a, rng, torch: _one_replaced(a, rng, [np.inf, -np.inf][rng.integers(2)]),
    "out of range": lambda space, a, rng, torch: _out_of_range(space, a, rng),
    "fraction": lambda space, a, rng, torch: _one_replaced(a, rng, 0.5 + rng.integers(2)) if _is_discrete(space)
    else None,
    "python bool": lambda space, a, rng, torch: bool(rng.integers(2)),
    "hidden bool": lambda space, a, rng, torch: _hidden_bool(a, rng),
    "bool array": lambda space, a, rng, torch: np.zeros(a.shape, bool) if a.ndim else np.bool_(True),
    "string": lambda space, a, rng, torch: _string(a, rng),
    "bytes": lambda space, a, rng, torch: b"1",
    "None": lambda space, a, rng, torch: None,
    "dict": lambda space, a, rng, torch: {"value": a},
    "set": lambda space, a, rng, torch: {1},
    "object": lambda space, a, rng, torch: object(),
    "object array": lambda space, a, rng, torch: _object_array(a, rng),
    "complex": lambda space, a, rng, torch: a + 1j,
    "big int": lambda space, a, rng, torch: _big_int(a, rng),
    "datetime": lambda space, a, rng, torch: np.full(a.shape, np.datetime64("2020-01-01")),
    "wrong shape": lambda space, a, rng, torch: _wrong_shape(a, rng),
    "ragged": lambda space, a, rng, torch: [a.tolist(), [0, [1]]],
    "empty list": lambda space, a, rng, torch: [],
    "failing __array__": lambda space, a, rng, torch: FailingArray(),
    "grad tensor": lambda space, a, rng, torch: _tensor(torch, lambda: torch.tensor(a.astype(np.float32),
                                                                                    requires_grad=True)),
    "meta tensor": lambda space, a, rng, torch: _tensor(torch, lambda: torch.zeros(a.shape, device="meta")),
    "bool tensor": lambda space, a, rng, torch: _tensor(torch, lambda: torch.zeros(a.shape, dtype=torch.bool)),
    "nan tensor": lambda space, a, rng, torch: _tensor(torch, lambda: torch.as_tensor(_one_replaced(a, rng, np.nan))),
}


def bad_leaf(space: spaces.Space, rng: np.random.Generator, torch: Any) -> tuple[str, Any]:
    array = valid_numbers(space, rng)
    while True:
        name = str(rng.choice(list(BAD_LEAVES)))
        value = BAD_LEAVES[name](space, array, rng, torch)
        if value is not None or name == "None":
            return name, value


# --- one agent's action of any space (a hybrid Dict space: {part: leaf}) -----------------------------------

def valid_action(space: spaces.Space, rng: np.random.Generator, torch: Any) -> Any:
    if isinstance(space, spaces.Dict):
        keys = list(space.spaces)[::-1] if rng.random() < 0.5 else list(space.spaces)  # key order is free
        return {key: valid_leaf(space[key], rng, torch)[1] for key in keys}
    return valid_leaf(space, rng, torch)[1]


def bad_action(space: spaces.Space, rng: np.random.Generator, torch: Any) -> tuple[str, Any]:
    if not isinstance(space, spaces.Dict):
        return bad_leaf(space, rng, torch)
    action = valid_action(space, rng, torch)
    key = str(rng.choice(list(space.spaces)))
    kind = rng.integers(4)
    if kind == 0:
        return "missing key", {k: v for k, v in action.items() if k != key}
    if kind == 1:
        return "extra key", {**action, "speed": 1.0}
    if kind == 2:
        label, value = bad_leaf(space[key], rng, torch)
        return f"part {key}: {label}", {**action, key: value}
    return "not a dict", [np.zeros(3), None, list(action.values())][rng.integers(3)]


# --- a step's actions ----------------------------------------------------------------------------------

def parallel_case(space: spaces.Space, agents: list[str], rng: np.random.Generator, torch: Any) -> Case:
    """{agent: action} for the live ``agents``: valid, one agent's action bad, or the dict itself wrong."""
    actions = {a: valid_action(space, rng, torch) for a in agents}
    roll = rng.random()
    if roll < 0.3:
        return Case("valid", actions, True)
    if roll < 0.8:
        agent = agents[rng.integers(len(agents))]
        label, actions[agent] = bad_action(space, rng, torch)
        return Case(label, actions, False, culprit=agent)
    kind = rng.integers(3)
    if kind == 0:
        del actions[agents[rng.integers(len(agents))]]
        return Case("missing agent", actions, False, names_space=False)
    if kind == 1:
        return Case("extra agent", {**actions, "intruder_0": actions[agents[0]]}, False, names_space=False)
    garbage = [list(actions.values()), None, np.zeros(len(agents)), "actions"][rng.integers(4)]
    return Case("not a dict", garbage, False, names_space=False)


def slot_name(slot: int, shape: tuple[int, int], names: list[str]) -> str:
    worlds, agents = shape
    return f"{names[slot % agents]} in env {slot // agents}" if worlds > 1 else names[slot]


def valid_batch(space: spaces.Space, slots: int, rng: np.random.Generator, torch: Any) -> Any:
    """(slots, ...) valid actions of a leaf space: an array, a tensor, or a list or tuple of any valid forms."""
    kind = rng.integers(4)
    if kind == 0:
        return np.stack([valid_numbers(space, rng) for _ in range(slots)])
    if kind == 1 and torch is not None:
        return torch.as_tensor(np.stack([valid_numbers(space, rng) for _ in range(slots)]))
    items = [valid_leaf(space, rng, torch)[1] for _ in range(slots)]
    return tuple(items) if kind == 2 else items


def bad_batch(space: spaces.Space, shape: tuple[int, int], names: list[str], rng: np.random.Generator,
              torch: Any) -> tuple[str, Any, Optional[str]]:
    """(label, invalid (slots, ...) actions of a leaf space, the slot's name to blame or None)."""
    slots = shape[0] * shape[1]
    slot = int(rng.integers(slots))
    kind = rng.integers(3)
    if kind == 0:  # one slot's value bad, in a list of per-slot values
        items = [valid_leaf(space, rng, torch)[1] for _ in range(slots)]
        label, items[slot] = bad_leaf(space, rng, torch)
        return f"slot {slot}: {label}", items, slot_name(slot, shape, names)
    if kind == 1:  # one slot's number bad, in an array
        batch = np.stack([valid_numbers(space, rng) for _ in range(slots)]).astype(np.float64)
        label = str(rng.choice(["nan", "inf", "out of range"] + (["fraction"] if _is_discrete(space) else [])))
        batch[slot] = BAD_LEAVES[label](space, np.asarray(batch[slot], space.dtype), rng, torch)
        return f"slot {slot} in an array: {label}", batch, slot_name(slot, shape, names)
    return whole_batch_garbage(space, slots, rng, torch) + (None,)


def whole_batch_garbage(space: spaces.Space, slots: int, rng: np.random.Generator, torch: Any) -> tuple[str, Any]:
    good = np.stack([valid_numbers(space, rng) for _ in range(slots)])
    garbage = {
        "None": None, "string": "actions", "scalar": 1, "dict": {"actions": good}, "object": object(), "empty": [],
        "one slot short": good[:-1], "one slot too many": np.concatenate([good, good[:1]]),
        "bool array": good.astype(bool), "complex array": good + 1j, "string array": good.astype(str),
        "extra trailing axis": good[..., None], "failing __array__": FailingArray(),
    }
    if torch is not None:
        garbage |= {"grad tensor": torch.tensor(good.astype(np.float32), requires_grad=True),
                    "meta tensor": torch.zeros(good.shape, device="meta"),
                    "bool tensor": torch.zeros(good.shape, dtype=torch.bool)}
    label = str(rng.choice(list(garbage)))
    return f"batch: {label}", garbage[label]


def vector_case(space: spaces.Space, shape: tuple[int, int], names: list[str], rng: np.random.Generator,
                torch: Any) -> Case:
    """(slots, ...) actions (a dict of them for a Dict space) of a vector env shaped (worlds, agents)."""
    slots = shape[0] * shape[1]
    parts = space.spaces if isinstance(space, spaces.Dict) else {None: space}
    batches = {key: valid_batch(sub, slots, rng, torch) for key, sub in parts.items()}
    roll = rng.random()
    if roll < 0.3:
        return Case("valid", batches if None not in batches else batches[None], True)
    if roll < 0.85 or None in parts:
        key = list(parts)[rng.integers(len(parts))]
        label, batches[key], culprit = bad_batch(parts[key], shape, names, rng, torch)
        return Case(label if key is None else f"part {key}: {label}",
                    batches if key is not None else batches[key], False, culprit=culprit)
    kind = rng.integers(3)
    if kind == 0:
        return Case("missing key", dict(list(batches.items())[:-1]), False)
    if kind == 1:
        return Case("extra key", {**batches, "speed": np.zeros(slots)}, False)
    return Case("not a dict", np.zeros((slots, 4)), False)
