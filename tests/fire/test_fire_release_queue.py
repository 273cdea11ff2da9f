"""The release's burning queue: ``FireSpec.burn_list`` 'release' and ``FireState.carry`` (hivex_dsl.sim.fire.queue).

ForestDataGenerator.BurnNext drops from its burning list's front, each fire step, as many trees as caught fire ten steps
before; the fire's first trees were never counted, so the list keeps, past their burn, as many of the youngest trees as
the fire started with, and they go on trying their neighbours until the fire is out (ten steps without an ignition), and
each step it shows its oldest fifth burnt. Worked by hand: every factor but the wind is false (cool, damp, overcast,
flat), one factor is worth a certain ignition and the cone is exact, so a tree sets its neighbour alight exactly when
the wind blows from it to that neighbour.
"""

from __future__ import annotations

import numpy as np

from hivex_dsl.sim.fire import FireSpec, FireState, TreeState, any_burning, douse, fire_reset, fire_step
from hivex_dsl.sim.fire.engine import fire_copy, fire_put_worlds
from hivex_dsl.sim.fire.queue import keep_youngest, show_front_burnt

SYMBOLS = {".": TreeState.NONE, "T": TreeState.EXISTING, "B": TreeState.BURNING}
EAST, WEST = 0.0, np.pi  # the way the wind blows: +col, -col
AGE = FireSpec(spread_chance_per_factor=1.0, downwind_cone_deg=0.0, burn_steps=3, quiet_steps_out=5)
QUEUE = AGE.model_copy(update={"burn_list": "release"})
# A burns; B, west of it, catches only from a wind blowing west
PAIR = [".....", ".....", ".TB..", ".....", "....."]
A, B = (2, 2), (2, 1)


def reset(*worlds) -> FireState:
    trees = np.array([[[SYMBOLS[ch] for ch in line] for line in world] for world in worlds], dtype=np.uint8)
    return fire_reset(trees != TreeState.NONE, trees == TreeState.BURNING)


def cool_damp_overcast(world, row, col):
    return np.zeros(len(world)), np.ones(len(world)), np.ones(len(world))


def step(state: FireState, spec: FireSpec, wind: float) -> FireState:
    heights = np.zeros(state.trees.shape, np.float32)
    return fire_step(state, np.random.default_rng(0), spec, np.full(state.batch, wind), heights, cool_damp_overcast)


def course(spec: FireSpec, winds: list[float]) -> list[FireState]:
    states, state = [], reset(PAIR)
    for wind in winds:
        state = step(state, spec, wind)
        states.append(fire_copy(state))  # a step writes the trees in place
    return states


# the wind blows east for three fire steps (A's whole burn), then west
WINDS = [EAST, EAST, EAST] + [WEST] * 7


def test_the_first_trees_are_what_the_queue_keeps():
    state = reset(["B.B", "...", "BBB"], ["..B", "...", "..."])
    assert state.carry.tolist() == [5, 1]
    fresh = reset(["BB.", "...", "..."])
    assert fire_put_worlds(state, np.array([False, True]), fresh).carry.tolist() == [5, 2]
    wet, _, _ = douse(state, np.array([0]), np.array([0.0]), np.array([0.0]), 0.5, np.array([0]), 1, spreading=True)
    assert wet.carry.tolist() == [5, 1]


def test_by_age_a_burnt_out_tree_never_tries_again():
    states = course(AGE, WINDS)
    assert states[2].trees[0][A] == TreeState.BURNT and any_burning(states[2])[0] == False  # noqa: E712
    assert [s.trees[0][B] for s in states] == [TreeState.EXISTING] * len(WINDS)
    assert [bool(s.out[0]) for s in states].index(True) == 4  # quiet for five steps: out at the fifth


