"""The fire engine's shortcuts give exactly the general path's fire (same cells, lists and random draws).

Shortcuts: skipping burning trees whose block is known to hold no existing tree (``FireState.spent``),
weather factors read from a :class:`FactorGrid` instead of a ``conditions`` callable, int64 pairs for
short burning lists, burn-out by slicing when the oldest trees lead the list, the one-world tally in
Python numbers and the one-sum check of the wind. Entries for simulators that hold valid state:
fire_step_unchecked skips fire_step's argument checks; fire_put_worlds puts fresh fires (from
fire_reset) into masked worlds without rebuilding their tree grids, as fire_reset_where does from those grids.
"""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from hivex_dsl.sim.fire import (FactorGrid, FireSpec, FireState, TreeState, count_factors, douse, fire_copy,
                                fire_put_worlds, fire_reset, fire_reset_where, fire_step, fire_step_unchecked,
                                grid_cell_table)
from hivex_dsl.sim.fire import engine as engine_module
from hivex_dsl.sim.fire import spread as spread_module
from hivex_dsl.sim.fire.spread import block_offsets


@st.composite
def fires(draw):
    batch, cells = draw(st.integers(1, 3)), draw(st.integers(3, 12))
    spec = FireSpec(spread_radius_cells=draw(st.integers(1, 3)),
                    spread_chance_per_factor=draw(st.sampled_from([0.1, 0.2, 0.5, 1.0])),
                    downwind_cone_deg=draw(st.sampled_from([0.0, 45.0, 90.0, 180.0])),
                    burn_steps=draw(st.integers(1, 5)),
                    quiet_steps_out=draw(st.integers(1, 6)))
    return batch, cells, spec, draw(st.integers(0, 2**32 - 1))


def heights_and_weather(rng, worlds, cells):
    """Random float32 cell heights (worlds, cells, cells) and a conditions callable reading three random fields."""
    heights = rng.normal(size=(worlds, cells, cells)).astype(np.float32)
    fields = rng.random((3, worlds, cells, cells))
    return heights, lambda w, r, c: tuple(f[w, r, c] for f in fields)


def random_forest(rng, worlds, cells):
    exists = rng.random((worlds, cells, cells)) < rng.uniform(0.3, 1.0)
    return exists, exists & (rng.random(exists.shape) < 0.1)


def forget_spent(state: FireState) -> FireState:
    """The same fire with nothing known to be spent (every burning tree tries its block)."""
    return FireState(trees=state.trees, burning=state.burning, age=state.age, quiet=state.quiet, out=state.out,
                     ignited=state.ignited, burnt_out=state.burnt_out)


FIRE_FIELDS = ("trees", "burning", "age", "quiet", "out", "ignited", "burnt_out")


def assert_same_fire(a: FireState, b: FireState, fields: tuple[str, ...] = FIRE_FIELDS) -> None:
    for name in fields:
        np.testing.assert_array_equal(getattr(a, name), getattr(b, name), err_msg=name)
        assert getattr(a, name).dtype == getattr(b, name).dtype, name


def assert_lockstep(step_a, step_b, fire: FireState, rng: np.random.Generator, seed: int, steps: int,
                    fields: tuple[str, ...] = FIRE_FIELDS) -> None:
    """Step two copies of ``fire`` with ``step_a`` and ``step_b`` ((fire, draws, wind) -> fire), under twin
    random streams and the same wind, and check after every step that the fires and the draws agree."""
    a, b = fire, fire_copy(fire)
    draws_a, draws_b = np.random.default_rng(seed + 1), np.random.default_rng(seed + 1)
    for _ in range(steps):
        wind = rng.uniform(-np.pi, np.pi, fire.batch)
        a, b = step_a(a, draws_a, wind), step_b(b, draws_b, wind)
        assert_same_fire(a, b, fields)
        assert draws_a.bit_generator.state == draws_b.bit_generator.state


def assert_spent_is_true(state: FireState, radius: int) -> None:
    """Every burning tree marked spent for a radius >= ``radius`` has no existing tree in its block."""
    cells = state.cells
    world, inside = np.divmod(state.burning, cells * cells)
    row, col = np.divmod(inside, cells)
    for w, r, c, spent in zip(world, row, col, state.spent):
        if spent >= radius:
            block = state.trees[w, max(r - spent, 0):r + spent + 1, max(c - spent, 0):c + spent + 1]
            assert not np.any(block == TreeState.EXISTING)


