"""The seed streams of a scenario's train/test split, as :class:`hivex_dsl.runtime.BatchedEnv` plays them."""

from __future__ import annotations

from typing import Optional

import numpy as np

from ..base.errors import is_integer

_UNSEEDED_STREAMS: dict[int, int] = {}  # scenario seed -> unseeded streams started from it in this process


def copy_stream(seed: int) -> np.random.Generator:
    """The stream of the next unseeded copy of a scenario whose integer seed is ``seed``.

    The first copy in a process plays the scenario's own stream; copy k (k >= 1) a child stream
    ``SeedSequence(seed, spawn_key=(k,))``. So copies (SuperSuit's concatenation, several adapters
    of one scenario) are different worlds unless seeded, and a program is still reproducible.
    """
    k = _UNSEEDED_STREAMS.get(seed, 0)
    _UNSEEDED_STREAMS[seed] = k + 1
    return np.random.default_rng(seed if k == 0 else np.random.SeedSequence(seed, spawn_key=(k,)))


class SeedSchedule:
    """Seeds of one split: an integer seeds a stream that episodes continue; a list seeds each episode.

    ``distinct_copies`` (the adapters): an integer stream started without a user's seed is the
    scenario's own for the first such copy in the process and a child of it for later ones
    (:func:`copy_stream`); without it (``hivex run``, the report) always the scenario's own.
    """

    def __init__(self, seeds: int | tuple[int, ...], distinct_copies: bool = False):
        self.seeds = seeds
        self.episode = 0
        self.rng: Optional[np.random.Generator] = None
        self.distinct_copies = distinct_copies

    def next_rng(self, explicit: Optional[int]) -> np.random.Generator:
        """The generator for the next reset; ``explicit`` (a user's seed) restarts the stream."""
        if explicit is not None:
            if not is_integer(explicit) or explicit < 0:
                raise ValueError(f"seed must be a non-negative integer or None, got {explicit!r}")
            self.rng = np.random.default_rng(explicit)
        elif isinstance(self.seeds, tuple):
            self.rng = np.random.default_rng(self.seeds[self.episode % len(self.seeds)])
        elif self.rng is None:
            self.rng = copy_stream(self.seeds) if self.distinct_copies else np.random.default_rng(self.seeds)
        self.episode += 1
        return self.rng
