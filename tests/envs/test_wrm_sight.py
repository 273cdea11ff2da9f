"""Wildfire Resource Management's fast paths give exactly the general answers.

The towers' closest fire, kept per cohort of trees that ignited together (.sight), is closest_burning's
answer after every step; its one-world path matches the many-world one; the weather sampled in one call
matches island.sample_conditions and the towers' own sample; tower performance, which all three terms read,
is computed once per sighting and kept with it, with fewer operations than the paper's formula but the same floats.
"""

from __future__ import annotations

from dataclasses import replace
from types import SimpleNamespace

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import hivex_dsl
from hivex_dsl.envs.island import sample_conditions
from hivex_dsl.envs.wildfire_resource_management.params import WildfireResourceParams
from hivex_dsl.envs.wildfire_resource_management.sight import (key_cells, key_tables, nearest_keys, nearest_of_sorted,
                                                                square_table)
from hivex_dsl.envs.wildfire_resource_management.terms import (broken_power_law, collective_performance, remapped_distance,
                                                               tower_performance)
from hivex_dsl.envs.wildfire_resource_management.types import Sighting
from hivex_dsl.sim.fire import TreeState, closest_burning, fire_reset

ENV = "wildfire_resource_management"


def simulator(**params):
    compiled = hivex_dsl.compile({"hivex": 1, "environment": ENV, "terrain_level": 1, "params": params})
    return compiled.entry.make_simulator(compiled)


def closest_by_search(sim, fire):
    """(rows, cols) (B, A) of closest_burning over the whole burning list, -1 where none."""
    batch, agents = fire.batch, sim.agents
    world = np.repeat(np.arange(batch), agents)
    tower = np.tile(np.arange(agents), batch)
    found, rows, cols = closest_burning(fire, world, sim.tower_rows[tower], sim.tower_cols[tower],
                                        sim.params.detection_radius_m / sim.cell_m)
    return np.where(found, rows, -1).reshape(batch, agents), np.where(found, cols, -1).reshape(batch, agents)


@pytest.mark.parametrize("params", [
    {}, {"burn_steps": 3, "fire_step_interval": 2}, {"burn_steps": 1, "spread_chance_per_factor": 0.5},
    {"detection_radius_m": 150.0, "tower_spacing_m": 300.0, "redraw_island": "episode"}])
def test_the_cohort_tracker_is_closest_burning_after_every_step_and_reset(params):
    sim = simulator(**params)
    rng = np.random.default_rng(11)
    state = sim.reset(rng, 3)
    for step in range(60):
        state, _ = sim.step(state, rng.integers(0, 3, (3, 9, 4)), rng)
        rows, cols = closest_by_search(sim, state.fire)
        np.testing.assert_array_equal(state.sighting.row, rows)
        np.testing.assert_array_equal(state.sighting.col, cols)
        if step % 20 == 10:
            state = sim.reset_where(state, np.array([True, False, step > 20]), rng)
            rows, cols = closest_by_search(sim, state.fire)
            np.testing.assert_array_equal(state.sighting.row, rows)


@st.composite
def burning_lists(draw):
    batch, cells = draw(st.integers(1, 4)), draw(st.integers(2, 30))
    flat = draw(st.lists(st.integers(0, batch * cells * cells - 1), max_size=60, unique=True))
    towers = draw(st.integers(1, 5))
    centres = st.floats(-5.0, cells + 5.0, allow_nan=False)
    rows = np.array(draw(st.lists(centres, min_size=towers, max_size=towers)))
    cols = np.array(draw(st.lists(centres, min_size=towers, max_size=towers)))
    half = draw(st.sampled_from([0.0, 0.5, 1.0, 2.5, 7.0, 100.0]))
    return batch, cells, np.sort(np.array(flat, np.int64)), rows, cols, half


@settings(max_examples=150, deadline=None)
@given(burning_lists())
def test_nearest_of_sorted_is_closest_burning(case):
    batch, cells, flat, rows, cols, half = case
    trees = np.zeros((batch, cells, cells), np.uint8)
    trees.reshape(-1)[flat] = TreeState.BURNING
    fire = fire_reset(trees > 0, trees > 0)
    tables = square_table(rows, half, cells), square_table(cols, half, cells)
    distance, best = nearest_of_sorted(flat, batch, cells, *tables)
    towers = len(rows)
    world = np.repeat(np.arange(batch), towers)
    found, r, c = closest_burning(fire, world, np.tile(rows, batch), np.tile(cols, batch), half)
    np.testing.assert_array_equal(best.reshape(-1), np.where(found, r * cells + c, -1))
    assert np.array_equal(np.isfinite(distance).reshape(-1), found)


@settings(max_examples=80, deadline=None)
@given(burning_lists())
def test_the_one_world_path_matches_the_many_world_path(case):
    _, cells, flat, rows, cols, half = case
    flat = flat[flat < cells * cells]  # one world's cells
    other = np.arange(0, cells * cells, 3) + cells * cells  # a second world with its own fire
    tables = square_table(rows, half, cells), square_table(cols, half, cells)
    alone = nearest_of_sorted(flat, 1, cells, *tables)
    together = nearest_of_sorted(np.concatenate([flat, other]), 2, cells, *tables)
    for one, many in zip(alone, together):
        np.testing.assert_array_equal(one[0], many[0])


