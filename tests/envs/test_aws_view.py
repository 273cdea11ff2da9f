"""The cameras' fast path (the tiled ``look`` image kept in the state) agrees with the exact path.

camera.cameras classifies every pixel from its coordinates over the trees and ground; view.look_cameras
reads the same palette index from one image per world. They must agree bit for bit, wherever the
planes are (over the island, the water ring, on the border line, beyond it), and the image must
stay equal to one drawn afresh while fires spread, drops wet trees and worlds restart.
"""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import hivex_dsl
from hivex_dsl.envs.aerial_wildfire_suppression import view
from hivex_dsl.envs.aerial_wildfire_suppression.camera import OUTSIDE, PALETTE_FLOAT, WATER_RING, cameras
from hivex_dsl.envs.aerial_wildfire_suppression.simulator import AerialWildfireSimulator
from hivex_dsl.envs.island import conditions_reader, sample_conditions, weather_reader
from hivex_dsl.sim.fire import FireState, TreeState

CELLS = 400


@pytest.fixture(scope="module")
def sim():
    return AerialWildfireSimulator(hivex_dsl.compile({"hivex": 1, "environment": "aerial_wildfire_suppression"}))


def random_island(rng: np.random.Generator, batch: int) -> tuple[np.ndarray, np.ndarray]:
    trees = rng.integers(0, 5, (batch, CELLS, CELLS)).astype(np.uint8)
    ground = rng.integers(0, view.MIXED, (batch, CELLS, CELLS)).astype(np.uint8)
    return trees, ground


# scenarios whose frames differ: the defaults, a border one cell beyond the island, odd pixels, a wide border
SCENARIOS = {
    "default": {},
    "narrow ring": {"border_half_extent_m": 601.0, "camera_pixel_m": 3.7},
    "wide border": {"border_half_extent_m": 1400.0, "plane_speed_m": 12.5, "camera_pixel_m": 11.0},
    "huge border": {"border_half_extent_m": 5000.0},  # beyond the widest frame: far planes take the exact path
    "border unseen": {"camera_sees_border": False},
    "wide border unseen": {"border_half_extent_m": 1400.0, "camera_pixel_m": 11.0, "camera_sees_border": False},
}
_SIMS: dict[str, AerialWildfireSimulator] = {}


def simulator(name: str) -> AerialWildfireSimulator:
    if name not in _SIMS:
        compiled = hivex_dsl.compile({"hivex": 1, "environment": "aerial_wildfire_suppression",
                                      "params": SCENARIOS[name]})
        _SIMS[name] = AerialWildfireSimulator(compiled)
    return _SIMS[name]


def edges(sim: AerialWildfireSimulator) -> list[float]:
    """Coordinates that stress the cell mapping: the island edge, the border line, beside and beyond them."""
    p = sim.params
    border = np.float32(p.border_half_extent_m)
    return [p.island_half_extent_m, p.border_half_extent_m, float(np.nextafter(border, np.float32(0.0))),
            float(np.nextafter(border, np.float32(1e5))), 0.0, p.border_half_extent_m + p.plane_speed_m,
            p.border_half_extent_m - 2.5, p.border_half_extent_m + 2.5]


@pytest.mark.parametrize("scenario", list(SCENARIOS))
@settings(max_examples=30, deadline=None)
@given(seed=st.integers(0, 2**32 - 1), batch=st.sampled_from([1, 2, 5]), edge=st.booleans(), square=st.booleans())
def test_cameras_through_the_look_are_the_exact_cameras(scenario, seed, batch, edge, square):
    sim = simulator(scenario)
    p = sim.params
    rng = np.random.default_rng(seed)
    trees, ground = random_island(rng, batch)
    reach = p.border_half_extent_m + p.plane_speed_m  # planes stay inside the border, or stop one step beyond
    position = rng.uniform(-reach, reach, (batch, sim.agents, 2))
    if edge:  # exactly on or beside the island edge and the border line
        position = rng.choice(edges(sim), position.shape) * rng.choice([-1.0, 1.0], position.shape)
    heading = rng.uniform(-np.pi, np.pi, (batch, sim.agents))
    if square:  # axis-aligned cameras put pixel rows exactly on cell and border lines
        heading = rng.choice([0.0, np.pi / 2, np.pi, -np.pi / 2], heading.shape)
    look = view.build_look(trees, ground, sim.frame_template, sim.frame)
    fast = view.plane_cameras(position, heading, look, trees, ground, sim.frame, sim.camera_offsets)
    exact = cameras(position, heading, trees, ground, sim.camera_offsets, p.island_half_extent_m,
                    view.drawn_border_m(p, len(sim.frame.forward)))
    np.testing.assert_array_equal(fast, exact)
    if np.abs(position).max() <= sim.frame.safe_m:  # the frame covers these planes: the look was read
        np.testing.assert_array_equal(view.look_cameras(position, heading, look, sim.frame), exact)


