"""Spread, burn-out, the end of the fire and resets of ``hivex_dsl.sim.fire`` on hand-drawn grids.

The rule (ENVIRONMENTS.md, AWS "Spread"): each burning tree tries each existing tree of its 5x5
block with probability min(1, 0.2 x n), n = [downwind within 45 deg] + [uphill] + [hot] + [dry] +
[overcast low]. Probabilities are forced to 0 or 1 by the choice of weather, wind, heights and
chance per factor, so the exact outcome is known by hand; the rest is checked statistically.
Grids are drawn as strings, row 0 first (rows run along y, columns along x): '.' no tree,
'T' a tree, 'B' a tree burning at reset.
"""

from __future__ import annotations

import numpy as np
import pytest
from pydantic import ValidationError

from hivex_dsl.sim.fire import (
    FireSpec, TreeState, burning_count, cell_coords, cell_xy, fire_reset, fire_reset_where, fire_step, length_in_cells,
)
from hivex_dsl.sim.procgen.forest import ForestSpec, cell_centres

SYMBOLS = {".": TreeState.NONE, "T": TreeState.EXISTING, "B": TreeState.BURNING}
FULL_7 = ["TTTTTTT"] * 3 + ["TTTBTTT"] + ["TTTTTTT"] * 3  # a burning tree amid a full 7x7 forest
EMPTY_FIRE_7 = ["T.T.T.T", ".T.T.T.", "TT..TTT", "...T...", "T.T.T.T", "TTTTTTT", "......."]  # no fire


def drawn(*worlds):
    return np.array([[[SYMBOLS[ch] for ch in line] for line in world] for world in worlds], dtype=np.uint8)


def reset(*worlds):
    trees = drawn(*worlds)
    return fire_reset(trees != TreeState.NONE, trees == TreeState.BURNING)


def weather(temperature, humidity, overcast, calls=None):
    def conditions(world, row, col):
        if calls is not None:
            calls.append((world.copy(), row.copy(), col.copy()))
        return np.full(len(world), temperature), np.full(len(world), humidity), np.full(len(world), overcast)
    return conditions


HOT_DRY_LOW = weather(1.0, 0.0, 0.0)  # the three weather factors hold
MILD = weather(0.0, 1.0, 1.0)  # none holds
NO_WIND_CONE = {"downwind_cone_deg": 0.0}  # with a 10 degree wind no offset of the block is downwind
WIND_10 = np.radians(10.0)


def level(batch, cells):
    return np.zeros((batch, cells, cells), np.float32)