@settings(max_examples=60, deadline=None)
@given(fires())
def test_skipping_spent_trees_changes_nothing(fire):
    batch, cells, spec, seed = fire
    rng = np.random.default_rng(seed)
    exists, ignite = random_forest(rng, batch, cells)
    tracked = fire_reset(exists, ignite)
    fresh = fire_copy(tracked)
    heights, conditions = heights_and_weather(rng, batch, cells)
    draws_a, draws_b = np.random.default_rng(seed + 1), np.random.default_rng(seed + 1)
    for step in range(12):
        wind = rng.uniform(-np.pi, np.pi, batch)
        tracked = fire_step(tracked, draws_a, spec, wind, heights, conditions)
        fresh = fire_step(forget_spent(fresh), draws_b, spec, wind, heights, conditions)
        assert_same_fire(tracked, fresh)
        assert draws_a.bit_generator.state == draws_b.bit_generator.state
        assert_spent_is_true(tracked, spec.spread_radius_cells)
        if step == 5:  # a drop and a partial reset keep the spent marks aligned with the list
            points = rng.uniform(0, cells, (2, 3))
            world, owner = rng.integers(0, batch, 3), np.arange(3)
            tracked, *_ = douse(tracked, world, points[0], points[1], 1.5, owner, 3)
            fresh, *_ = douse(fresh, world, points[0], points[1], 1.5, owner, 3)
            mask = rng.random(batch) < 0.5
            new_exists, new_ignite = random_forest(rng, int(mask.sum()), cells)
            tracked = fire_reset_where(tracked, mask, new_exists, new_ignite)
            fresh = fire_reset_where(fresh, mask, new_exists, new_ignite)
            assert len(tracked.spent) == len(tracked.burning)


def test_a_smaller_radius_uses_marks_of_a_larger_one_but_not_the_reverse():
    trees = np.full((1, 9, 9), TreeState.BURNT, np.uint8)
    trees[0, 4, 4] = TreeState.BURNING
    trees[0, 4, 7] = TreeState.EXISTING  # 3 cells away: inside a radius-3 block only
    state = fire_reset(trees != TreeState.NONE, trees == TreeState.BURNING)
    state.trees[...] = trees
    certain = FireSpec(spread_radius_cells=1, spread_chance_per_factor=1.0, burn_steps=100)
    level, rng = np.zeros((1, 9, 9), np.float32), np.random.default_rng(0)
    hot = lambda w, r, c: (np.ones(len(w)), np.zeros(len(w)), np.zeros(len(w)))  # noqa: E731
    state = fire_step(state, rng, certain, np.zeros(1), level, hot)
    assert state.spent.tolist() == [1]  # nothing existing within one cell
    wide = certain.model_copy(update={"spread_radius_cells": 3})
    state = fire_step(state, rng, wide, np.zeros(1), level, hot)
    assert state.trees[0, 4, 7] == TreeState.BURNING  # the radius-1 mark did not hide the wider block


def grid_conditions(rng, batch, cells, grid):
    """A (B, G, G, 3) float32 weather grid, its nearest-cell callable and its FactorGrid for ``spec``."""
    values = rng.random((batch, grid, grid, 3)).astype(np.float32)
    lookup = (np.arange(cells) * grid) // cells

    def read(world, rows, cols):
        at = values[world, lookup[rows], lookup[cols]]
        return at[:, 0], at[:, 1], at[:, 2]

    return values, lookup, read


@settings(max_examples=40, deadline=None)
@given(fires(), st.integers(1, 4))
def test_a_factor_grid_gives_the_fire_of_the_conditions_callable(fire, grid):
    batch, cells, spec, seed = fire
    rng = np.random.default_rng(seed)
    fire = fire_reset(*random_forest(rng, batch, cells))
    heights = rng.normal(size=(batch, cells, cells)).astype(np.float32)
    values, lookup, read = grid_conditions(rng, batch, cells, min(grid, cells))
    factors = FactorGrid(count_factors(values, spec), grid_cell_table(lookup, min(grid, cells)))
    assert_lockstep(lambda f, draws, wind: fire_step(f, draws, spec, wind, heights, read),
                    lambda f, draws, wind: fire_step(f, draws, spec, wind, heights, factors),
                    fire, rng, seed, steps=8)