def test_weather_sampled_in_one_call_matches_the_separate_samples():
    sim = simulator(weather_refresh_interval=3)
    rng = np.random.default_rng(4)
    state = sim.reset(rng, 4)
    for _ in range(6):  # the last step refreshes the weather
        state, _ = sim.step(state, np.zeros((4, 9, 4), np.int64), rng)
    conditions, tower_weather = sim._sample_weather(state.weather)
    p = sim.params
    np.testing.assert_array_equal(conditions, sample_conditions(state.weather, sim.weather_spec,
                                                                p.island_half_extent_m, p.weather_grid_cells))
    np.testing.assert_array_equal(tower_weather, sim._tower_weather(state.weather))
    np.testing.assert_array_equal(state.conditions, sample_conditions(state.weather, sim.weather_spec,
                                                                      p.island_half_extent_m, p.weather_grid_cells))


def paper_performance(sighting, p) -> np.ndarray:
    """P by the paper's two functions, idle where no fire is seen within the distance threshold."""
    seen = sighting.seen & (sighting.distance <= p.distance_threshold_m)
    return np.where(seen, broken_power_law(remapped_distance(np.where(seen, sighting.distance, 0.0),
                                                             sighting.approaching, p.distance_threshold_m),
                                           p.power_law_s, p.power_law_a), p.idle_performance)


def test_tower_performance_is_computed_once_per_sighting_and_kept_with_it():
    sim = simulator()
    rng = np.random.default_rng(7)
    state = sim.reset(rng, 3)
    p = sim.params
    for step in range(40):
        state, _ = sim.step(state, np.zeros((3, 9, 4), np.int64), rng)
        if step == 25:  # the reset worlds' sighting brings its own P
            state = sim.reset_where(state, np.array([True, False, True]), rng)
        sighting = state.sighting
        assert tower_performance(state, p) is sighting.performance  # the three terms read what the step computed
        np.testing.assert_array_equal(sighting.performance, paper_performance(sighting, p))
    bare = replace(state, sighting=replace(sighting, performance=None))  # as a hand-made sighting: computed here
    np.testing.assert_array_equal(tower_performance(bare, p), sighting.performance)
    other = p.model_copy(update={"idle_performance": 0.5})
    np.testing.assert_array_equal(tower_performance(bare, other), paper_performance(sighting, other))


@settings(max_examples=200, deadline=None)
@given(st.lists(st.tuples(st.one_of(st.floats(0.0, 1000.0), st.just(np.inf)), st.booleans()), min_size=1, max_size=9),
       st.floats(1.0, 500.0), st.floats(1.0, 1000.0), st.floats(0.5, 20.0), st.floats(0.0, 1.0))
def test_the_fused_performance_is_the_papers_formula(towers, threshold, s, a, idle):
    """tower_performance's fewer operations give exactly broken_power_law(remapped_distance(...)) where a
    fire is seen within the threshold, and the collective term's root mean square needs no absolute value
    (every P is in [0, 1])."""
    distance = np.array([[d for d, _ in towers]])
    approaching = np.array([[m for _, m in towers]]) & np.isfinite(distance)
    params = WildfireResourceParams(distance_threshold_m=threshold, power_law_s=s, power_law_a=a, idle_performance=idle,
                                    performance_weight="none")  # P alone: the collective reads no resources here
    seen = distance <= threshold
    expected = np.where(seen, broken_power_law(remapped_distance(np.where(seen, distance, 0.0), approaching, threshold),
                                               s, a), idle)
    sighting = Sighting(cell=np.zeros(distance.shape, np.int64), cells=400, offset=np.zeros(distance.shape + (3,)),
                        distance=distance, approaching=approaching)
    got = tower_performance(SimpleNamespace(sighting=sighting), params)
    np.testing.assert_array_equal(got, expected)
    assert np.all((got >= 0.0) & (got <= 1.0))
    paper = 1.0 - np.abs(1.0 - np.sqrt(np.mean(got * got, axis=-1)))  # R = 1 - |1 - sqrt(MSE)|, every tower
    collective = collective_performance(None, SimpleNamespace(sighting=sighting), None, params)
    np.testing.assert_array_equal(collective, np.broadcast_to(paper[:, None], got.shape))


def test_keys_outside_the_box_and_empty_answers_read_as_no_cell():
    tables = square_table(np.array([5.0, 50.0]), 2.0, 20), square_table(np.array([5.0, 5.0]), 2.0, 20)
    keys = key_tables(*tables)
    flat = np.array([5 * 20 + 5, 19 * 20 + 19])  # (5, 5) in the first tower's box; nothing in the second's
    nearest = nearest_keys(flat, 1, 20, *keys)
    assert key_cells(nearest).tolist() == [[105, -1]]
    assert key_cells(nearest_keys(flat[1:], 1, 20, *keys)).tolist() == [[-1, -1]]  # outside every box
    assert key_cells(nearest_keys(flat[:0], 1, 20, *keys)).tolist() == [[-1, -1]]  # no burning tree at all
    assert np.all(keys[0].imag[np.isinf(keys[0].real)] < 0) and np.all(keys[1].imag[np.isinf(keys[1].real)] < 0)
