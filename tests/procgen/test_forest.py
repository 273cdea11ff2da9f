"""Forest placement and fire ignition of Aerial Wildfire Suppression (``hivex_dsl.sim.procgen.forest``).

Facts are re-derived here from ENVIRONMENTS.md: cell centres at -600 + 1.5 + 3k, the height rule
"10 <= h <= 100 and a uniform draw exceeds 2 |55 - h| / 100", and the ignition rule "among every
10th cell more than 300 m from the village, lowest humidity + (1 - temperature) + overcast first,
with its 5x5 block, until more than 15 trees burn".
"""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from pydantic import ValidationError

from hivex_dsl.envs.island import grid_lookup, ignition_of

from hivex_dsl.sim.procgen.forest import (
    ForestPreset, ForestSpec, IgnitionSpec, ignition_mask, load_forest_preset, place_forest, rank_ignition_cells,
    select_ignition,
)
from hivex_dsl.sim.procgen.presets import load_preset

SPEC = ForestSpec()
IGNITION = IgnitionSpec()
FAR_AWAY = np.array([5000.0, 5000.0])  # a village that clears nothing
SMALL = ForestSpec(cells=40, spacing_m=3.0, half_extent_m=60.0, village_clear_radius_m=20.0)


def ramp(xy: np.ndarray) -> np.ndarray:
    """0 m at the west edge (x = -600) rising to 120 m at the east edge."""
    return 0.1 * (xy[:, 0] + 600.0)


def flat(height: float):
    return lambda xy: np.full(len(xy), height)


def forest(seed=0, spec=SPEC, height_at=ramp, village=(0.0, 0.0)):
    return place_forest(np.random.default_rng(seed), spec, height_at, np.asarray(village))


def cell_of(points: np.ndarray, spec: ForestSpec = SPEC) -> np.ndarray:
    """(row, col) of the cell holding each point, from the geometry alone."""
    return np.floor((points[:, ::-1] + spec.half_extent_m) / spec.spacing_m).astype(int)


# --- preset and spec ---------------------------------------------------------------------------


def test_preset_equals_code_defaults():
    preset = load_preset("forest.yaml", ForestPreset)
    assert preset.forest == ForestSpec() and preset.ignition == IgnitionSpec()
    assert (SPEC.cells, SPEC.spacing_m, SPEC.half_extent_m, SPEC.jitter_m) == (400, 3.0, 600.0, 1.5)
    assert (IGNITION.candidate_stride, IGNITION.min_village_distance_m, IGNITION.block, IGNITION.min_burning) == (10, 300.0, 5, 15)


@pytest.mark.parametrize("model, kwargs, words", [
    (ForestSpec, {"cells": 399}, r"must equal 2 \* half_extent_m"),
    (ForestSpec, {"jitter_m": 1.6}, "stays inside its cell"),
    (ForestSpec, {"ideal_height_m": 120.0}, "min_height_m <= ideal_height_m <= max_height_m"),
    (ForestSpec, {"cells": "400"}, "valid integer"),
    (IgnitionSpec, {"block": 4}, "must be odd"),
    (IgnitionSpec, {"block": 11}, "never overlap"),
    (IgnitionSpec, {"candidate_stride": 0}, "greater than or equal to 1"),
])
def test_specs_refuse_inconsistent_values(model, kwargs, words):
    with pytest.raises(ValidationError, match=words):
        model(**kwargs)


def test_every_field_has_a_source_tag():
    for model in (ForestSpec, IgnitionSpec):
        for name, field in model.model_fields.items():
            assert field.description.startswith(("[orig] ", "[ours] ")), name


# --- placement ---------------------------------------------------------------------------------


def test_same_seed_same_forest_other_seed_other_forest():
    a, b, c = forest(7), forest(7), forest(8)
    for name in ("positions", "heights", "cell_index", "grid"):
        np.testing.assert_array_equal(getattr(a, name), getattr(b, name))
    assert a.count != c.count or not np.array_equal(a.positions, c.positions)


def test_trees_obey_the_height_rule_and_the_village_clearing():
    village = np.array([30.0, -40.0])  # 63 m high on the ramp: dense forest all around
    f = forest(1, village=village)
    heights = ramp(f.positions)
    np.testing.assert_allclose(f.heights, heights)
    assert f.count > 10_000
    assert heights.min() >= 10.0 and heights.max() <= 100.0
    distance = np.hypot(*(f.positions - village).T)
    assert distance.min() > 100.0
    assert np.count_nonzero(distance < 110.0) > 50  # the clearing stops at 100 m