def test_the_frame_covers_every_plane_that_stays_near_the_border():
    assert simulator("huge border").frame.safe_m < 5000.0
    for name in ("default", "narrow ring", "wide border", "border unseen", "wide border unseen"):
        p = simulator(name).params
        assert simulator(name).frame.safe_m >= p.border_half_extent_m + p.plane_speed_m, name


@pytest.mark.parametrize("scenario", ["default", "narrow ring", "wide border", "border unseen", "wide border unseen"])
def test_a_camera_sees_the_dark_outside_only_where_the_scenario_draws_the_border(scenario):
    """A plane a step beyond the border, facing out, sees the dark outside under most of its camera when the
    border is drawn; undrawn (the release's sea runs on past its border) it sees only the water ring there, as
    it does short of the border, so nothing but its observed position tells it where the border is."""
    sim = simulator(scenario)
    p = sim.params
    trees, ground = random_island(np.random.default_rng(5), 1)
    beyond = p.border_half_extent_m + p.plane_speed_m
    position = np.array([[[beyond, 0.0], [0.0, -beyond], [beyond, beyond]]])
    heading = np.array([[0.0, -np.pi / 2, np.pi / 4]])  # outward: +x, -y and the corner's diagonal
    look = view.build_look(trees, ground, sim.frame_template, sim.frame)
    seen = view.plane_cameras(position, heading, look, trees, ground, sim.frame, sim.camera_offsets)
    outside = np.all(seen == PALETTE_FLOAT[OUTSIDE], axis=-1).mean(axis=(-1, -2))  # (1, 3) share of pixels
    ring = np.all(seen == PALETTE_FLOAT[WATER_RING], axis=-1).mean(axis=(-1, -2))
    if p.camera_sees_border:  # at least the half of the camera beyond the line, three quarters in the corner
        assert (outside >= [0.49, 0.49, 0.74]).all(), outside
    else:
        assert (outside == 0.0).all() and (ring == 1.0).all(), (outside, ring)


def test_planes_beyond_the_frame_take_the_exact_path(sim):
    rng = np.random.default_rng(3)
    trees, ground = random_island(rng, 2)
    position = np.array([[[0.0, 0.0], [2000.0, -100.0], [700.0, 700.0]], [[-5000.0, 3.0], [1.0, 2.0], [0.0, 760.0]]])
    heading = rng.uniform(-np.pi, np.pi, (2, 3))
    look = view.build_look(trees, ground, sim.frame_template, sim.frame)
    got = view.plane_cameras(position, heading, look, trees, ground, sim.frame, sim.camera_offsets)
    np.testing.assert_array_equal(got, cameras(position, heading, trees, ground, sim.camera_offsets, 600.0, 750.0))


