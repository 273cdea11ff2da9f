"""Value types of the command line's options: a bad value is argparse's usage error naming it."""

from __future__ import annotations

import argparse
import json

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


def generators(text: str) -> dict:
    """A scenario's generators section as JSON (``'{"weather": {"noise_scale_m": 926}}'``), for the benchmarks
    that play a scenario under other generators; the scenario validates what it names."""
    try:
        value = json.loads(text)
    except json.JSONDecodeError as error:
        raise argparse.ArgumentTypeError(f"{text!r} is not JSON ({error})") from None
    if not isinstance(value, dict):
        raise argparse.ArgumentTypeError(f"{text!r}: expected a JSON object of generator overrides")
    return value


def _integer(text: str, expected: str) -> int:
    try:
        return int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected {expected}, got {text!r}") from None