def test_grid_cells_and_jitter_are_consistent():
    f = forest(2)
    assert f.positions.shape == (f.count, 2) and f.positions.dtype == np.float64
    assert f.grid.shape == (400, 400) and f.grid.dtype == np.int32
    np.testing.assert_array_equal(f.grid[f.cell_index[:, 0], f.cell_index[:, 1]], np.arange(f.count))
    assert np.count_nonzero(f.grid >= 0) == f.count
    centre_xy = -600.0 + 1.5 + 3.0 * f.cell_index[:, ::-1]
    offset = f.positions - centre_xy
    assert np.abs(offset).max() <= 1.5 and np.abs(offset).max() > 1.45  # uniform in +/-1.5 m
    np.testing.assert_array_equal(cell_of(f.positions), f.cell_index)


@pytest.mark.parametrize("height, density", [(55.0, 1.0), (30.0, 0.5), (80.0, 0.5), (100.0, 0.1),
                                             (9.9, 0.0), (100.1, 0.0)])
def test_density_on_flat_terrain_follows_the_rule(height, density):
    f = forest(3, height_at=flat(height), village=FAR_AWAY)
    # 160 000 cells: binomial standard deviation at most 0.00125
    assert f.count / 400**2 == pytest.approx(density, abs=0.006)


def test_forest_is_densest_around_55_m():
    f = forest(4, village=FAR_AWAY)
    per_metre, _ = np.histogram(ramp(f.positions), bins=np.arange(0.0, 121.0))
    assert 45 <= int(np.argmax(per_metre)) <= 65
    assert per_metre[55] > 2.5 * per_metre[20] and per_metre[55] > 2.5 * per_metre[90]
    assert per_metre[:10].sum() == 0 and per_metre[100:].sum() == 0


def test_bad_inputs_are_refused():
    rng = np.random.default_rng(0)
    with pytest.raises(ValueError, match="village_xy must be a finite"):
        place_forest(rng, SMALL, flat(55.0), np.zeros(3))
    with pytest.raises(ValueError, match="height_at must map"):
        place_forest(rng, SMALL, lambda xy: np.zeros(5), np.zeros(2))
    f = forest(0, spec=SMALL)
    with pytest.raises(ValueError, match="tree_ids must lie in"):
        f.neighbours_within(np.array([f.count]), 5.0)
    with pytest.raises(ValueError, match="1-D integer array"):
        f.neighbours_within(np.array([0.0]), 5.0)
    with pytest.raises(ValueError, match="radius_m must be"):
        f.trees_near(np.zeros((1, 2)), -1.0)
    with pytest.raises(ValueError, match=r"\(P, 2\)"):
        f.trees_near(np.zeros(2), 1.0)


# --- neighbourhood queries against brute force -------------------------------------------------


def as_matrix(ids: np.ndarray, within: np.ndarray, columns: int) -> np.ndarray:
    """Boolean (M, columns) relation from a query result; asserts no tree is listed twice."""
    rows = np.nonzero(within)[0]
    relation = np.zeros((len(ids), columns), dtype=int)
    np.add.at(relation, (rows, ids[within]), 1)
    assert relation.max(initial=0) <= 1
    return relation.astype(bool)


@pytest.mark.parametrize("radius", [0.0, 2.0, 3.0, 4.5, 10.0, 17.3])
def test_neighbours_within_matches_brute_force(radius):
    f = forest(5, spec=SMALL, height_at=flat(45.0))  # density 0.8 with a 20 m clearing
    ids, within = f.neighbours_within(np.arange(f.count), radius)
    assert ids.shape == within.shape and ids.shape[0] == f.count
    assert np.all(ids[within] >= 0)
    gaps = np.linalg.norm(f.positions[:, None] - f.positions[None], axis=-1)
    expected = (gaps <= radius) & ~np.eye(f.count, dtype=bool)
    np.testing.assert_array_equal(as_matrix(ids, within, f.count), expected)


@pytest.mark.parametrize("radius", [0.5, 3.0, 10.0, 30.0])
def test_trees_near_matches_brute_force(radius):
    f = forest(6, spec=SMALL, height_at=flat(45.0))
    points = np.random.default_rng(9).uniform(-80.0, 80.0, (300, 2))  # some off the grid
    ids, within = f.trees_near(points, radius)
    gaps = np.linalg.norm(points[:, None] - f.positions[None], axis=-1)
    np.testing.assert_array_equal(as_matrix(ids, within, f.count), gaps <= radius)


