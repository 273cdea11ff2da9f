"""Value types of the command line's numeric options: a bad value is argparse's usage error naming it."""

from __future__ import annotations

import argparse

from ..lang.spec.common import MAX_SEED


def positive(text: str) -> int:
    """An integer of at least 1 (``--episodes``, ``--steps``, ...)."""
    value = _integer(text, "a positive integer")
    if value < 1:
        raise argparse.ArgumentTypeError(f"expected a positive integer, got {text}")
    return value


def seed(text: str) -> int:
    """A seed, as a scenario's seeds are: an integer from 0 to 2**32 - 1."""
    expected = f"an integer from 0 to {MAX_SEED}"
    value = _integer(text, expected)
    if not 0 <= value <= MAX_SEED:
        raise argparse.ArgumentTypeError(f"expected {expected}, got {text}")
    return value


def _integer(text: str, expected: str) -> int:
    try:
        return int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected {expected}, got {text!r}") from None
