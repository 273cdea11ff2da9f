"""Located errors: every problem in a user's file is reported as ``path:line:col: message``."""

from __future__ import annotations

import difflib
import math
import numbers
from dataclasses import dataclass
from typing import Iterable, Sequence


@dataclass(frozen=True, order=True)
class Location:
    """A 1-based line and column in a named source (a file path, or ``<dict>`` for Python input)."""

    path: str
    line: int
    col: int

    def __str__(self) -> str:
        return f"{self.path}:{self.line}:{self.col}"


@dataclass(frozen=True)
class Problem:
    """One thing wrong with a scenario, at a place the user can jump to."""

    location: Location
    message: str

    def __post_init__(self) -> None:
        # one line, every character visible, even when it quotes a key that holds a line break or a
        # zero-width space ('a\u200bgents' rather than an 'agents' that looks right)
        if not self.message.isprintable():
            visible = "".join(c if c.isprintable() else c.encode("unicode_escape").decode() for c in self.message)
            object.__setattr__(self, "message", visible)

    def __str__(self) -> str:
        return f"{self.location}: {self.message}"


class HivexError(Exception):
    """Base class of every error this package raises on purpose."""


class ScenarioError(HivexError, ValueError):
    """A scenario or reward table is invalid. Carries every problem found, in file order."""

    def __init__(self, problems: Sequence[Problem]):
        if not problems:
            raise ValueError("ScenarioError needs at least one problem")
        self.problems: tuple[Problem, ...] = tuple(sorted(problems, key=lambda p: p.location))
        super().__init__("\n".join(str(p) for p in self.problems))

    @property
    def first(self) -> Problem:
        return self.problems[0]


class ItemValueError(ValueError):
    """Raised by a field validator to blame one part of the value, ``at`` (indices or keys below the field)."""

    def __init__(self, message: str, at: tuple = ()):
        super().__init__(message)
        self.at = tuple(at)


class ActionError(HivexError, ValueError):
    """An action handed to an environment is outside its space."""


class ResetNeeded(HivexError, RuntimeError):
    """An environment was stepped before its first ``reset()``, or after every agent's episode ended."""


class KeywordError(HivexError, TypeError):
    """A keyword argument the function does not take (e.g. vector_env's old ``num_envs``)."""


def did_you_mean(word: str, choices: Iterable[str]) -> str:
    """`` (did you mean 'x'?)`` for the closest of ``choices``, or an empty string."""
    close = difflib.get_close_matches(str(word), list(choices), n=1, cutoff=0.6)
    return f"; did you mean '{close[0]}'?" if close else ""


def one_of(choices: Iterable[object]) -> str:
    """A readable list of allowed values: ``'a', 'b' or 'c'``."""
    items = [f"'{c}'" if isinstance(c, str) else str(c) for c in choices]
    if not items:
        return "nothing"
    if len(items) == 1:
        return items[0]
    return ", ".join(items[:-1]) + " or " + items[-1]


def show(value: object) -> str:
    """A value as the user wrote it, short enough for one line."""
    if isinstance(value, str):
        text = repr(value)
    elif isinstance(value, bool):
        text = "true" if value else "false"
    elif isinstance(value, float) and not math.isfinite(value):
        text = ".nan" if math.isnan(value) else (".inf" if value > 0 else "-.inf")  # as YAML spells them
    elif value is None:
        text = "null"
    elif isinstance(value, dict):
        text = "a mapping"
    elif isinstance(value, list):
        text = "a list"
    else:
        try:
            text = str(value)
        except ValueError:  # an integer too long to print
            text = "a very large integer"
    return text if len(text) <= 60 else text[:57] + "..."


def got(value: object) -> str:
    """The tail of 'expected ..., got ...': ``'8' (a string)``, ``4 (an integer)``, ``a list``."""
    shown, kind = show(value), kind_of(value)
    return shown if shown == kind else f"{shown} ({kind})"


def kind_of(value: object) -> str:
    """The YAML kind of a value, for 'got ... (a string)' messages."""
    if isinstance(value, bool):
        return "a boolean"
    if isinstance(value, int):
        return "an integer"
    if isinstance(value, float):
        return "a number"
    if isinstance(value, str):
        return "a string"
    if value is None:
        return "null"
    if isinstance(value, dict):
        return "a mapping"
    if isinstance(value, list):
        return "a list"
    return type(value).__name__


def is_integer(value: object) -> bool:
    """True for a Python or NumPy integer; False for a bool, which Python counts as an int."""
    return isinstance(value, numbers.Integral) and not isinstance(value, bool)