def test_the_queue_keeps_the_first_tree_trying_after_its_burn():
    states = course(QUEUE, WINDS)
    assert states[0].trees[0][A] == TreeState.BURNT  # the list's oldest fifth shows burnt at once
    third = states[2]  # A's burn is over: BURNT, seen burning nowhere, yet kept on the list
    assert third.trees[0][A] == TreeState.BURNT and third.burning.size == 0
    assert third.doused.tolist() == [A[0] * 5 + A[1]] and third.doused_age.tolist() == [3]
    assert any_burning(third)[0] and not third.out[0]
    fourth = states[3]  # the wind turns west: A sets B alight
    assert fourth.trees[0][B] == TreeState.BURNING and fourth.quiet[0] == 0
    assert fourth.doused_age.tolist() == [4]
    # B's burn ends at the seventh step; as the youngest past its burn it takes A's place
    assert states[6].doused.tolist() == [B[0] * 5 + B[1]] and states[6].doused_age.tolist() == [3]
    outs = [bool(s.out[0]) for s in states]
    assert outs.index(True) == 8  # five steps without an ignition after B's, though B is still on the list
    assert states[8].doused.size == 0 and states[8].burning.size == 0 and not any_burning(states[8])[0]
    assert states[8].trees[0][B] == TreeState.BURNT


def test_the_queue_goes_out_on_its_quiet_steps_with_trees_still_on_its_list():
    spec = QUEUE.model_copy(update={"burn_steps": 8, "quiet_steps_out": 2})
    states = course(spec, [EAST] * 3)
    assert [bool(s.out[0]) for s in states] == [False, True, True]
    assert states[0].doused.tolist() == [12] and states[0].doused_age.tolist() == [1]  # within its burn, trying
    assert states[1].doused.size == 0 and states[1].burning.size == 0 and not any_burning(states[1])[0]


def test_the_oldest_fifth_of_the_list_shows_burnt_and_goes_on_trying():
    # one world of 3 x 3 cells: burning cells 0-4 aged 4, 4, 2, 1, 0, and cell 8 doused at age 3
    def front(before):
        trees = np.full((1, 3, 3), TreeState.BURNING, np.uint8)
        trees[0, 2, 2] = TreeState.WET
        burning, age = np.array([0, 1, 2, 3, 4]), np.array([4, 4, 2, 1, 0], np.int32)
        out = show_front_burnt(trees, np.array([before]), burning, age, np.zeros(5, np.uint8), np.array([8]),
                               np.array([3], np.int32))
        return trees, out

    trees, (burning, age, _, doused, doused_age, shown) = front(6)  # a fifth of 6 is 1.2: the two oldest
    assert burning.tolist() == [2, 3, 4] and age.tolist() == [2, 1, 0]
    assert doused.tolist() == [8, 0, 1] and doused_age.tolist() == [3, 4, 4] and shown.tolist() == [0, 1]
    assert trees.reshape(-1).tolist() == [TreeState.BURNT] * 2 + [TreeState.BURNING] * 6 + [TreeState.WET]
    assert front(11)[1][0].tolist() == [2, 3, 4]  # three: the doused cell 8, older than cell 2, is the third
    assert front(16)[1][0].tolist() == [3, 4]  # four: cell 2 too
    assert front(0)[1][0].tolist() == [0, 1, 2, 3, 4]  # an empty list before shows nothing


def test_a_single_burning_tree_shows_burnt_at_the_first_step():
    first = course(QUEUE, [EAST])[0]
    assert first.trees[0][A] == TreeState.BURNT and first.burning.size == 0 and first.burnt_out.tolist() == [1]
    assert course(AGE, [EAST])[0].trees[0][A] == TreeState.BURNING  # by age it burns its three steps


def test_keep_youngest_keeps_each_worlds_carry_of_the_trees_past_their_burn():
    # worlds of 9 cells; burn_steps 10: cells 0 and 2 (world 0) and 10 (world 1) just ended their burn, the doused
    # cell 4 (world 0) is past it at age 12, the doused cell 13 (world 1) still within it
    ended, doused, ages = np.array([0, 2, 10]), np.array([4, 13]), np.array([12, 3], np.int32)
    cells, kept = keep_youngest(ended, doused, ages, np.array([2, 0]), 10, 9)
    assert cells.tolist() == [13, 0, 2] and kept.tolist() == [3, 10, 10]
    cells, kept = keep_youngest(ended, doused, ages, np.array([1, 0]), 10, 9)
    assert cells.tolist() == [13, 2] and kept.tolist() == [3, 10]  # a tie in age keeps the later, as the queue does
    cells, kept = keep_youngest(ended, doused, ages, np.array([3, 5]), 10, 9)
    assert cells.tolist() == [13, 0, 2, 10, 4] and kept.tolist() == [3, 10, 10, 10, 12]


def test_the_default_is_this_toolkits_burn_by_age():
    assert FireSpec().burn_list == "age"
