"""Finished planes that wait for the rest of their world (``finished_planes: wait``), as the release's do.

The release's AgentManager counts calls of ``AgentDone``: a plane calls it once when it crosses the border or
meets its task's end (and freezes), and the episodes of all its planes end together when the count reaches the
plane count. Two of its checks skip the freeze test, so a frozen plane that found the village (still within its
radius) or the fire is paid again and calls ``AgentDone`` again every step it waits: the first finder ends its
world within (planes - 1) steps, two for the paper's three. That its tree still burns then is taken as given (a
tree burns ten fire steps, 220 steps at the default cadence). This module counts those calls; the simulator
holds the planes (``held_events``, see hivex_dsl.runtime.contract).
"""

from __future__ import annotations

import numpy as np

from ...base.numeric import and_not

# the task ends whose release check a frozen plane still passes, and the latch saying it passed it before
_REPEATED = {"found_fire": "seen_fire", "found_village": "seen_village"}


def count_finishes(prev, flying: np.ndarray, events: dict[str, np.ndarray], plane_endings: tuple[str, ...]
                   ) -> tuple[np.ndarray, np.ndarray]:
    """(finishes (B,) int64, world ended (B,) bool) after a step from ``prev``. ``flying`` (B, A) after the step;
    ``events`` (name -> (B, A) bool) gain, in place, the repeated finds of waiting planes (paid again)."""
    calls = and_not(prev.flying, flying).sum(axis=1)  # planes that finished this step: crossed or met the end
    for event in plane_endings:
        latch = _REPEATED.get(event)
        if latch is not None:
            again = and_not(getattr(prev, latch), prev.flying)  # frozen where it found: finds again
            events[event] = events[event] | again
            calls = calls + again.sum(axis=1)
    finishes = prev.finishes + calls
    agents = flying.shape[1]
    return finishes, (finishes >= agents) & (prev.finishes < agents)
