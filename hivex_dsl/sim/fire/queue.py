"""The release's burning list: a queue that keeps, past their burn, as many trees as the fire started with.

ForestDataGenerator.BurnNext (the Aerial Wildfire Suppression release, read from its IL: the reward table's note 'The
release's fire start and burning queue') appends each fire step's ignitions to its burning list and their count to
``burningCountHistory``; once that history holds more than ten counts, it drops from the list's front as many trees as
the oldest count says, and that count. The fire's first trees (InitiateFireEnvProbability, 15 to 25 of them) stand at
the list's front but were never counted, so every drop lands one batch short: the list holds the last ten steps'
ignitions and, besides them, as many older trees as the fire started with, the youngest of those whose ten steps are
over. Every tree of the list tries its neighbours, whatever it shows, and each step shows the list's oldest fifth (of
its length before the step) burnt. The fire is out once the ten counts are all 0 (``burning`` false), whatever the list
still holds.

Here a tree tries its neighbours for ``burn_steps`` fire steps while it is on the burning list (or the doused
list, when water reached it); under ``FireSpec.burn_list`` 'release' the ``FireState.carry`` youngest of the trees
past that stay on the doused list, burnt (or wet), still trying, until younger ones push them out or the fire is
out; and each step the oldest fifth of a world's list moves from the burning list to the doused one, burnt, still
trying (:func:`show_front_burnt`). Ties in age keep the later in the list, as the queue drops from its front.
"""

from __future__ import annotations

import numpy as np

from .engine import BURNT, FireState


def keep_youngest(ended: np.ndarray, doused: np.ndarray, doused_age: np.ndarray, carry: np.ndarray,
                  burn_steps: int, area: int) -> tuple[np.ndarray, np.ndarray]:
    """The doused list after a fire step under the release's queue: (cells (D',) int64, ages (D',) int32).

    ``ended`` (E,) flat cells whose burn just ended (age ``burn_steps``), in list order; ``doused``/``doused_age``
    (D,) the doused list after it aged a step; ``carry`` (B,) the trees each world keeps past their burn;
    ``area`` cells a world. Keeps the doused trees still within their burn, in order, then in each world ``w``
    the ``carry[w]`` youngest of the ended and the doused past their burn, in the order they came.
    """
    young = doused_age < burn_steps
    if young.all() and ended.size == 0:
        return doused, doused_age
    old = np.concatenate([ended, doused[~young]])
    old_age = np.concatenate([np.full(len(ended), burn_steps, np.int32), doused_age[~young]])
    world = old // area
    later_first = -np.arange(len(old))
    order = np.lexsort((later_first, old_age, world))  # each world's youngest first, the later of a tie first
    kept = np.sort(_first_of_each_world(order, world, carry))
    return (np.concatenate([doused[young], old[kept]]),
            np.concatenate([doused_age[young], old_age[kept]]).astype(np.int32, copy=False))


def _first_of_each_world(order: np.ndarray, world: np.ndarray, quota: np.ndarray) -> np.ndarray:
    """The entries of ``order`` (N,), indices sorted by ``world`` (N,) first, that come among the first ``quota[w]``
    (``quota`` (B,)) of their world ``w``'s run."""
    runs = world[order]
    rank = np.arange(len(order)) - np.searchsorted(runs, runs, side="left")
    return order[rank < quota[runs]]


def put_out(trees: np.ndarray, out: np.ndarray, burning: np.ndarray, age: np.ndarray, spent: np.ndarray,
            doused: np.ndarray, doused_age: np.ndarray
            ) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Empty both lists in the worlds whose fire is ``out`` (B,) bool: their burning trees turn BURNT in
    ``trees`` (B, C, C), written in place, and nothing of theirs tries again.
    -> (burning, age, spent, doused, doused_age, the flat cells that burnt out here (N,))."""
    area = trees.shape[1] * trees.shape[2]
    going = ~out[burning // area]
    ended = burning[~going]
    trees.reshape(-1)[ended] = BURNT
    staying = ~out[doused // area]
    return burning[going], age[going], spent[going], doused[staying], doused_age[staying], ended


def list_lengths(state: FireState) -> np.ndarray:
    """(B,) int64 trees on each world's lists, burning and doused: the release's burning list as long as it is."""
    area = state.trees[0].size
    return (np.bincount(state.burning // area, minlength=state.batch)
            + np.bincount(state.doused // area, minlength=state.batch))


def show_front_burnt(trees: np.ndarray, before: np.ndarray, burning: np.ndarray, age: np.ndarray, spent: np.ndarray,
                     doused: np.ndarray, doused_age: np.ndarray
                     ) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """BurnNext's last loop: each world's list, ``before`` (B,) trees long when the step began, shows its oldest
    ceil(0.2 x before) trees burnt (the release sets state 3 on list positions d < 0.2 x that length), and they go
    on trying. Those still on the burning list move to the doused list, BURNT in ``trees`` (B, C, C, written in
    place); the doused ones (older, carried or wet) count in the fifth as they stand. The oldest first, and of one
    age the earlier in the list. -> (burning, age, spent, doused, doused_age, the flat cells shown burnt (N,))."""
    zone = np.ceil(0.2 * before).astype(np.int64)
    if burning.size == 0 or not zone.any():
        return burning, age, spent, doused, doused_age, burning[:0]
    area = trees[0].size
    cells = np.concatenate([doused, burning])
    ages = np.concatenate([doused_age, age]).astype(np.int64)
    world = cells // area
    order = np.lexsort((np.arange(len(cells)), -ages, world))  # each world's oldest first
    front = _first_of_each_world(order, world, zone)
    moved = np.sort(front[front >= len(doused)]) - len(doused)
    if moved.size == 0:
        return burning, age, spent, doused, doused_age, burning[:0]
    shown = burning[moved]
    trees.reshape(-1)[shown] = BURNT
    keep = np.ones(len(burning), bool)
    keep[moved] = False
    return (burning[keep], age[keep], spent[keep], np.concatenate([doused, shown]),
            np.concatenate([doused_age, age[moved]]).astype(np.int32, copy=False), shown)


def settle(trees: np.ndarray, before: np.ndarray, went_out: np.ndarray, lists: tuple) -> tuple:
    """The release's list at the end of a fire step: its oldest fifth shown burnt (:func:`show_front_burnt`, by the
    list's length ``before`` (B,) the step), then both lists emptied in the worlds whose fire ``went_out`` (B,)
    bool this step (:func:`put_out`). ``lists`` = (burning, age, spent, doused, doused_age) after the step's
    ignitions. -> those five, then (B,) int64 the trees either turned BURNT in ``trees`` (written in place)."""
    burning, age, spent, doused, doused_age, shown = show_front_burnt(trees, before, *lists)
    burnt = shown
    if np.logical_or.reduce(went_out):
        burning, age, spent, doused, doused_age, put = put_out(trees, went_out, burning, age, spent, doused,
                                                               doused_age)
        burnt = np.concatenate([shown, put])
    return burning, age, spent, doused, doused_age, np.bincount(burnt // trees[0].size, minlength=len(before))
