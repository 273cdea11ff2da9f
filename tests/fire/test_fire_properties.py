"""Invariants of ``hivex_dsl.sim.fire`` over random sequences of fire steps, water drops and resets.

After every call: the burning list is exactly the set of BURNING cells (no duplicates), ages are
below burn_steps, no tree marked spent has an existing tree in its block, trees only move forward
(existing -> burning -> burnt, existing or burning -> wet), so the number of trees of each world is
conserved; the counters match the changes; a world that is out has nothing burning and stays out
until it is reset.
"""

from __future__ import annotations

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

from hivex_dsl.sim.fire import FireSpec, TreeState, burning_count, douse, fire_reset, fire_reset_where, fire_step

E, B, X, W = TreeState.EXISTING, TreeState.BURNING, TreeState.BURNT, TreeState.WET
FORWARD = {(E, B), (B, X), (E, W), (B, W)}  # every allowed change of one cell
OPS = st.sampled_from(["step", "step", "step", "douse", "reset"])


def check_consistent(state, spec, trees_per_world):
    assert len(np.unique(state.burning)) == len(state.burning)
    assert sorted(state.burning.tolist()) == np.flatnonzero(state.trees == B).tolist()
    assert np.all((state.age >= 0) & (state.age < spec.burn_steps))
    assert state.trees.max() <= TreeState.WET
    assert np.count_nonzero(state.trees, axis=(1, 2)).tolist() == trees_per_world.tolist()
    assert np.all(burning_count(state)[state.out] == 0)
    assert len(state.spent) == len(state.burning)
    cells = state.cells
    for flat, spent in zip(state.burning, state.spent):  # a tree marked spent has nothing left to try
        if spent:
            world, row, col = flat // (cells * cells), flat % (cells * cells) // cells, flat % cells
            block = state.trees[world, max(row - spent, 0):row + spent + 1, max(col - spent, 0):col + spent + 1]
            assert not np.any(block == E)


def check_forward(before, after, worlds):
    """Every cell of ``worlds`` kept its state or moved one allowed step."""
    changed = before[worlds] != after[worlds]
    moves = set(zip(before[worlds][changed].tolist(), after[worlds][changed].tolist()))
    assert moves <= FORWARD


@st.composite
def scenarios(draw):
    batch, cells = draw(st.integers(1, 3)), draw(st.integers(3, 9))
    spec = FireSpec(spread_radius_cells=draw(st.integers(1, 3)), spread_chance_per_factor=draw(st.sampled_from([0.0, 0.2, 0.5, 1.0])),
                    downwind_cone_deg=draw(st.sampled_from([0.0, 45.0, 90.0, 180.0])), burn_steps=draw(st.integers(1, 4)),
                    quiet_steps_out=draw(st.integers(1, 6)))
    return batch, cells, spec, draw(st.integers(0, 2**32 - 1)), draw(st.lists(OPS, min_size=1, max_size=25))


def random_forest(rng, worlds, cells):
    exists = rng.random((worlds, cells, cells)) < rng.uniform(0.3, 1.0)
    return exists, exists & (rng.random(exists.shape) < 0.15)