@settings(max_examples=30, deadline=None)
@given(fires())
def test_int64_pairs_of_short_lists_match_int32_pairs(fire):
    batch, cells, spec, seed = fire
    rng = np.random.default_rng(seed)
    exists, ignite = random_forest(rng, batch, cells)
    states = [fire_reset(exists, ignite) for _ in range(2)]
    heights, conditions = heights_and_weather(rng, batch, cells)
    draws = [np.random.default_rng(seed + 1) for _ in range(2)]
    saved = spread_module.SHORT_LIST
    try:
        for _ in range(6):
            wind = rng.uniform(-np.pi, np.pi, batch)
            for i, short in enumerate((10**9, -1)):  # every list short (int64), none short (int32)
                spread_module.SHORT_LIST = short
                states[i] = fire_step(states[i], draws[i], spec, wind, heights, conditions)
            assert_same_fire(*states)
    finally:
        spread_module.SHORT_LIST = saved


@pytest.mark.parametrize("order", ["ignition", "shuffled"])
def test_burn_out_by_slices_matches_the_gathers(order):
    rng = np.random.default_rng(3)
    age = np.sort(rng.integers(0, 6, 40))[::-1].astype(np.int32)  # ignition order: the oldest first
    if order == "shuffled":
        rng.shuffle(age)
    trees = np.zeros((1, 8, 8), np.uint8)
    burning = rng.choice(64, 40, replace=False).astype(np.int64)
    trees.reshape(-1)[burning] = TreeState.BURNING
    state = FireState(trees=trees, burning=burning, age=age, quiet=np.zeros(1, np.int32), out=np.zeros(1, bool),
                      ignited=np.zeros(1, np.int64), burnt_out=np.zeros(1, np.int64),
                      spent=rng.integers(0, 3, 40).astype(np.uint8))
    ended, rest, older, spent = spread_module._burn_out(state, state.spent, 5)
    done = age + 1 >= 5
    for got, expected in ((ended, burning[done]), (rest, burning[~done]), (older, age[~done] + 1),
                          (spent, state.spent[~done])):
        np.testing.assert_array_equal(got, expected)


def test_spent_must_follow_the_burning_list():
    state = fire_reset(np.ones((1, 3, 3), bool), np.eye(3, dtype=bool)[None])
    with pytest.raises(ValueError, match="spent"):
        FireState(trees=state.trees, burning=state.burning, age=state.age, quiet=state.quiet, out=state.out,
                  ignited=state.ignited, burnt_out=state.burnt_out, spent=np.zeros(2, np.uint8))
    assert state.spent.tolist() == [0, 0, 0] and len(block_offsets(1)[0]) == 8


@settings(max_examples=200, deadline=None)
@given(st.integers(0, 30), st.booleans(), st.integers(0, 3), st.integers(0, 3), st.integers(0, 4), st.integers(1, 6))
def test_the_one_world_tally_matches_the_general_one(quiet, out, ignitions, burnt, older, quiet_steps_out):
    if out:  # a world that is out has nothing burning, so nothing ignites there
        ignitions, older = 0, 0
    new, ended = np.arange(ignitions, dtype=np.int64), np.arange(burnt, dtype=np.int64) + 8
    burning = np.arange(older + ignitions, dtype=np.int64)
    state = FireState(trees=np.zeros((1, 4, 4), np.uint8), burning=np.zeros(0, np.int64), age=np.zeros(0, np.int32),
                      quiet=np.array([quiet], np.int32), out=np.array([out]), ignited=np.zeros(1, np.int64),
                      burnt_out=np.zeros(1, np.int64))
    args = (state, ignitions, burnt, burning, quiet_steps_out, new, ended)
    for one, general in zip(spread_module._tally_one(*args), spread_module._tally(*args)):
        assert one.dtype == general.dtype and one.shape == general.shape
        np.testing.assert_array_equal(one, general)


@pytest.mark.parametrize("wind, batch", [
    (np.array([0.5]), 1), (np.array([0.5, -3.0]), 2), (np.zeros(2, np.float32), 2), ([0.25], 1), (np.array([0.5]), 2),
    (np.array([np.nan]), 1), (np.array([0.0, np.inf]), 2), (np.array([1e308, 1e308]), 2), (np.zeros((1, 1)), 1)])
