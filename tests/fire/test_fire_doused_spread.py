"""Doused trees that still spread: ``douse(..., spreading=True)`` and ``FireState.doused``.

The release's ForestDataGenerator.BurnNext tries the neighbours of every tree of its burning list, whatever that
tree's state (BurnNNeighbourIndexes reads only the targets' states), and no water code touches the list: a burning
tree that a drop wets stops counting as burning but goes on spreading until its cohort leaves the list. Worked by
hand with certain ignition: every try has the three weather factors at 0.4 a factor (chance 1).
"""

from __future__ import annotations

import numpy as np
import pytest

from hivex_dsl.sim.fire import FireSpec, FireState, TreeState, any_burning, closest_burning, douse, fire_reset, fire_step
from hivex_dsl.sim.fire.engine import fire_put_worlds

SYMBOLS = {".": TreeState.NONE, "T": TreeState.EXISTING, "B": TreeState.BURNING}
CERTAIN = FireSpec(spread_chance_per_factor=0.4, downwind_cone_deg=0.0, burn_steps=3, quiet_steps_out=3)


def reset(*worlds) -> FireState:
    trees = np.array([[[SYMBOLS[ch] for ch in line] for line in world] for world in worlds], dtype=np.uint8)
    return fire_reset(trees != TreeState.NONE, trees == TreeState.BURNING)


def hot_dry_low(world, row, col):
    return np.ones(len(world)), np.zeros(len(world)), np.zeros(len(world))


def step(state: FireState, spec: FireSpec = CERTAIN) -> FireState:
    heights = np.zeros(state.trees.shape, np.float32)
    return fire_step(state, np.random.default_rng(0), spec, np.zeros(state.batch), heights, hot_dry_low)


# a burning tree in the west, a gap of one cell, then forest: the tree at column 2 is within its 5 x 5 block
LINE = ["B.TTTTT"] + ["......."] * 6


def wet_the_burning_tree(spreading: bool) -> FireState:
    state = reset(LINE)
    state, extinguished, prepared = douse(state, np.array([0]), np.array([0.0]), np.array([0.0]), 0.5,
                                          np.array([0]), 1, spreading=spreading)
    assert extinguished.tolist() == [1] and prepared.tolist() == [0]
    assert state.trees[0, 0, 0] == TreeState.WET and state.burning.size == 0
    return state


def test_a_wet_tree_stops_the_fire_unless_doused_trees_spread():
    stopped = step(wet_the_burning_tree(spreading=False))
    assert stopped.trees[0, 0, 2] == TreeState.EXISTING  # nothing tried it
    assert not any_burning(stopped)[0]

    going = wet_the_burning_tree(spreading=True)
    assert going.doused.tolist() == [0] and going.doused_age.tolist() == [0]
    assert any_burning(going)[0]  # the world's fire goes on, though no tree burns
    after = step(going)
    assert after.trees[0, 0, 2] == TreeState.BURNING  # the wet tree set it alight
    assert after.trees[0, 0, 0] == TreeState.WET  # and stays wet
    assert after.burning.tolist() == [2] and after.doused.tolist() == [0] and after.doused_age.tolist() == [1]


def test_doused_trees_are_never_found_as_burning_and_leave_at_the_end_of_their_burn():
    state = wet_the_burning_tree(spreading=True)
    found, _, _ = closest_burning(state, np.array([0]), np.array([0.0]), np.array([0.0]), 2.0)
    assert not found[0]  # a plane or the village sees no fire there
    for age in (1, 2):
        state = step(state)
        assert state.doused_age.tolist() == [age]
    state = step(state)  # its third fire step: burn_steps 3 reached
    assert state.doused.size == 0 and state.trees[0, 0, 0] == TreeState.WET


def test_a_fire_of_doused_trees_alone_goes_out_only_after_its_quiet_steps():
    state = reset(["B......"] + ["......."] * 6)  # nothing to spread to
    state, _, _ = douse(state, np.array([0]), np.array([0.0]), np.array([0.0]), 0.5, np.array([0]), 1, spreading=True)
    outs = []
    for _ in range(3):
        state = step(state)
        outs.append(bool(state.out[0]))
    assert outs == [False, False, True]  # quiet 1, 2, 3 >= quiet_steps_out, and by then the doused tree left


def test_resetting_a_world_drops_its_doused_trees_and_keeps_the_others():
    state = reset(LINE, LINE)
    state, _, _ = douse(state, np.array([0, 1]), np.array([0.0, 0.0]), np.array([0.0, 0.0]), 0.5, np.array([0, 1]), 2,
                        spreading=True)
    area = state.cells * state.cells
    assert state.doused.tolist() == [0, area] and state.burning.size == 0
    assert any_burning(state).tolist() == [True, True]  # both fires go on through their doused trees
    fresh = reset(["T......"] + ["......."] * 6)
    state = fire_put_worlds(state, np.array([True, False]), fresh)
    assert state.doused.tolist() == [area] and state.doused_age.tolist() == [0]
    assert any_burning(state).tolist() == [False, True]


def test_doused_and_its_ages_come_together():
    trees = np.zeros((1, 3, 3), np.uint8)
    with pytest.raises(ValueError, match="doused"):
        FireState(trees=trees, burning=np.zeros(0, np.int64), age=np.zeros(0, np.int32), quiet=np.zeros(1, np.int32),
                  out=np.zeros(1, bool), ignited=np.zeros(1, np.int64), burnt_out=np.zeros(1, np.int64),
                  doused=np.array([4]))