@settings(max_examples=80, deadline=None)
@given(scenarios())
def test_random_sequences_keep_the_fire_consistent(scenario):
    batch, cells, spec, seed, ops = scenario
    rng = np.random.default_rng(seed)
    exists, ignite = random_forest(rng, batch, cells)
    state = fire_reset(exists, ignite)
    trees_per_world = np.count_nonzero(exists, axis=(1, 2))
    heights = rng.normal(size=(batch, cells, cells)).astype(np.float32)
    fields = rng.random((3, batch, cells, cells))
    conditions = lambda w, r, c: tuple(f[w, r, c] for f in fields)  # noqa: E731
    check_consistent(state, spec, trees_per_world)
    for op in ops:
        before, was_out, quiet = state.trees.copy(), state.out.copy(), state.quiet.copy()
        everywhere = np.ones(batch, bool)
        if op == "step":
            state = fire_step(state, rng, spec, rng.uniform(-np.pi, np.pi, batch), heights, conditions)
            ignited = np.count_nonzero((before == E) & (state.trees == B), axis=(1, 2))
            burnt = np.count_nonzero((before == B) & (state.trees == X), axis=(1, 2))
            assert state.ignited.tolist() == ignited.tolist() and state.burnt_out.tolist() == burnt.tolist()
            assert np.all(state.out[was_out]) and np.all(state.quiet[was_out] == quiet[was_out])
            np.testing.assert_array_equal(state.trees[was_out], before[was_out])  # out worlds do nothing
            assert not np.any((before == E) & (state.trees == W)) and not np.any((before == B) & (state.trees == W))
        elif op == "douse":
            points = int(rng.integers(0, 5))
            owner = rng.integers(0, 2 * batch, points)
            state, extinguished, prepared = douse(state, owner // 2, rng.uniform(-2, cells + 2, points),
                                                  rng.uniform(-2, cells + 2, points), float(rng.uniform(0, 3)), owner,
                                                  2 * batch)
            assert extinguished.sum() == np.count_nonzero((before == B) & (state.trees == W))
            assert prepared.sum() == np.count_nonzero((before == E) & (state.trees == W))
            assert np.all(state.quiet == quiet) and np.all(state.out == was_out)
        else:
            mask = rng.random(batch) < 0.5
            fresh_exists, fresh_ignite = random_forest(rng, int(mask.sum()), cells)
            state = fire_reset_where(state, mask, fresh_exists, fresh_ignite)
            trees_per_world[mask] = np.count_nonzero(fresh_exists, axis=(1, 2))
            np.testing.assert_array_equal(state.trees[~mask], before[~mask])
            assert not state.out[mask].any() and np.all(state.quiet[mask] == 0)
            everywhere = ~mask
        check_forward(before, state.trees, everywhere)
        check_consistent(state, spec, trees_per_world)


def factors_brute_force(spec, source, target, wind, heights, fields):
    """n for one (source, target) pair of cells (row, col), from the rule's wording."""
    (sr, sc), (tr, tc) = source, target
    dx, dy = tc - sc, tr - sr  # columns run along x, rows along y
    cosine = (dx * np.cos(wind) + dy * np.sin(wind)) / np.hypot(dx, dy)
    downwind = cosine >= np.cos(np.radians(spec.downwind_cone_deg))
    uphill = heights[tr, tc] > heights[sr, sc]
    temperature, humidity, overcast = (f[sr, sc] for f in fields)
    return int(downwind) + int(uphill) + int(temperature > spec.hot_temperature) + int(
        humidity < spec.dry_humidity) + int(overcast < spec.low_overcast)


@settings(max_examples=60, deadline=None)
@given(st.integers(3, 8), st.integers(1, 3), st.sampled_from([1.0, 0.5, 1.0 / 3.0, 0.25, 0.2]),
       st.floats(0.0, 180.0), st.floats(-np.pi, np.pi), st.integers(0, 2**32 - 1))
def test_certain_and_impossible_ignitions_match_the_rule(cells, radius, chance, cone, wind, seed):
    """Targets some burning tree tries with n >= 1 / chance always ignite; those every try gives n = 0 never do."""
    rng = np.random.default_rng(seed)
    exists = rng.random((1, cells, cells)) < 0.8
    state = fire_reset(exists, exists & (rng.random(exists.shape) < 0.3))
    heights = rng.integers(0, 3, (1, cells, cells)).astype(np.float32)  # equal heights happen: not uphill
    fields = rng.choice([0.2, 0.8], (3, cells, cells))
    spec = FireSpec(spread_radius_cells=radius, spread_chance_per_factor=chance, downwind_cone_deg=cone)
    before = state.trees[0].copy()
    sources = list(zip(*np.nonzero(before == B)))
    state = fire_step(state, rng, spec, np.array([wind]), heights,
                      lambda w, r, c: tuple(f[r, c] for f in fields))
    for target in zip(*np.nonzero(before == E)):
        tries = [factors_brute_force(spec, s, target, wind, heights[0], fields) for s in sources
                 if max(abs(s[0] - target[0]), abs(s[1] - target[1])) <= radius]
        if tries and max(tries) * chance >= 1.0 - 1e-12:
            assert state.trees[0][target] == B, (target, tries)
        if not any(tries):
            assert state.trees[0][target] == E, (target, tries)