def test_the_tiled_offset_is_the_cell_of_its_tile(sim):
    frame = sim.frame
    span = np.arange(-frame.pad, frame.side - frame.pad)
    rows, cols = np.meshgrid(span, span, indexing="ij")
    offset = view.tiled_offset(rows.ravel().copy(), cols.ravel().copy(), frame)
    r, c = rows.ravel() + frame.pad, cols.ravel() + frame.pad
    tiles = frame.side // view.TILE
    expected = ((r // 8) * tiles + c // 8) * 64 + (r % 8) * 8 + c % 8
    np.testing.assert_array_equal(offset, expected)


@pytest.mark.parametrize("count", [3, 300_000, 300_001])
def test_colour_triples_are_the_single_colours(count):
    index = np.random.default_rng(count).integers(0, len(PALETTE_FLOAT), count).astype(np.uint8)
    np.testing.assert_array_equal(view.colours(index), PALETTE_FLOAT[index])


@pytest.mark.parametrize("burn_list", ["age", "release"])  # the release's list shows trees burnt it ignited
def test_the_look_stays_the_picture_of_the_trees_through_fires_drops_and_restarts(burn_list):
    compiled = hivex_dsl.compile({"hivex": 1, "environment": "aerial_wildfire_suppression", "task": "main",
                                  "params": {"burn_list": burn_list}})
    sim = AerialWildfireSimulator(compiled)
    act = compiled.entry.scripted_policy(compiled)
    rng = np.random.default_rng(11)
    state = sim.reset(rng, 3)
    wet = 0
    for step in range(200):  # the pilot's first drops come after about 120 steps (3 m a step to the fire)
        state, _ = sim.step(state, act(sim.observe(state)), rng)
        wet += int(state.extinguished.sum() + state.prepared.sum())
        if step in (60, 130):
            state = sim.reset_where(state, np.array([True, False, step == 130]), rng)
    assert wet > 0  # drops happened
    fresh = view.build_look(state.fire.trees, state.maps.ground, sim.frame_template, sim.frame)
    np.testing.assert_array_equal(state.look, fresh)
    np.testing.assert_array_equal(sim.observe(state)["visual"], sim.derive(state).visual)


def test_a_fire_step_redraws_a_tree_the_release_showed_burnt_as_it_caught():
    """Under burn_list 'release' a tree can catch fire and fall in its list's oldest fifth in one step (a list that
    lost most of its trees): it goes to the doused list at age 0, BURNT, and the look must show it so."""
    sim = simulator("default")
    state = sim.reset(np.random.default_rng(3), 1)
    fire = state.fire
    cell = int(np.flatnonzero(fire.trees.reshape(-1) == TreeState.EXISTING)[0])
    fire.trees.reshape(-1)[cell] = TreeState.BURNT
    after = FireState(trees=fire.trees, burning=fire.burning, age=fire.age, quiet=fire.quiet, out=fire.out,
                      ignited=fire.ignited, burnt_out=fire.burnt_out, doused=np.array([cell]),
                      doused_age=np.zeros(1, np.int32))
    view.redraw_fire_step(state.look, fire.burning, after, sim.frame)
    np.testing.assert_array_equal(state.look, view.build_look(fire.trees, state.maps.ground, sim.frame_template,
                                                              sim.frame))


def test_the_observed_camera_is_read_only(sim):
    state = sim.reset(np.random.default_rng(0), 1)
    with pytest.raises(ValueError):
        sim.observe(state)["visual"][0, 0, 0, 0, 0] = 1.0


@pytest.mark.parametrize("batch", [1, 4])
def test_the_weather_read_where_fires_burn_is_the_weather_grid_read(sim, batch):
    rng = np.random.default_rng(batch)
    state = sim.reset(rng, batch)
    for _ in range(30):
        state = sim.step(state, {"continuous": np.zeros((batch, 3, 1), np.float32),
                                 "discrete": np.zeros((batch, 3, 1), np.int64)}, rng)[0]
    world, rest = np.divmod(state.fire.burning, CELLS * CELLS)
    rows, cols = np.divmod(rest, CELLS)
    spec, cells = sim.weather_spec, sim.params.weather_grid_cells
    lazy = weather_reader(state.weather, spec, 600.0, cells, sim.weather_lookup)(world, rows, cols)
    grid_reader = conditions_reader(sample_conditions(state.weather, spec, 600.0, cells), sim.weather_lookup)
    grid = grid_reader(world, rows, cols)
    assert len(world) > 0
    for got, expected in zip(lazy, grid):
        np.testing.assert_array_equal(got, expected)