def test_the_wind_check_accepts_what_the_general_check_accepts(wind, batch):
    try:
        expected = engine_module.vector("downwind_rad", wind, batch)
    except ValueError:
        with pytest.raises(ValueError):
            spread_module._checked_wind(wind, batch)
        return
    np.testing.assert_array_equal(spread_module._checked_wind(wind, batch), expected)


@settings(max_examples=60, deadline=None)
@given(fires(), st.booleans())
def test_the_unchecked_step_is_the_checked_step(fire, factor_grid):
    batch, cells, spec, seed = fire
    rng = np.random.default_rng(seed)
    fire = fire_reset(*random_forest(rng, batch, cells))
    height = rng.normal(size=(batch, cells, cells)).astype(np.float32)
    if factor_grid:
        conditions = FactorGrid(count_factors(rng.random((batch, 4, 4, 3)).astype(np.float32), spec),
                                grid_cell_table(np.arange(cells) * 4 // cells, 4))
    else:
        fields = rng.random((3, batch, cells, cells))
        conditions = lambda w, r, c: tuple(f[w, r, c] for f in fields)  # noqa: E731
    assert_lockstep(lambda f, draws, wind: fire_step(f, draws, spec, wind, height, conditions),
                    lambda f, draws, wind: fire_step_unchecked(f, draws, spec, wind, height, conditions),
                    fire, rng, seed, steps=15, fields=tuple(FireState.__dataclass_fields__))


def test_the_one_world_tally_keeps_unchanged_arrays_with_their_dtypes():
    rng = np.random.default_rng(3)
    exists = np.ones((1, 6, 6), bool)
    fire = fire_reset(exists, np.zeros_like(exists))  # nothing burns: the counter grows, then the fire is out
    spec = FireSpec(quiet_steps_out=2)
    height = np.zeros((1, 6, 6), np.float32)
    conditions = lambda w, r, c: (np.zeros(len(w)),) * 3  # noqa: E731
    for quiet, out in ((1, False), (2, True), (2, True)):
        fire = fire_step(fire, rng, spec, np.zeros(1), height, conditions)
        assert fire.quiet.tolist() == [quiet] and fire.out.tolist() == [out]
        assert fire.quiet.dtype == np.int32 and fire.out.dtype == np.bool_


@settings(max_examples=60, deadline=None)
@given(st.integers(1, 4), st.integers(3, 10), st.integers(0, 2**32 - 1))
def test_putting_fresh_fires_is_resetting_from_their_grids(batch, cells, seed):
    rng = np.random.default_rng(seed)
    exists = rng.random((batch, cells, cells)) < 0.7
    fire = fire_reset(exists, exists & (rng.random(exists.shape) < 0.2))
    spec, height = FireSpec(), rng.normal(size=exists.shape).astype(np.float32)
    conditions = lambda w, r, c: (np.ones(len(w)), np.zeros(len(w)), np.zeros(len(w)))  # noqa: E731
    for _ in range(3):
        fire = fire_step(fire, rng, spec, rng.uniform(-np.pi, np.pi, batch), height, conditions)
    mask = rng.random(batch) < 0.5
    new_exists = rng.random((int(mask.sum()), cells, cells)) < 0.6
    fresh = fire_reset(new_exists, new_exists & (rng.random(new_exists.shape) < 0.2))
    by_grids = fire_reset_where(fire_copy(fire), mask, fresh.trees != TreeState.NONE,
                                fresh.trees == TreeState.BURNING)
    assert_same_fire(fire_put_worlds(fire_copy(fire), mask, fresh), by_grids, tuple(FireState.__dataclass_fields__))


def test_putting_fresh_fires_checks_the_mask_and_the_worlds():
    fire = fire_reset(np.ones((2, 4, 4), bool), np.zeros((2, 4, 4), bool))
    fresh = fire_reset(np.ones((1, 4, 4), bool), np.zeros((1, 4, 4), bool))
    with pytest.raises(ValueError, match="mask"):
        fire_put_worlds(fire, np.array([1, 0]), fresh)
    with pytest.raises(ValueError, match="masked worlds"):
        fire_put_worlds(fire, np.array([True, True]), fresh)
