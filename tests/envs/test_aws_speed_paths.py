"""The fast paths of Aerial Wildfire Suppression's one-world step agree with the general ones.

* the unchecked closest-fire entries (``closest_burning_unchecked``, ``closest_burning_at``) answer as
  the checked ``closest_burning``, on one world (the complex (M, K) box test) and on several;
* a row-major ``look`` (small batches) and a tiled one (large batches) give the exact cameras, and
  planes within ``ViewFrame.clear_m`` see no MIXED cell, so their cameras may skip that test;
* a one-world sighting (the complex path) is the sighting of the same world among others;
* the reward terms are their plain formulas, bit for bit (zero signs included).
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import hivex_dsl
from hivex_dsl.envs.aerial_wildfire_suppression import terms, view
from hivex_dsl.envs.aerial_wildfire_suppression.camera import cameras
from hivex_dsl.envs.aerial_wildfire_suppression.simulator import AerialWildfireSimulator
from hivex_dsl.sim.fire import FireState, TreeState, closest_burning
from hivex_dsl.sim.fire.search import closest_burning_at, closest_burning_unchecked

CELLS = 400


@pytest.fixture(scope="module")
def sim():
    return AerialWildfireSimulator(hivex_dsl.compile("aerial_wildfire_suppression/main"))


def fire_of(trees: np.ndarray, seed: int) -> FireState:
    """A FireState over ``trees`` (B, C, C) with its burning list in a shuffled order."""
    burning = np.flatnonzero(trees == TreeState.BURNING).astype(np.int64)
    burning = burning[np.random.default_rng(seed).permutation(len(burning))]
    batch = len(trees)
    return FireState(trees=trees, burning=burning, age=np.zeros(len(burning), np.int32),
                     quiet=np.zeros(batch, np.int32), out=np.zeros(batch, bool), ignited=np.zeros(batch, np.int64),
                     burnt_out=np.zeros(batch, np.int64))


@settings(max_examples=120, deadline=None)
@given(seed=st.integers(0, 2**32 - 1), batch=st.sampled_from([1, 1, 2, 3]), cells=st.integers(1, 12),
       density=st.sampled_from([0.0, 0.05, 0.3, 1.0]), queries=st.integers(0, 6), grid_aligned=st.booleans(),
       shared=st.booleans())
def test_unchecked_closest_burning_entries_answer_as_the_checked_one(seed, batch, cells, density, queries,
                                                                     grid_aligned, shared):
    rng = np.random.default_rng(seed)
    trees = np.where(rng.random((batch, cells, cells)) < density, TreeState.BURNING, TreeState.EXISTING)
    fire = fire_of(trees.astype(np.uint8), seed)
    world = rng.integers(0, batch, queries)
    rows, cols = rng.uniform(-3.0, cells + 3.0, queries), rng.uniform(-3.0, cells + 3.0, queries)
    half = rng.uniform(0.0, 5.0, queries)
    if grid_aligned:  # coordinates and boxes on cell centres and edges: ties and exact box edges
        rows, cols, half = np.round(rows * 2.0) / 2.0, np.round(cols * 2.0) / 2.0, np.round(half)
    box = float(half[0]) if shared and queries else half
    expected = closest_burning(fire, world, rows, cols, box)
    points = np.ascontiguousarray(np.stack([cols, rows], axis=-1))  # (col, row)
    for got in (closest_burning_unchecked(fire, world, rows, cols, box), closest_burning_at(fire, world, points, box)):
        for a, b in zip(got, expected):
            np.testing.assert_array_equal(a, b)
            assert a.dtype == b.dtype


def random_island(rng: np.random.Generator, batch: int) -> tuple[np.ndarray, np.ndarray]:
    trees = rng.integers(0, 5, (batch, CELLS, CELLS)).astype(np.uint8)
    ground = rng.integers(0, view.MIXED, (batch, CELLS, CELLS)).astype(np.uint8)
    return trees, ground


@settings(max_examples=40, deadline=None)
@given(seed=st.integers(0, 2**32 - 1), batch=st.sampled_from([1, 2, 3]), tiled=st.booleans(),
       near=st.sampled_from(["anywhere", "clear", "border"]), square=st.booleans())
def test_both_look_layouts_give_the_exact_cameras(sim, seed, batch, tiled, near, square):
    """Row-major or tiled, with the MIXED test or (planes within clear_m) without it."""
    p, frame = sim.params, sim.frame
    rng = np.random.default_rng(seed)
    trees, ground = random_island(rng, batch)
    reach = {"anywhere": p.border_half_extent_m + p.plane_speed_m, "clear": frame.clear_m,
             "border": p.border_half_extent_m + p.plane_speed_m}[near]
    position = rng.uniform(-reach, reach, (batch, sim.agents, 2))
    if near == "border":  # on or beside the border line, where MIXED cells are seen
        position[..., 0] = rng.choice([-1.0, 1.0], position.shape[:-1]) * rng.uniform(740.0, reach, position.shape[:-1])
    heading = rng.uniform(-np.pi, np.pi, (batch, sim.agents))
    if square:
        heading = rng.choice([0.0, np.pi / 2, np.pi, -np.pi / 2], heading.shape)
    look = view.build_look(trees, ground, sim.frame_template, frame, tiled)
    assert view.is_tiled(look) == tiled
    exact = cameras(position, heading, trees, ground, sim.camera_offsets, p.island_half_extent_m,
                    p.border_half_extent_m)
    np.testing.assert_array_equal(view.plane_cameras(position, heading, look, trees, ground, frame,
                                                     sim.camera_offsets), exact)
    np.testing.assert_array_equal(view.look_cameras(position, heading, look, frame), exact)
    if near == "clear":
        np.testing.assert_array_equal(view.look_cameras(position, heading, look, frame, mixed=False), exact)


@settings(max_examples=60, deadline=None)
@given(seed=st.integers(0, 2**32 - 1))
def test_planes_within_clear_m_see_no_mixed_cell(sim, seed):
    frame = sim.frame
    rng = np.random.default_rng(seed)
    edge = np.nextafter(frame.clear_m, 0.0)
    position = rng.choice([-edge, edge, 0.0], (4, 3, 2)) + rng.uniform(-1.0, 1.0, (4, 3, 2)) * (rng.random() < 0.5)
    position = np.clip(position, -edge, edge)
    heading = rng.uniform(-np.pi, np.pi, (4, 3))
    rows, cols = view._pixel_axes(position, heading, frame, None)
    cells = view.cell_of(np.add(rows[..., :, None], cols[..., None, :]), frame)
    template = view.frame_template(frame)
    picked = template[cells[1] + frame.pad, cells[0] + frame.pad]
    island = (cells >= 0).all(axis=0) & (cells < frame.cells).all(axis=0)
    assert not (picked[~island] == view.MIXED).any()


def test_the_defaults_skip_the_mixed_test_over_the_island_and_keep_one_world_row_major(sim):
    assert sim.params.island_half_extent_m - 5.0 < sim.frame.clear_m < sim.params.border_half_extent_m
    assert not view.tiled_for(1, sim.frame) and view.tiled_for(256, sim.frame)


@pytest.mark.parametrize("batch", [1, 2])
def test_a_row_major_look_stays_the_picture_of_the_trees_through_fires_drops_and_restarts(batch):
    compiled = hivex_dsl.compile("aerial_wildfire_suppression/main")
    sim = AerialWildfireSimulator(compiled)
    act = compiled.entry.scripted_policy(compiled)
    rng = np.random.default_rng(batch)
    state = sim.reset(rng, batch)
    assert not view.is_tiled(state.look)
    for step in range(120):
        state, _ = sim.step(state, act(sim.observe(state)), rng)
        if step in (40, 80):
            state = sim.reset_where(state, np.arange(batch) == step % batch, rng)
    assert not view.is_tiled(state.look)
    fresh = view.build_look(state.fire.trees, state.maps.ground, sim.frame_template, sim.frame)
    np.testing.assert_array_equal(state.look, fresh)
    np.testing.assert_array_equal(sim.observe(state)["visual"], sim.derive(state).visual)


def test_a_one_world_sighting_is_its_sighting_among_other_worlds(sim):
    rng = np.random.default_rng(4)
    state = sim.reset(rng, 1)
    still = {"continuous": np.zeros((1, 3, 1), np.float32), "discrete": np.zeros((1, 3, 1), np.int64)}
    for _ in range(60):
        state, _ = sim.step(state, still, rng)
    seen = 0
    for trial in range(40):  # planes near the fire, far from it and on the village
        burning = state.fire.burning
        centre = np.array(np.divmod(burning[trial % len(burning)], CELLS))[::-1] * sim.cell_m - 600.0
        position = centre + rng.uniform(-200.0, 200.0, (1, 3, 2))
        position[0, 2] = state.maps.village[0] if trial % 3 == 0 else position[0, 2]
        flying = rng.random((1, 3)) < 0.8
        one = sim._sight_of(state.fire, state.maps.village, position, flying)
        other = rng.integers(0, 5, (1, CELLS, CELLS)).astype(np.uint8)
        pair = fire_of(np.concatenate([other, state.fire.trees]), trial)
        two = sim._sight_of(pair, np.concatenate([state.maps.village + 50.0, state.maps.village]),
                            np.concatenate([position[:, ::-1], position]), np.concatenate([flying, flying]))
        np.testing.assert_array_equal(one.plane_found, two.plane_found[1:])
        np.testing.assert_array_equal(one.plane_xy, two.plane_xy[1:])
        np.testing.assert_array_equal(one.village_threat, two.village_threat[1:])
        seen += int(one.plane_found.sum())
    assert seen > 0


def test_the_terms_are_their_plain_formulas_bit_for_bit(sim):
    rng = np.random.default_rng(2)
    state = sim.reset(rng, 4)
    flags = {name: rng.random((4, 3)) < 0.5 for name in ("crossed", "picked_up", "found_fire", "found_village",
                                                          "flying", "water")}
    counts = {name: rng.integers(0, 9, (4, 3)).astype(np.int32) for name in ("extinguished", "prepared")}
    worlds = {name: rng.random(4) < 0.5 for name in ("fire_went_out", "village_threatened", "burning")}
    state = replace(state, **flags, **counts, **worlds)
    p = sim.params
    every = np.ones((4, 3))
    expected = {
        "crossed_border": -100.0 * state.crossed, "pick_up_water": 1.0 * state.picked_up,
        "fire_out": 10.0 * (state.fire_went_out[:, None] * state.flying),  # a waiting plane is frozen: unpaid
        "too_close_to_village": -50.0 * (state.village_threatened[:, None] * every),
        "time_step_burning": -0.01 * (state.burning[:, None] * every),
        "find_fire": 100.0 * state.found_fire, "find_village": 100.0 * state.found_village,
        "extinguishing_tree": 5.0 * state.extinguished, "preparing_tree": 1.0 * state.prepared,
        # waiting planes (the default) pay the pick-up task's time while they wait, as the release charges it
        "time_step_without_water": -p.water_wait_penalty * ((state.flying & ~state.water) | ~state.flying)}
    for name, value in expected.items():
        got = np.asarray(terms.TERMS[name](state, state, None, p), dtype=np.float64)
        np.testing.assert_array_equal(got, value)
        np.testing.assert_array_equal(np.signbit(got), np.signbit(value))


@settings(max_examples=60, deadline=None)
@given(seed=st.integers(0, 2**32 - 1))
def test_planes_beyond_blind_m_see_no_island_cell(sim, seed):
    frame, p = sim.frame, sim.params
    rng = np.random.default_rng(seed)
    far = np.nextafter(frame.blind_m, np.inf)
    position = rng.uniform(-p.border_half_extent_m - p.plane_speed_m, p.border_half_extent_m + p.plane_speed_m,
                           (4, 3, 2))
    axis = rng.integers(0, 2, (4, 3))
    beyond = rng.choice([-1.0, 1.0], (4, 3)) * rng.choice([far, far + 1e-3, p.border_half_extent_m + 0.5], (4, 3))
    np.put_along_axis(position, axis[..., None], beyond[..., None], axis=-1)
    heading = rng.uniform(-np.pi, np.pi, (4, 3))
    rows, cols = view._pixel_axes(position, heading, frame, None)
    cells = view.cell_of(np.add(rows[..., :, None], cols[..., None, :]), frame)
    island = (cells >= 0).all(axis=0) & (cells < frame.cells).all(axis=0)
    assert not island.any()


def test_planes_out_of_the_game_beyond_the_island_keep_their_picture_which_stays_exact(sim):
    """A one-world batch keeps the pictures of planes parked beyond the border; each step they equal the
    pictures drawn afresh, through crossings, fires, drops and restarts."""
    rng = np.random.default_rng(8)
    state = sim.reset(rng, 1)
    policy = np.random.default_rng(9)
    kept = 0
    for step in range(400):
        steer = np.where(policy.random((1, 3, 1)) < 0.9, 0.0, policy.uniform(-0.05, 0.05, (1, 3, 1)))  # mostly on
        actions = {"continuous": steer.astype(np.float32), "discrete": policy.integers(0, 2, (1, 3, 1))}
        prev_flying = state.flying
        state, _ = sim.step(state, actions, rng)
        kept += int((~prev_flying).sum())
        if step % 25 == 0:
            np.testing.assert_array_equal(state.visual, sim.derive(state).visual)
        if not state.flying.any():
            state = sim.reset_where(state, np.ones(1, bool), rng)
    assert kept > 100  # planes spent many steps parked beyond the border
    np.testing.assert_array_equal(state.visual, sim.derive(state).visual)
