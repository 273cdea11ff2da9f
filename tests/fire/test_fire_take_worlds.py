"""Taking some worlds of a fire out, stepping them alone and putting them back (fire_take_worlds, used where
worlds' fires step at different times: Aerial Wildfire Suppression's params.fire_cadence 'frames')."""

from __future__ import annotations

import numpy as np

from hivex_dsl.envs.aerial_wildfire_suppression.burn_clock import of_worlds, step_worlds
from hivex_dsl.sim.fire import FireSpec, FireState, TreeState, fire_put_worlds, fire_reset, fire_step, fire_take_worlds

SYMBOLS = {".": TreeState.NONE, "T": TreeState.EXISTING, "B": TreeState.BURNING}
# every downwind neighbour catches (one factor, chance 1): the steps below need no random draw
SURE = FireSpec(spread_chance_per_factor=1.0, downwind_cone_deg=0.0, burn_steps=2, quiet_steps_out=3)
EAST = 0.0
WORLDS = (["TBTT", "....", "BTTT", "...."],  # two fires, each with trees east of it
          ["....", ".BT.", "....", "...."],
          ["BTT.", "....", "....", "..BT"])


def reset(*worlds) -> FireState:
    trees = np.array([[[SYMBOLS[ch] for ch in line] for line in world] for world in worlds], dtype=np.uint8)
    return fire_reset(trees != TreeState.NONE, trees == TreeState.BURNING)


def mild(world, row, col):
    return np.zeros(len(world)), np.ones(len(world)), np.ones(len(world))


def step(state: FireState, winds=None) -> FireState:
    winds = np.full(state.batch, EAST) if winds is None else winds
    return fire_step(state, np.random.default_rng(0), SURE, winds, np.zeros(state.trees.shape, np.float32), mild)


def lists_by_world(state: FireState) -> list[list[int]]:
    """Each world's burning list, in order, as cells of its own grid."""
    area = state.cells ** 2
    return [[int(c % area) for c in state.burning if c // area == w] for w in range(state.batch)]


def test_taking_worlds_renumbers_them_and_keeps_their_lists():
    fire = step(reset(*WORLDS))  # ages and quiet counters no longer all zero
    some = fire_take_worlds(fire, np.array([True, False, True]))
    assert some.batch == 2
    assert np.array_equal(some.trees, fire.trees[[0, 2]])
    assert lists_by_world(some) == [lists_by_world(fire)[0], lists_by_world(fire)[2]]
    assert some.age.tolist() == [a for a, c in zip(fire.age, fire.burning) if c // 16 != 1]
    assert some.carry.tolist() == [2, 2] and some.quiet.tolist() == fire.quiet[[0, 2]].tolist()
    some.trees[0, 0, 0] = TreeState.BURNT  # a copy: the whole fire is untouched
    assert fire.trees[0, 0, 0] == TreeState.EXISTING


def test_stepping_some_worlds_is_stepping_them_alone():
    mask = np.array([True, False, True])
    before = reset(*WORLDS)
    world_one = before.trees[1].copy()
    stepped = step_worlds(before, mask, lambda some, index: step(some, of_worlds(np.full(3, EAST), index)))
    alone = step(reset(WORLDS[0], WORLDS[2]))
    assert np.array_equal(stepped.trees[[0, 2]], alone.trees)
    assert np.array_equal(stepped.trees[1], world_one)  # world 1 waited: its tree east of the fire stands
    assert lists_by_world(stepped) == [lists_by_world(alone)[0], [5], lists_by_world(alone)[1]]
    assert stepped.ignited.tolist() == [alone.ignited[0], 1, alone.ignited[1]]  # world 1 keeps its reset's count


def test_every_world_or_none():
    calls = []

    def counting(some, index):
        calls.append(index)
        return step(some)

    fire = reset(*WORLDS)
    assert step_worlds(fire, np.zeros(3, bool), counting) is fire and calls == []
    step_worlds(fire, None, counting)
    step_worlds(reset(*WORLDS), np.ones(3, bool), counting)
    assert calls == [None, None]  # the whole fire, with no copy


def test_a_narrowed_reader_asks_the_worlds_it_stands_for():
    asked = []
    reader = of_worlds(lambda world, rows, cols: asked.append(world.tolist()), np.array([0, 2]))
    reader(np.array([1, 0, 1]), np.zeros(3, int), np.zeros(3, int))
    assert asked == [[2, 0, 2]]
    assert of_worlds(np.array([10.0, 11.0, 12.0]), np.array([2])).tolist() == [12.0]


def test_taking_and_putting_back_changes_nothing():
    fire = step(reset(*WORLDS))
    mask = np.array([False, True, True])
    back = fire_put_worlds(step(reset(*WORLDS)), mask, fire_take_worlds(fire, mask))
    assert np.array_equal(back.trees, fire.trees)
    assert lists_by_world(back) == lists_by_world(fire)
    assert back.quiet.tolist() == fire.quiet.tolist() and back.carry.tolist() == fire.carry.tolist()