def test_subset_queries_and_empty_queries():
    f = forest(5, spec=SMALL, height_at=flat(45.0))
    pick = np.array([3, 0, 3])
    ids, within = f.neighbours_within(pick, 6.0)
    full_ids, full_within = f.neighbours_within(np.arange(f.count), 6.0)
    np.testing.assert_array_equal(ids, full_ids[pick])
    np.testing.assert_array_equal(within, full_within[pick])
    assert f.neighbours_within(np.array([], dtype=int), 6.0).ids.shape[0] == 0
    empty = forest(0, spec=SMALL, height_at=flat(0.0))
    assert empty.count == 0 and not empty.trees_near(np.zeros((2, 2)), 50.0).within.any()


# --- ignition ----------------------------------------------------------------------------------

DRIEST = (50, 180)  # centre (-58.5, -448.5): 54 m on the ramp, 452 m from a village at (0, 0)


def weather(driest=DRIEST, score_ramp=True):
    """Hand-built weather with a known driest cell; elsewhere scores rise with row then col."""
    n = SPEC.cells
    rows, cols = np.meshgrid(np.arange(n), np.arange(n), indexing="ij")
    humidity = 0.5 + (0.4 * (rows * n + cols) / n**2 if score_ramp else np.zeros((n, n)))
    temperature = np.full((n, n), 0.5)
    overcast = np.full((n, n), 0.5)
    humidity[driest] = 0.0
    temperature[driest] = 1.0
    overcast[driest] = 0.0
    return temperature, humidity, overcast


def reference_ignition(f, village, temperature, humidity, overcast):
    """The rule in plain Python over candidate cells, with tree cells found from positions."""
    centres = -600.0 + 1.5 + 3.0 * np.arange(400)
    candidates = [(r, c) for r in range(0, 400, 10) for c in range(0, 400, 10)
                  if np.hypot(centres[c] - village[0], centres[r] - village[1]) > 300.0]
    candidates.sort(key=lambda rc: (humidity[rc] + 1.0 - temperature[rc] + overcast[rc], rc))
    tree_cells = cell_of(f.positions)
    burning: list[int] = []
    for r, c in candidates:
        in_block = np.all(np.abs(tree_cells - (r, c)) <= 2, axis=1)
        burning += sorted(np.flatnonzero(in_block).tolist(), key=lambda t: tuple(tree_cells[t]))
        if len(burning) > 15:
            return burning
    raise AssertionError("reference found too few trees")


@pytest.mark.parametrize("seed", [0, 1, 2, 3])
def test_driest_block_ignites_whatever_the_forest_seed(seed):
    f = forest(seed)
    burning = select_ignition(f, IGNITION, np.zeros(2), *weather())
    block = np.flatnonzero(np.all(np.abs(cell_of(f.positions) - DRIEST) <= 2, axis=1))
    assert len(block) > 15  # 25 cells at 54 m: one block suffices
    np.testing.assert_array_equal(np.sort(burning), block)


def test_ignition_follows_the_rule_across_several_blocks():
    village = np.array([100.0, 50.0])
    f = forest(11, village=village)
    # driest is an empty cell on low ground; the next ones hold sparse high forest (~99 m, ~12 %)
    temperature, humidity, overcast = weather(driest=(0, 0))
    humidity[:, 330] -= 0.45
    burning = select_ignition(f, IGNITION, village, temperature, humidity, overcast)
    assert burning.dtype == np.int64 and len(np.unique(burning)) == len(burning) > 15
    assert burning.tolist() == reference_ignition(f, village, temperature, humidity, overcast)
    cells = cell_of(f.positions[burning])
    centre_cells = np.round(cells / 10.0).astype(int) * 10
    assert np.all(np.abs(cells - centre_cells) <= 2)
    centre_xy = -600.0 + 1.5 + 3.0 * centre_cells[:, ::-1]
    assert np.hypot(*(centre_xy - village).T).min() > 300.0
    assert len(np.unique(centre_cells, axis=0)) >= 2
    ranked = rank_ignition_cells(f, IGNITION, village, temperature, humidity, overcast)
    assert tuple(ranked[0]) == (0, 0)


def test_ties_keep_row_major_cell_order_and_the_village_excludes_candidates():
    f = forest(0)
    village = np.array([0.0, 0.0])
    ranked = rank_ignition_cells(f, IGNITION, village, *weather(score_ramp=False, driest=(1, 1)))
    keys = ranked[:, 0] * 400 + ranked[:, 1]
    assert np.all(np.diff(keys) > 0) and np.all(ranked % 10 == 0)
    centres = -600.0 + 1.5 + 3.0 * np.arange(0, 400, 10)
    far = np.hypot(*np.meshgrid(centres, centres)) > 300.0
    assert len(ranked) == np.count_nonzero(far) < 40 * 40


