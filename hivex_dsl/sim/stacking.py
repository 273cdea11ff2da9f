"""Stacked observations shift once a decision, as ML-Agents' stacking sensors do.

A simulator that stacks its observations (``observation_stacks`` n > 1) builds them newest first along the last
axis of the state fields it names in ``stacked_fields``, and shifts them on every physics step: its ``step``
cannot know where a decision ends. ML-Agents shifts a stack when the agent's sensors are updated, and that
happens only when the agent sends its info to the brain: at a decision, and when its episode ends:

- ``StackingSensor.Update`` (com.unity.ml-agents/Runtime/Sensors/StackingSensor.cs) advances the circular
  buffer's index; ``StackingSensor.Write`` writes the wrapped sensor's observation into the current slot and
  outputs the saved ones.
- ``Agent.UpdateSensors`` (com.unity.ml-agents/Runtime/Agent.cs, the release-19 era source, whose doc links name
  release_19_docs) calls every sensor's ``Update``. Its callers are ``Agent.SendInfoToBrain``, which
  ``Agent.SendInfo`` calls only when a decision was requested (``m_RequestDecision``, set by ``RequestDecision``,
  which ``DecisionRequester`` calls every ``DecisionPeriod`` academy steps), and ``Agent.NotifyAgentDone``, which
  sends an ended agent's last observation and then ``ResetSensors``, zeroing the buffers for its next episode
  (release 6's ``NotifyAgentDone`` wrote the last observation without the ``Update``).

So at a decision period k the older stack the policy sees is what it saw as the newest at the previous decision,
k physics steps back (an episode's last observation included: its older stack is the newest of the decision
the agent ended in); :func:`stack_per_decision`, which the runtime (:meth:`hivex_dsl.runtime.BatchedEnv.step`)
calls after a decision's last physics step, puts it there. At k = 1 a physics step is a decision and the
simulator's own shift is already this one.
"""

from __future__ import annotations

from typing import Sequence, TypeVar

import numpy as np

from .batching import evolve

S = TypeVar("S")


def stack_per_decision(start: S, end: S, fields: Sequence[str], stacks: int) -> S:
    """``end`` (the state after a decision's last physics step) with the older stacks of each of ``fields`` taken
    from ``start`` (the state the decision was taken in): the newest stack of ``end``, then the ``stacks - 1``
    newest stacks of ``start``, each field an array (B, A, ..., stacks x size) stacked newest first on its last
    axis. The runtime respawns agents and restarts worlds after this, so their first observations keep the older
    stack their simulator gives a first observation."""
    changes = {}
    for name in fields:
        before, after = getattr(start, name), getattr(end, name)
        size = after.shape[-1] // stacks
        changes[name] = np.concatenate([after[..., :size], before[..., :(stacks - 1) * size]], axis=-1)
    return evolve(end, **changes)


__all__ = ["stack_per_decision"]
