"""The fire engine's entries for simulators that hold valid state give exactly the checked entries' fires.

fire_step_unchecked skips fire_step's argument checks; fire_put_worlds puts fresh fires (from fire_reset) into
masked worlds without rebuilding their tree grids, as fire_reset_where does from those grids.
"""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from hivex_dsl.fire import (FactorGrid, FireSpec, TreeState, count_factors, fire_copy, fire_put_worlds, fire_reset,
                            fire_reset_where, fire_step, fire_step_unchecked, grid_cell_table)


def assert_same(a, b) -> None:
    for name in a.__dataclass_fields__:
        np.testing.assert_array_equal(getattr(a, name), getattr(b, name), err_msg=name)
        assert getattr(a, name).dtype == getattr(b, name).dtype, name


@st.composite
def fires(draw):
    batch, cells = draw(st.integers(1, 3)), draw(st.integers(3, 12))
    spec = FireSpec(spread_radius_cells=draw(st.integers(1, 3)),
                    spread_chance_per_factor=draw(st.sampled_from([0.1, 0.2, 0.5, 1.0])),
                    downwind_cone_deg=draw(st.sampled_from([0.0, 45.0, 90.0, 180.0])),
                    burn_steps=draw(st.integers(1, 5)), quiet_steps_out=draw(st.integers(1, 6)))
    return batch, cells, spec, draw(st.integers(0, 2**32 - 1)), draw(st.booleans())


@settings(max_examples=60, deadline=None)
@given(fires())
def test_the_unchecked_step_is_the_checked_step(fire):
    batch, cells, spec, seed, factor_grid = fire
    rng = np.random.default_rng(seed)
    exists = rng.random((batch, cells, cells)) < rng.uniform(0.3, 1.0)
    checked = fire_reset(exists, exists & (rng.random(exists.shape) < 0.1))
    unchecked = fire_copy(checked)
    height = rng.normal(size=(batch, cells, cells)).astype(np.float32)
    if factor_grid:
        conditions = FactorGrid(count_factors(rng.random((batch, 4, 4, 3)).astype(np.float32), spec),
                                grid_cell_table(np.arange(cells) * 4 // cells, 4))
    else:
        fields = rng.random((3, batch, cells, cells))
        conditions = lambda w, r, c: tuple(f[w, r, c] for f in fields)  # noqa: E731
    draws_a, draws_b = np.random.default_rng(seed + 1), np.random.default_rng(seed + 1)
    for _ in range(15):
        wind = rng.uniform(-np.pi, np.pi, batch)
        checked = fire_step(checked, draws_a, spec, wind, height, conditions)
        unchecked = fire_step_unchecked(unchecked, draws_b, spec, wind, height, conditions)
        assert_same(checked, unchecked)
        assert draws_a.bit_generator.state == draws_b.bit_generator.state


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
    assert_same(fire_put_worlds(fire_copy(fire), mask, fresh), by_grids)


def test_putting_fresh_fires_checks_the_mask_and_the_worlds():
    fire = fire_reset(np.ones((2, 4, 4), bool), np.zeros((2, 4, 4), bool))
    fresh = fire_reset(np.ones((1, 4, 4), bool), np.zeros((1, 4, 4), bool))
    with pytest.raises(ValueError, match="mask"):
        fire_put_worlds(fire, np.array([1, 0]), fresh)
    with pytest.raises(ValueError, match="masked worlds"):
        fire_put_worlds(fire, np.array([True, True]), fresh)
