"""When the release's fire steps (params.fire_cadence 'frames'): its BurnNext coroutine, read from the IL.

ForestDataGenerator.Update runs once a rendered frame (every ``wind_frame_steps`` academy steps) and starts
BurnNext when the fire burns and its flag ``burnCoroutineRunning`` is clear. BurnNext sets the flag, makes one
fire step and waits ``WaitForSeconds(1 / timeScale)``, which the next frame ends (after that frame's Update);
ending, it clears the flag. So one coroutine makes a fire step every two frames. A world's redraw
(AgentManager.TriggerDone -> InitiateForest -> ResetForest) clears the flag without stopping a coroutine that
waits: when it lands between the frame that started one and the frame that ends it, the next Update starts a
second chain, and from then on each frame's Update starts one coroutine while the one before ends after it,
clearing the flag: a fire step every frame, for the rest of the stream. The fire's going out lands there
always (the planes' FireReward reads the cleared ``burning`` flag on the first step after the Update that
cleared it), a redraw by the planes' finishes half the time.
"""

from __future__ import annotations

from typing import Any, Callable

import numpy as np

from ...sim.fire import FireState, fire_put_worlds, fire_take_worlds
from ...sim.procgen.wind import frame_ends

_NONE = np.zeros(0, bool)  # no world steps (read-only: every caller shares it)
_NONE.flags.writeable = False


def burn_frame(fire_out: np.ndarray, running: np.ndarray, waiting: np.ndarray
               ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """One rendered frame's Update and the coroutines it resumes, per world.

    fire_out (B,) bool: the release's ``burning`` flag cleared; running (B,) bool: ``burnCoroutineRunning``;
    waiting (B,) bool: a BurnNext started at the frame before waits now.
    -> (starts (B,) bool: the worlds whose fire steps at this frame, running (B,), waiting (B,)) after it."""
    starts = ~fire_out & ~running
    return starts, (running | starts) & ~waiting, starts


def stepping_worlds(params: Any, tick: int, fire_out: np.ndarray, running: np.ndarray, waiting: np.ndarray
                    ) -> tuple[np.ndarray | None, np.ndarray, np.ndarray]:
    """The worlds whose fire steps on the step from ``tick``, by params.fire_cadence: every fire_step_interval
    steps in all worlds ('interval'), or at a frame's end as :func:`burn_frame` says ('frames').
    -> (worlds: None for all, else (B,) bool or an empty array for none; running, waiting (B,) after it)."""
    if params.fire_cadence == "interval":
        return (None if (tick + 1) % params.fire_step_interval == 0 else _NONE), running, waiting
    if not frame_ends(tick, params.wind_frame_steps):
        return _NONE, running, waiting
    return burn_frame(fire_out, running, waiting)


def step_worlds(fire: FireState, worlds: np.ndarray | None,
                step: Callable[[FireState, np.ndarray | None], FireState]) -> FireState:
    """``fire`` after ``step(fire_of_the_worlds, their indices (M,) int, or None for all)`` in ``worlds`` alone
    (None: every world). ``fire`` is consumed, as a fire step consumes it."""
    if worlds is None or (worlds.size and worlds.all()):
        return step(fire, None)
    if not worlds.any():
        return fire
    return fire_put_worlds(fire, worlds, step(fire_take_worlds(fire, worlds), np.flatnonzero(worlds)))


def of_worlds(reader: Any, index: np.ndarray | None) -> Any:
    """A fire callback (world, row, col) -> values, or a (B,) array, narrowed to the worlds ``index`` (M,)."""
    if index is None:
        return reader
    if callable(reader):
        return lambda world, rows, cols: reader(index[world], rows, cols)
    return reader[index]
