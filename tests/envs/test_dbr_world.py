"""Drone-Based Reforestation world: flight invariants under random actions, the scaled generators,
the distance rasters against brute force, the camera, observations and the scenario checks."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest
from hypothesis import given, settings, strategies as st

import hivex_dsl
from hivex_dsl import ScenarioError
from hivex_dsl.envs.drone_based_reforestation.camera import STATION_GRAY
from hivex_dsl.envs.drone_based_reforestation.fertility import FAR_M, nearest_tree_distance, tree_distance_raster
from hivex_dsl.envs.drone_based_reforestation.params import forest_preset, terrain_preset
from hivex_dsl.sim.grids import Grid, sample_bilinear
from hivex_dsl.sim.procgen.terrain import Terrain, generate_terrain

ENV = "drone_based_reforestation"


def compiled_sim(**fields):
    compiled = hivex_dsl.compile({"hivex": 1, "environment": ENV, **fields})
    return compiled, compiled.entry.make_simulator(compiled)


@settings(max_examples=15, deadline=None)
@given(seed=st.integers(0, 2**32 - 1), level=st.integers(1, 10), agents=st.sampled_from([1, 3, 5]),
       steps=st.integers(1, 120), task=st.sampled_from(["main", "pick_up_seed"]))
def test_energy_stays_in_0_1_and_drones_never_go_under_ground_or_leave_the_world(seed, level, agents, steps, task):
    compiled, sim = compiled_sim(terrain_level=level, agents=agents, task=task)
    rng = np.random.default_rng(seed)
    state = sim.reset(rng, 2)
    terrains = [Terrain(h, sim.terrain_grid.cell, 2 * sim.half, np.zeros(2)) for h in state.heights]
    clearance, bound = compiled.params.min_clearance_m, compiled.params.height_bound_m
    for _ in range(steps):
        # long runs of full throttle and full descent as well as uniform noise
        continuous = rng.choice([-1.0, 1.0], (2, agents, 3)) if rng.random() < 0.5 else rng.uniform(-1, 1, (2, agents, 3))
        actions = {"continuous": continuous.astype(np.float32), "discrete": rng.integers(0, 2, (2, agents, 1))}
        state, _ = sim.step(state, actions, rng)
        assert np.all((state.energy >= 0.0) & (state.energy <= 1.0))
        for world, terrain in enumerate(terrains):
            ground = terrain.height_at(state.position[world, :, :2])
            assert np.all(state.position[world, :, 2] >= ground + clearance - 1e-9)
        assert np.all(state.position[..., 2] <= bound) and np.all(np.abs(state.position[..., :2]) <= sim.half)
        assert np.all(state.best_fertility <= 1.0) and np.all(state.new_count <= compiled.params.new_tree_capacity)


@settings(max_examples=20, deadline=None)
@given(seed=st.integers(0, 2**32 - 1), level=st.integers(1, 10))
def test_bilinear_sampling_is_the_terrains_height_at(seed, level):
    rng = np.random.default_rng(seed)
    terrain = generate_terrain(rng, terrain_preset(level))
    grid = Grid(-terrain.extent_m / 2, terrain.cell_m, terrain.heights.shape[0])
    points = rng.uniform(-230.0, 230.0, (1, 40, 2))  # inside and beyond the border
    np.testing.assert_allclose(sample_bilinear(terrain.heights[None], grid, points)[0], terrain.height_at(points[0]),
                               rtol=0, atol=1e-9)


@settings(max_examples=20, deadline=None)
@given(seed=st.integers(0, 2**32 - 1), density=st.floats(0.001, 0.3))
def test_tree_distance_raster_is_the_brute_force_distance_between_cell_centres(seed, density):
    rng = np.random.default_rng(seed)
    occupied = rng.random((2, 30, 30)) < density
    raster = tree_distance_raster(occupied, 4.0, 30.0)
    rows, cols = np.indices((30, 30))
    for world in range(2):
        trees = np.argwhere(occupied[world]) * 4.0
        if len(trees) == 0:
            assert np.all(raster[world] > 30.0)
            continue
        cells = np.stack([rows, cols], axis=-1).reshape(-1, 1, 2) * 4.0
        brute = np.linalg.norm(cells - trees[None], axis=-1).min(axis=1).reshape(30, 30)
        near = brute <= 30.0
        np.testing.assert_allclose(raster[world][near], brute[near], rtol=1e-6)
        assert np.all(raster[world][~near] > 30.0)


@settings(max_examples=20, deadline=None)
@given(seed=st.integers(0, 2**32 - 1))
def test_exact_nearest_tree_distance_matches_brute_force_within_reach(seed):
    rng = np.random.default_rng(seed)
    grid = Grid(-198.0, 4.0, 100)
    occupied = rng.random((1, 100, 100)) < 0.01
    centres = grid.origin + grid.cell * np.arange(100)
    trees = np.full((1, 100, 100, 2), FAR_M, np.float32)
    row, col = np.nonzero(occupied[0])
    trees[0, row, col] = np.stack([centres[col], centres[row]], axis=-1) + rng.uniform(-1.0, 1.0, (len(row), 2))
    points = rng.uniform(-200.0, 200.0, (25, 2))
    found = nearest_tree_distance(trees, grid, np.zeros(25, np.int64), points, 75.0)
    brute = np.linalg.norm(points[:, None] - trees[0, row, col][None].astype(np.float64), axis=-1).min(axis=1)
    np.testing.assert_allclose(found, np.where(brute <= 75.0, brute, np.inf), rtol=1e-6)


def test_terrain_levels_keep_their_relative_steepness_below_the_40_m_bound():
    peaks = [terrain_preset(level).height_multiplier * terrain_preset(level).metres_per_multiplier for level in range(1, 11)]
    assert peaks[0] == 8.0 and peaks[-1] == 30.0 and max(peaks) < 40.0  # 8..30 multipliers at 1 m each
    assert peaks == sorted(peaks)
    for level in (1, 10):
        heights = generate_terrain(np.random.default_rng(level), terrain_preset(level)).heights
        assert 0.8 * peaks[level - 1] < heights.max() <= peaks[level - 1] + 1e-9 and heights.min() >= 0.0
    spec = terrain_preset(5)
    # the same number of noise lattice units across the map as the original 241-cell, scale-40 island
    assert spec.extent_m == 400.0 and spec.size / spec.noise_scale == pytest.approx(241 / 40, rel=0.01)
    assert forest_preset(5).cells * forest_preset(5).spacing_m == 400.0


def test_every_world_has_a_forest_away_from_the_station_and_open_ground_to_plant():
    for level in (1, 5, 10):
        compiled, sim = compiled_sim(terrain_level=level)
        state = sim.reset(np.random.default_rng(level), 3)
        trees = state.tree_xy[..., 0] < FAR_M
        assert np.all(trees.sum(axis=(1, 2)) >= 20)  # patches: 20 trees in the sparsest of 64 worlds, median 114
        near_station = np.hypot(state.tree_xy[..., 0], state.tree_xy[..., 1]) <= compiled.generators[
            "forest"].station_clear_radius_m
        assert not np.any(trees & near_station)
        fertile = (state.tree_distance >= 2.5) & (state.tree_distance <= 75.0)
        assert np.all(fertile.mean(axis=(1, 2)) > 0.2)
        assert np.allclose(state.station[:, :2], 0.0)


def test_the_camera_footprint_grows_with_height_above_ground():
    compiled, sim = compiled_sim(params={"camera_images": "rendered"})
    state = sim.reset(np.random.default_rng(0), 1)
    pad_pixels = []
    for height in (1.5, 4.0, 10.0, 24.0):  # footprint half widths 2 (the minimum), 4, 10, 24 m
        position = np.array([[[0.0, 0.0, state.station[0, 2] + height]]])
        above = replace(state, position=position, ground=np.full((1, 1), state.station[0, 2]))
        image = sim.observe(above)["visual"][0, 0, :, :, 0]
        assert image.shape == (16, 16) and image.dtype == np.float32 and 0.0 <= image.min() <= image.max() <= 1.0
        pad_pixels.append(int(np.count_nonzero(image == STATION_GRAY)))
    assert pad_pixels[0] == 256 and pad_pixels == sorted(pad_pixels, reverse=True) and pad_pixels[-1] < 16


def test_vector_observation_holds_the_normalised_state_and_the_previous_step():
    compiled, sim = compiled_sim(agents=1)
    state = sim.reset(np.random.default_rng(2), 1)
    state = replace(state, position=np.array([[[100.0, -50.0, 20.0]]]), heading=np.array([[np.pi / 2]]),
                    ground=np.array([[4.0]]), energy=np.array([[0.8]]), away=np.ones((1, 1), bool))
    ground = sample_bilinear(state.heights, sim.terrain_grid, np.array([[[100.0, -50.0]]]))[0, 0]
    actions = {"continuous": np.zeros((1, 1, 3), np.float32), "discrete": np.zeros((1, 1, 1), np.int64)}
    before = state.frames[0, 0, :10].copy()
    state, _ = sim.step(state, actions, np.random.default_rng(2))
    vector = sim.observe(state)["vector"][0, 0]
    bound = 65.0  # the height bound heights are normalised by
    assert compiled.params.height_bound_m == bound
    expected = [(20.0 - ground) / bound, 0.5, -0.25, 20.0 / bound, 0.0, 1.0, 0.0, state.station[0, 2] / bound, 1.0,
                0.8 - 0.001]
    gain = compiled.params.vector_observation_gain  # the frame is sent times it
    np.testing.assert_allclose(vector[:10], gain * np.array(expected), atol=1e-6)
    np.testing.assert_array_equal(vector[10:], gain * before)
    assert sim.observation_space["vector"].contains(sim.observe(state)["vector"][0, 0])


def test_the_vector_is_sent_times_its_gain_and_a_scenario_stored_before_the_gain_reads_one():
    from hivex_dsl.compiler import as_written, written

    compiled, sim = compiled_sim()
    state = sim.reset(np.random.default_rng(0), 2)
    np.testing.assert_array_equal(sim.observe(state)["vector"], 3.0 * state.frames)
    assert sim.observation_space["vector"].contains(sim.observe(state)["vector"][1, 2])
    stored = compiled.resolved()
    del stored["params"]["vector_observation_gain"]  # a lock or checkpoint written before the gain existed
    before = written(hivex_dsl.compile(as_written(stored)), stored)
    assert before.params.vector_observation_gain == 1.0
    np.testing.assert_array_equal(before.entry.make_simulator(before).observe(state)["vector"], state.frames)
    with pytest.raises(ScenarioError, match="vector_observation_gain"):
        compiled_sim(params={"vector_observation_gain": 0.0})


@pytest.mark.parametrize("generators, field", [
    ({"terrain": {"metres_per_multiplier": 7.0}}, "metres_per_multiplier"),
    ({"terrain": {"village_half_range_m": 50.0}}, "village_half_range_m"),
    ({"terrain": {"extent_m": 800.0}, "forest": {"half_extent_m": 400.0, "cells": 200}}, "extent_m"),
    ({"forest": {"half_extent_m": 100.0, "cells": 50}}, "half_extent_m"),
])
def test_a_world_that_does_not_fit_the_paper_scale_is_a_located_compile_error(tmp_path, generators, field):
    import yaml

    path = tmp_path / "bad.yaml"
    path.write_text(yaml.safe_dump({"hivex": 1, "environment": ENV, "terrain_level": 10, "generators": generators}))
    with pytest.raises(ScenarioError) as error:
        hivex_dsl.compile(str(path))
    assert field in str(error.value) and "bad.yaml:" in str(error.value)


def test_a_scenario_may_lower_the_terrain_and_still_compile():
    compiled, sim = compiled_sim(terrain_level=10, generators={"terrain": {"metres_per_multiplier": 0.5}})
    state = sim.reset(np.random.default_rng(0), 1)
    assert state.heights.max() <= 15.0 + 1e-9


def test_the_global_state_s_planting_facts_match_the_state_once_the_drones_plant():
    """The drones fly ahead, climbing, and drop their seeds: they plant on the first steps, so the entry's
    state_facts names the planting quality too, and the global state agrees with it (tests/test_global_state.py
    checks every environment's facts; this makes sure DBR's planting ones are among them)."""
    env = hivex_dsl.parallel_env({"hivex": 1, "environment": "drone_based_reforestation", "episode_length": 30})
    env.reset(seed=2)
    plant = {"continuous": np.array([1.0, 0.0, 0.2], np.float32), "discrete": np.array([1])}
    for _ in range(3):
        env.step({agent: plant for agent in env.agents})
    core = env.core
    facts = core.compiled.entry.state_facts(core.sim, core.state, core.compiled.params)
    assert facts["trees planted"][0] > 0 and "planting quality" in facts
    state = env.state()
    for name, value in facts.items():
        np.testing.assert_allclose(state[env.global_state.slices[name]], value, rtol=1e-6, atol=1e-6, err_msg=name)