def bowl(batch, cells):
    span = (np.arange(cells) - cells // 2) ** 2
    return np.broadcast_to(np.add.outer(span, span).astype(np.float32), (batch, cells, cells)).copy()


def ramp(batch, cells, axis):
    """Height = column (axis 1, east) or row (axis 0, north)."""
    grid = np.indices((cells, cells))[axis].astype(np.float32)
    return np.broadcast_to(grid, (batch, cells, cells)).copy()


def step(state, spec, wind, heights, conditions, seed=0):
    wind = np.broadcast_to(np.asarray(wind, float), (state.batch,)).copy()
    return fire_step(state, np.random.default_rng(seed), spec, wind, heights, conditions)


def cells(grid, value):
    return {(int(r), int(c)) for r, c in zip(*np.nonzero(grid == value))}


def around(centre, offsets):
    return {(centre[0] + dr, centre[1] + dc) for dr, dc in offsets}


BLOCK = [(dr, dc) for dr in range(-2, 3) for dc in range(-2, 3) if (dr, dc) != (0, 0)]


def test_five_factors_ignite_the_whole_block_and_a_world_without_fire_is_untouched():
    state = reset(FULL_7, EMPTY_FIRE_7)
    before = state.trees[1].copy()
    spec = FireSpec(downwind_cone_deg=180.0)  # every target downwind; the bowl makes every target uphill
    state = step(state, spec, 0.3, bowl(2, 7), HOT_DRY_LOW)
    expected = drawn(FULL_7)[0]
    expected[1:6, 1:6] = TreeState.BURNING  # 0.2 x 5 = 1: all 24 neighbours within 2 cells
    np.testing.assert_array_equal(state.trees[0], expected)
    np.testing.assert_array_equal(state.trees[1], before)
    block = [r * 7 + c for r in range(1, 6) for c in range(1, 6) if (r, c) != (3, 3)]
    assert state.burning.tolist() == [3 * 7 + 3] + block  # the old tree first, then new ones by flat index
    assert state.age.tolist() == [1] + [0] * 24
    assert state.ignited.tolist() == [24, 0] and state.burnt_out.tolist() == [0, 0]
    assert burning_count(state).tolist() == [25, 0]


def test_no_factor_no_spread_ever():
    state = reset(FULL_7)
    for seed in range(15):
        state = step(state, FireSpec(**NO_WIND_CONE), WIND_10, level(1, 7), MILD, seed)
    expected = drawn(FULL_7)[0]
    expected[3, 3] = TreeState.BURNT
    np.testing.assert_array_equal(state.trees[0], expected)
    assert len(state.burning) == 0 and state.out.tolist() == [True]


@pytest.mark.parametrize(("wind_deg", "downwind"), [
    (0.0, [(0, 1), (0, 2), (1, 1), (-1, 1), (1, 2), (-1, 2), (2, 2), (-2, 2)]),  # east: |d_row| <= d_col
    (90.0, [(1, 0), (2, 0), (1, 1), (1, -1), (2, 1), (2, -1), (2, 2), (2, -2)]),  # north = +row (y)
    # 30 degrees: directions in [-15, 75] deg: 0 (0,1) (0,2), 26.6 (1,2), 45 (1,1) (2,2), 63.4 (2,1)
    (30.0, [(0, 1), (0, 2), (1, 2), (1, 1), (2, 2), (2, 1)]),
    (-135.0, [(-1, -1), (-2, -2), (-1, 0), (-2, 0), (0, -1), (0, -2), (-2, -1), (-1, -2)]),
])
def test_downwind_cone_is_counted_per_target(wind_deg, downwind):
    spec = FireSpec(spread_chance_per_factor=1.0)  # one factor suffices; only downwind can hold here
    state = step(reset(FULL_7), spec, np.radians(wind_deg), level(1, 7), MILD)
    assert cells(state.trees[0], TreeState.BURNING) == around((3, 3), downwind) | {(3, 3)}


@pytest.mark.parametrize(("axis", "uphill"), [
    (1, [(dr, dc) for dr, dc in BLOCK if dc > 0]),  # height = column: east is uphill, same column is not
    (0, [(dr, dc) for dr, dc in BLOCK if dr > 0]),
])
def test_uphill_is_counted_per_target_and_level_is_not_uphill(axis, uphill):
    spec = FireSpec(spread_chance_per_factor=1.0, **NO_WIND_CONE)
    state = step(reset(FULL_7), spec, WIND_10, ramp(1, 7, axis), MILD)
    assert cells(state.trees[0], TreeState.BURNING) == around((3, 3), uphill) | {(3, 3)}


@pytest.mark.parametrize("field", ["temperature", "humidity", "overcast"])
def test_each_weather_factor_alone_ignites_with_chance_one(field):
    values = {"temperature": (0.6, 1.0, 1.0), "humidity": (0.0, 0.4, 1.0), "overcast": (0.0, 1.0, 0.4)}[field]
    spec = FireSpec(spread_chance_per_factor=1.0, **NO_WIND_CONE)
    state = step(reset(FULL_7), spec, WIND_10, level(1, 7), weather(*values))
    assert cells(state.trees[0], TreeState.BURNING) == around((3, 3), BLOCK) | {(3, 3)}
    at_threshold = {"temperature": (0.5, 1.0, 1.0), "humidity": (0.0, 0.5, 1.0), "overcast": (0.0, 1.0, 0.5)}[field]
    state = step(reset(FULL_7), spec, WIND_10, level(1, 7), weather(*at_threshold))
    assert cells(state.trees[0], TreeState.BURNING) == {(3, 3)}  # strict comparisons: the threshold is not enough


def test_weather_is_read_at_the_burning_tree_not_the_target():
    grid = ["TTTTTTTTT"] * 9
    grid[1], grid[7] = "TBTTTTTTT", "TTTTTTTBT"  # burning trees at (1, 1) and (7, 7): their blocks do not meet
    calls = []

    def hot_except_at_7_7(world, row, col):
        calls.append((row.copy(), col.copy()))
        hot = np.where((row == 7) & (col == 7), 0.0, 1.0)
        return hot, np.ones(len(row)), np.ones(len(row))

    spec = FireSpec(spread_chance_per_factor=1.0, **NO_WIND_CONE)
    state = step(reset(grid), spec, WIND_10, level(1, 9), hot_except_at_7_7)
    # the tree at (1, 1) is hot: its block (clipped at the grid edge) ignites; (7, 7) is not, though its targets are
    assert cells(state.trees[0], TreeState.BURNING) == {(r, c) for r in range(0, 4) for c in range(0, 4)} | {(7, 7)}
    assert len(calls) == 1 and sorted(zip(calls[0][0].tolist(), calls[0][1].tolist())) == [(1, 1), (7, 7)]


def test_chance_per_factor_is_capped_at_one_and_scales_the_probability():
    worlds = 400
    state = reset(*[FULL_7] * worlds)
    spec = FireSpec(spread_chance_per_factor=0.5)  # downwind cells: hot + downwind = 2 -> 1; others: hot only -> 0.5
    state = step(state, spec, 0.0, level(worlds, 7), weather(1.0, 1.0, 1.0), seed=3)
    downwind = around((3, 3), [(0, 1), (0, 2), (1, 1), (-1, 1), (1, 2), (-1, 2), (2, 2), (-2, 2)])
    others = around((3, 3), BLOCK) - downwind
    burning = state.trees == TreeState.BURNING
    assert all(burning[:, r, c].all() for r, c in downwind)
    rate = np.mean([burning[:, r, c].mean() for r, c in others])
    assert abs(rate - 0.5) < 0.03  # 6,400 draws: standard error 0.006


def test_several_burning_trees_draw_independently():
    worlds = 10_000
    two = ["...", "BTB", "..."]  # the middle tree is tried by both: 1 - 0.8^2 = 0.36 (not 0.2, not 0.4)
    one = ["...", "BT.", "..."]
    spec = FireSpec(**NO_WIND_CONE)  # chance 0.2, one factor (hot)
    hot = weather(1.0, 1.0, 1.0)
    rate_two = (step(reset(*[two] * worlds), spec, WIND_10, level(worlds, 3), hot, 5).trees[:, 1, 1] == 2).mean()
    rate_one = (step(reset(*[one] * worlds), spec, WIND_10, level(worlds, 3), hot, 6).trees[:, 1, 1] == 2).mean()
    assert abs(rate_two - 0.36) < 0.02 and abs(rate_one - 0.2) < 0.02  # standard errors 0.005 and 0.004


def test_a_tree_burns_for_exactly_burn_steps_and_the_fire_goes_out_after_quiet_steps():
    spec = FireSpec(burn_steps=3, quiet_steps_out=5)
    state = reset(["...", ".B.", "..."], ["...", ".T.", "..."])
    history = []
    for _ in range(7):
        state = step(state, spec, 0.0, level(2, 3), HOT_DRY_LOW)
        history.append((int(state.trees[0, 1, 1]), state.age.tolist(), state.burnt_out[0], state.quiet[0], state.out[0]))
    assert history == [
        (TreeState.BURNING, [1], 0, 1, False),
        (TreeState.BURNING, [2], 0, 2, False),
        (TreeState.BURNT, [], 1, 3, False),
        (TreeState.BURNT, [], 0, 4, False),
        (TreeState.BURNT, [], 0, 5, True),
        (TreeState.BURNT, [], 0, 5, True),  # out worlds do nothing, the count stops
        (TreeState.BURNT, [], 0, 5, True),
    ]
    assert state.out.tolist() == [True, True]  # a world without fire goes out too


def test_the_fire_is_not_out_while_a_tree_still_burns():
    spec = FireSpec(burn_steps=6, quiet_steps_out=2)
    state = reset(["...", ".B.", "..."])
    outs = []
    for _ in range(7):
        state = step(state, spec, 0.0, level(1, 3), MILD)
        outs.append(bool(state.out[0]))
    assert outs == [False] * 5 + [True, True]  # quiet reached 2 at step 2, the tree burnt out at step 6


def test_each_ignition_restarts_the_quiet_count_and_joins_the_list_in_order():
    line = ["......."] * 3 + ["BTTTTTT"] + ["......."] * 3
    spec = FireSpec(spread_radius_cells=1, spread_chance_per_factor=1.0, **NO_WIND_CONE)
    state = reset(line)
    for k in range(1, 7):
        state = step(state, spec, WIND_10, ramp(1, 7, 1), MILD)  # only the eastern neighbour is uphill
        assert state.ignited.tolist() == [1] and state.quiet.tolist() == [0]
        assert state.burning.tolist() == [21 + c for c in range(k + 1)] and state.age.tolist() == list(range(k, -1, -1))
    state = step(state, spec, WIND_10, ramp(1, 7, 1), MILD)
    assert state.ignited.tolist() == [0] and state.quiet.tolist() == [1]


def test_same_seed_same_fire_different_seed_different_fire():
    rng = np.random.default_rng(11)
    exists = rng.random((2, 40, 40)) < 0.7
    ignite = np.zeros_like(exists)
    ignite[:, 18:22, 18:22] = exists[:, 18:22, 18:22]
    heights = rng.random((2, 40, 40)).astype(np.float32)
    spec = FireSpec()

    def run(seed):
        state, gen = fire_reset(exists, ignite), np.random.default_rng(seed)
        for _ in range(8):
            state = fire_step(state, gen, spec, np.array([0.5, 2.0]), heights, weather(0.7, 0.6, 0.6))
        return state

    first, again, other = run(1), run(1), run(2)
    np.testing.assert_array_equal(first.trees, again.trees)
    np.testing.assert_array_equal(first.burning, again.burning)
    np.testing.assert_array_equal(first.age, again.age)
    assert not np.array_equal(first.trees, other.trees)


def test_reset_where_replaces_only_the_masked_worlds():
    state = reset(FULL_7, EMPTY_FIRE_7, FULL_7)
    state = step(state, FireSpec(downwind_cone_deg=180.0), 0.0, bowl(3, 7), HOT_DRY_LOW)
    kept = state.trees[[0, 2]].copy()
    old_burning = state.burning.copy()
    fresh = drawn(["B......"] + ["......."] * 5 + ["......B"])
    state = fire_reset_where(state, np.array([False, True, False]), fresh != 0, fresh == TreeState.BURNING)
    np.testing.assert_array_equal(state.trees[[0, 2]], kept)
    np.testing.assert_array_equal(state.trees[1], fresh[0])
    assert state.burning.tolist() == old_burning.tolist() + [49, 49 + 48]  # others keep their order; then world 1
    assert state.age.tolist()[-2:] == [0, 0] and state.ignited.tolist() == [24, 2, 24]
    assert state.quiet.tolist() == [0, 0, 0] and not state.out.any()


def test_reset_rejects_fire_without_trees_and_wrong_shapes():
    exists = np.zeros((1, 3, 3), bool)
    with pytest.raises(ValueError, match="without a tree"):
        fire_reset(exists, np.ones((1, 3, 3), bool))
    with pytest.raises(ValueError, match="bool"):
        fire_reset(exists.astype(int), exists)
    state = fire_reset(exists, exists)
    with pytest.raises(ValueError, match=r"\(0, 3, 3\)"):
        fire_reset_where(state, np.array([False]), np.zeros((1, 3, 3), bool), np.zeros((1, 3, 3), bool))
    with pytest.raises(ValueError, match="downwind_rad"):
        fire_step(state, np.random.default_rng(0), FireSpec(), np.zeros(2), level(1, 3), MILD)
    with pytest.raises(ValueError, match="cell_height"):
        fire_step(state, np.random.default_rng(0), FireSpec(), np.zeros(1), level(1, 4), MILD)


@pytest.mark.parametrize("bad", [{"spread_radius_cells": 0}, {"spread_chance_per_factor": 1.5}, {"downwind_cone_deg": 181.0},
                                 {"hot_temperature": -0.1}, {"burn_steps": 0}, {"quiet_steps_out": 0}])
def test_spec_fields_are_bounded(bad):
    with pytest.raises(ValidationError):
        FireSpec(**bad)


def test_spec_defaults_and_tags():
    spec = FireSpec()
    assert (spec.spread_radius_cells, spec.spread_chance_per_factor, spec.downwind_cone_deg, spec.burn_steps,
            spec.quiet_steps_out) == (2, 0.2, 45.0, 10, 10)
    for name, field in FireSpec.model_fields.items():
        assert field.description.startswith(("[orig]", "[ours]", "[paper]")), name


def test_cell_coordinates_put_cell_centres_on_integers():
    spec = ForestSpec()
    centres = cell_centres(spec)  # x of column c / y of row r
    row, col = cell_coords(spec, centres[[0, 7, 399]], centres[[399, 200, 0]])
    np.testing.assert_allclose(row, [399, 200, 0], atol=1e-9)
    np.testing.assert_allclose(col, [0, 7, 399], atol=1e-9)
    np.testing.assert_allclose(cell_coords(spec, -600.0, 600.0), (399.5, -0.5))  # grid corners are half a cell out
    np.testing.assert_allclose(cell_xy(spec, 200.0, 7.0), (centres[7], centres[200]))
    assert length_in_cells(spec, 30.0) == 10.0 and length_in_cells(spec, 150.0) == 50.0