def test_ignition_errors_are_clear():
    small = forest(0, spec=SMALL, height_at=flat(55.0), village=FAR_AWAY)
    calm = [np.full((40, 40), 0.5)] * 3
    with pytest.raises(ValueError, match="no ignition candidate"):
        select_ignition(small, IGNITION, np.zeros(2), *calm)
    bare = forest(0, height_at=flat(0.0))
    with pytest.raises(ValueError, match="cannot ignite more than 15 trees"):
        select_ignition(bare, IGNITION, np.zeros(2), *weather())
    with pytest.raises(ValueError, match="humidity must be a finite"):
        select_ignition(small, IGNITION, FAR_AWAY, calm[0], np.zeros((40, 41)), calm[0])


def test_ignition_from_the_tree_grid_alone_matches_the_forest_choice():
    rng = np.random.default_rng(12)
    preset = load_forest_preset()
    spec, ignition = preset.forest, preset.ignition
    village = np.array([40.0, -30.0])
    forest = place_forest(rng, spec, lambda p: np.full(len(p), 55.0), village)
    weather = [rng.random((spec.cells, spec.cells)) for _ in range(3)]
    ids = select_ignition(forest, ignition, village, *weather)
    expected = np.zeros((spec.cells, spec.cells), bool)
    expected[forest.cell_index[ids, 0], forest.cell_index[ids, 1]] = True
    mask = ignition_mask(forest.grid >= 0, spec, ignition, village, *weather)
    assert np.array_equal(mask, expected) and mask.sum() > ignition.min_burning


def _plain_ignition_mask(exists, ignition, village, temperature, humidity, overcast):
    """The rule over the small forest in plain Python: candidates by score (ties row-major), blocks in
    turn until more than min_burning trees burn, or every candidate block's trees if that never happens."""
    n = exists.shape[0]
    centres = SMALL.half_extent_m * -1 + SMALL.spacing_m * (np.arange(n) + 0.5)
    stride, half = ignition.candidate_stride, ignition.block // 2
    candidates = [(r, c) for r in range(0, n, stride) for c in range(0, n, stride)
                  if np.hypot(centres[c] - village[0], centres[r] - village[1]) > ignition.min_village_distance_m]
    candidates.sort(key=lambda rc: (humidity[rc] + (1.0 - temperature[rc]) + overcast[rc], rc))
    mask = np.zeros_like(exists)
    for r, c in candidates:
        mask[max(r - half, 0):r + half + 1, max(c - half, 0):c + half + 1] |= \
            exists[max(r - half, 0):r + half + 1, max(c - half, 0):c + half + 1]
        if mask.sum() > ignition.min_burning:
            break
    return mask


@settings(max_examples=60, deadline=None)
@given(seed=st.integers(0, 2**32 - 1), density=st.sampled_from([0.0, 0.02, 0.3, 0.9]),
       stride=st.sampled_from([3, 5, 10]), block=st.sampled_from([1, 3]), min_burning=st.sampled_from([0, 4, 15, 400]),
       distance=st.sampled_from([0.0, 30.0, 200.0]), weather_cells=st.sampled_from([1, 4, 7, 40, 60]))
def test_kept_forests_ignite_by_the_rule_and_the_islands_read_their_weather_cells(
        seed, density, stride, block, min_burning, distance, weather_cells):
    """ignition_mask and the islands' weather-grid path (no upsampling) agree with the plain rule, also
    where it cannot light enough trees (then every candidate block's trees burn, possibly none)."""
    rng = np.random.default_rng(seed)
    exists = rng.random((40, 40)) < density
    village = rng.uniform(-60.0, 60.0, 2)
    ignition = IgnitionSpec(candidate_stride=stride, block=block, min_burning=min_burning, min_village_distance_m=distance)
    conditions = rng.random((weather_cells, weather_cells, 3)).round(1)  # coarse values: many ties
    lookup = grid_lookup(40, weather_cells)
    temperature, humidity, overcast = (conditions[lookup][:, lookup][..., k] for k in range(3))
    expected = _plain_ignition_mask(exists, ignition, village, temperature, humidity, overcast)
    np.testing.assert_array_equal(ignition_mask(exists, SMALL, ignition, village, temperature, humidity, overcast),
                                  expected)
    np.testing.assert_array_equal(ignition_of(exists, village, conditions, SMALL, ignition), expected)
