"""Aerial Wildfire Suppression by hand: flight, border, water, drops, sightings and one-off rewards.

Each test builds a world, places planes and trees exactly, steps once and compares with values
worked out from the rules in ENVIRONMENTS.md and the paper.
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest

import hivex_dsl
from hivex_dsl.envs.aerial_wildfire_suppression.simulator import AerialWildfireSimulator
from hivex_dsl.sim.fire import TreeState, fire_reset
from hivex_dsl.runtime import BatchedEnv
from ..aws_rules import LONE_PLANES

CELL = 3.0
HALF = 600.0


@pytest.fixture(scope="module")
def compiled():
    # the camera's test looks at its picture; the mechanics worked by hand are those of the lone planes
    return hivex_dsl.compile({"hivex": 1, "environment": "aerial_wildfire_suppression", "agents": 2,
                              "params": {"camera_images": "rendered", **LONE_PLANES}})


@pytest.fixture(scope="module")
def base(compiled):
    sim = AerialWildfireSimulator(compiled)
    return sim, sim.reset(np.random.default_rng(0), 1)


def cell_of(x: float, y: float) -> tuple[int, int]:
    return int((y + HALF) // CELL), int((x + HALF) // CELL)


def centre_of(x: float, y: float) -> tuple[float, float]:
    """The centre of the forest cell holding (x, y), where the engine places its tree."""
    row, col = cell_of(x, y)
    return (col + 0.5) * CELL - HALF, (row + 0.5) * CELL - HALF


def world(base, planes, trees=(), water=True, village=(-400.0, -400.0)):
    """State with planes [(x, y, heading_deg)], only ``trees`` [(x, y, TreeState)] and flat land everywhere; each
    plane last cast its ray where it is placed (under terrain_cast 'frame' as under 'step')."""
    sim, state = base
    exists = np.zeros((1, 400, 400), bool)
    ignite = np.zeros((1, 400, 400), bool)
    for x, y, kind in trees:
        r, c = cell_of(x, y)
        exists[0, r, c] = True
        ignite[0, r, c] = kind == TreeState.BURNING
    fire = fire_reset(exists, ignite)
    n = len(planes)
    maps = replace(state.maps, ground=np.zeros_like(state.maps.ground), height=np.zeros_like(state.maps.height),
                   village=np.array([village]))
    shape = (1, n)
    position = np.array([[[x, y] for x, y, _ in planes]], float)
    new = replace(state, maps=maps, fire=fire, position=position, cast_at=position.copy(),
                  heading=np.radians(np.array([[h for _, _, h in planes]], float)),
                  water=np.full(shape, water), flying=np.ones(shape, bool),
                  seen_fire=np.zeros(shape, bool), seen_village=np.zeros(shape, bool), village_hit=np.zeros(1, bool),
                  village_reached=np.zeros(1, bool))
    return sim, sim.derive(new)


def act(steer, drop):
    steer, drop = np.asarray(steer, np.float32), np.asarray(drop, np.int64)
    return {"continuous": steer.reshape(1, -1, 1), "discrete": drop.reshape(1, -1, 1)}


def term(compiled, name, prev, new):
    return compiled.entry.terms[name](prev, new, None, compiled.params)


def test_a_plane_turns_5_degrees_per_unit_of_steer_then_flies_3_m(base):
    sim, state = world(base, [(0.0, 0.0, 0.0), (100.0, 100.0, 90.0)])
    new, _ = sim.step(state, act([1.0, -0.5], [0, 0]), np.random.default_rng(1))
    assert np.allclose(np.degrees(new.heading[0]), [5.0, 87.5])
    # 3 m a step: fitted to the original's Pick Up Water pages (issue 52; the release's figure was 5 m)
    expected = [[3 * np.cos(np.radians(5)), 3 * np.sin(np.radians(5))],
                [100 + 3 * np.cos(np.radians(87.5)), 100 + 3 * np.sin(np.radians(87.5))]]
    assert np.allclose(new.position[0], expected)


def test_crossing_the_border_costs_100_ends_that_plane_and_freezes_it(compiled, base):
    sim, state = world(base, [(748.0, 0.0, 0.0), (0.0, 0.0, 0.0)])  # 3 m on: 751 m, past the 750 m border
    new, outcome = sim.step(state, act([0, 0], [0, 0]), np.random.default_rng(1))
    assert outcome.terminated[0].tolist() == [True, False]
    assert term(compiled, "crossed_border", state, new)[0].tolist() == [-100.0, 0.0]
    later, outcome = sim.step(new, act([1, 0], [0, 0]), np.random.default_rng(2))
    assert np.array_equal(later.position[0, 0], new.position[0, 0]) and not later.flying[0, 0]
    assert not outcome.terminated[0, 0]  # the crossing is reported once


def test_entering_the_water_ring_without_water_fills_up_once(compiled, base):
    sim, state = world(base, [(598.0, 0.0, 0.0), (0.0, 0.0, 0.0)], water=False)  # 3 m on: 601 m, over the ring
    new, outcome = sim.step(state, act([0, 0], [0, 0]), np.random.default_rng(1))
    assert new.water[0].tolist() == [True, False]
    assert outcome.events["picked_up_water"][0].tolist() == [True, False]
    assert term(compiled, "pick_up_water", state, new)[0].tolist() == [1.0, 0.0]
    assert term(compiled, "time_step_without_water", state, new)[0].tolist() == [0.0, -100.0 / 3000.0]
    again, outcome = sim.step(new, act([0, 0], [0, 0]), np.random.default_rng(2))
    assert not outcome.events["picked_up_water"][0, 0]


def test_a_drop_wets_existing_and_burning_trees_within_30_m_of_the_four_points(compiled, base):
    # plane at the origin heading +x: swath points at x = 5, 25, 45, 65 after the move
    trees = [(15.0, 0.0, TreeState.BURNING),    # 10 m past point 1: extinguished
             (70.0, 20.0, TreeState.EXISTING),  # 20.6 m from point 4: prepared
             (5.0, 28.0, TreeState.EXISTING),   # about 28 m from point 1: prepared
             (100.0, 0.0, TreeState.EXISTING),  # 35 m beyond point 4: dry
             (25.0, -40.0, TreeState.BURNING)]  # 40 m beside point 2: still burning
    sim, state = world(base, [(0.0, 0.0, 0.0), (300.0, 300.0, 0.0)], trees)
    new, outcome = sim.step(state, act([0, 0], [1, 0]), np.random.default_rng(1))
    assert outcome.events["dropped_water"][0].tolist() == [True, False]
    assert new.extinguished[0].tolist() == [1, 0] and new.prepared[0].tolist() == [2, 0]
    assert term(compiled, "extinguishing_tree", state, new)[0].tolist() == [5.0, 0.0]
    assert term(compiled, "preparing_tree", state, new)[0].tolist() == [2.0, 0.0]
    assert new.water[0].tolist() == [False, True]
    states = [int(new.fire.trees[0][cell_of(x, y)]) for x, y, _ in trees]
    assert states == [TreeState.WET, TreeState.WET, TreeState.WET, TreeState.EXISTING, TreeState.BURNING]


def test_no_drop_without_water_or_over_the_water_ring(base):
    # plane 2 ends the move at x = 605 heading -x: over the ring, its swath would reach the tree at 590
    trees = [(10.0, 0.0, TreeState.BURNING), (590.0, 100.0, TreeState.EXISTING)]
    sim, state = world(base, [(0.0, 0.0, 0.0), (610.0, 100.0, 180.0)], trees, water=False)
    state = replace(state, water=np.array([[False, True]]))
    new, outcome = sim.step(state, act([0, 0], [1, 1]), np.random.default_rng(1))
    assert not outcome.events["dropped_water"].any()
    assert new.water[0].tolist() == [False, True]
    assert new.extinguished.sum() == 0 and new.prepared.sum() == 0


def test_the_closest_burning_tree_in_the_view_square_is_observed(base):
    trees = [(100.0, 100.0, TreeState.BURNING), (-145.0, 10.0, TreeState.BURNING), (0.0, 170.0, TreeState.BURNING)]
    sim, state = world(base, [(0.0, 0.0, 90.0), (0.0, 400.0, 0.0)], trees)
    vector = sim.observe(state)["vector"][0]
    cx, cy = centre_of(100.0, 100.0)
    assert np.allclose(vector[0, 5:8], [cx / 750, cy / 750, 1.0], atol=1e-6)  # 141.4 m < 145.3 m
    assert np.allclose(vector[1, 5:8], [0.0, 0.0, 0.0])  # (0, 170) is 230 m from (0, 400): outside +/-150
    assert np.allclose(vector[0, :5], [0.0, 0.0, 0.0, 1.0, 1.0], atol=1e-6)


def test_find_fire_and_find_village_pay_once_per_episode(compiled, base):
    trees = [(0.0, 120.0, TreeState.BURNING)]
    sim, state = world(base, [(0.0, 0.0, 0.0), (-400.0, -287.0, -90.0)], trees, village=(-400.0, -400.0))
    state = replace(state, maps=replace(state.maps, terrain=np.zeros_like(state.maps.terrain)))  # all at 0 m
    first, outcome = sim.step(state, act([0, 0], [0, 0]), np.random.default_rng(1))
    assert term(compiled, "find_fire", state, first)[0].tolist() == [100.0, 0.0]
    # the release's 3-D distance from 100 m up (village_distance): 113 m away, sqrt(113^2 + 100^2) = 150.9 m; after
    # the 3 m move 110 m, 148.7 m
    assert term(compiled, "find_village", state, first)[0].tolist() == [0.0, 100.0]
    assert outcome.events["found_fire"][0].tolist() == [True, False]
    second, outcome = sim.step(first, act([0, 0], [0, 0]), np.random.default_rng(2))
    assert term(compiled, "find_fire", first, second).sum() == 0 and term(compiled, "find_village", first, second).sum() == 0


def test_fire_near_the_village_costs_every_plane_50_once(compiled, base):
    trees = [(-400.0, -290.0, TreeState.BURNING)]  # 110 m from the village centre
    sim, state = world(base, [(0.0, 0.0, 0.0), (10.0, 0.0, 0.0)], trees)
    first, _ = sim.step(state, act([0, 0], [0, 0]), np.random.default_rng(1))
    assert term(compiled, "too_close_to_village", state, first)[0].tolist() == [-50.0, -50.0]
    second, _ = sim.step(first, act([0, 0], [0, 0]), np.random.default_rng(2))
    assert term(compiled, "too_close_to_village", first, second).sum() == 0.0
    assert term(compiled, "time_step_burning", first, second)[0].tolist() == [-0.01, -0.01]


def test_the_fire_going_out_pays_10_and_is_an_event_for_every_plane(compiled, base):
    trees = [(200.0, 200.0, TreeState.BURNING)]
    sim, state = world(base, [(0.0, 0.0, 0.0), (10.0, 0.0, 0.0)], trees)
    state = replace(state, position=np.array([[[195.0, 200.0], [10.0, 0.0]]]))
    new, outcome = sim.step(state, act([0, 0], [1, 0]), np.random.default_rng(1))
    # extinguished, but still spreading (extinguished_spread, the release's fire): nothing is left to catch, so it
    # goes out once quiet_steps_out fire steps lit nothing
    assert new.extinguished[0, 0] == 1 and new.fire.burning.size == 0 and new.fire.doused.size == 1
    assert new.burning[0]
    steps = 0
    while not outcome.events["fire_out"].any():
        new, outcome = sim.step(new, act([0, 0], [0, 0]), np.random.default_rng(steps))
        steps += 1
        assert steps <= 10 * compiled.params.fire_step_interval * compiled.params.quiet_steps_out
    assert outcome.events["fire_out"][0].tolist() == [True, True]
    assert term(compiled, "fire_out", new, new)[0].tolist() == [10.0, 10.0]


@pytest.mark.parametrize("task", ["find_fire", "find_village"])
@pytest.mark.parametrize("water_in_find_tasks", [False, True])
def test_the_find_tasks_planes_neither_drop_nor_refill_unless_told_to(task, water_in_find_tasks):
    """The release's Find Fire and Find Village call neither DropWater nor PickupWater: one plane over land holding
    water asks to drop over a tree, another without water crosses into the ring. Told to (the rule before), both
    act as in every other task."""
    compiled = hivex_dsl.compile({"hivex": 1, "environment": "aerial_wildfire_suppression", "agents": 2, "task": task,
                                  "params": {"water_in_find_tasks": water_in_find_tasks}})
    sim = AerialWildfireSimulator(compiled)
    _, state = world((sim, sim.reset(np.random.default_rng(0), 1)), [(0.0, 0.0, 0.0), (598.0, 300.0, 0.0)],
                     [(15.0, 0.0, TreeState.EXISTING)])
    state = replace(state, water=np.array([[True, False]]))
    new, outcome = sim.step(state, act([0, 0], [1, 0]), np.random.default_rng(1))
    acts = water_in_find_tasks
    assert outcome.events["dropped_water"][0].tolist() == [acts, False]
    assert outcome.events["picked_up_water"][0].tolist() == [False, acts]
    assert new.water[0].tolist() == [not acts, acts] and new.prepared[0].tolist() == [int(acts), 0]


@pytest.mark.parametrize("task, holding", [("main", True), ("pick_up_water", False), ("find_fire", True)])
def test_planes_start_with_water_except_when_the_task_ends_on_picking_it_up(task, holding):
    compiled = hivex_dsl.compile({"hivex": 1, "environment": "aerial_wildfire_suppression", "task": task})
    state = AerialWildfireSimulator(compiled).reset(np.random.default_rng(3), 2)
    assert state.water.all() == holding and state.water.any() == holding


def test_planes_spawn_within_750_m_of_the_centre_and_inside_the_border(compiled):
    state = AerialWildfireSimulator(compiled).reset(np.random.default_rng(4), 3)
    assert (np.hypot(state.position[..., 0], state.position[..., 1]) <= 750.0 + 1e-9).all()
    assert (np.abs(state.position) <= 750.0).all()


def test_the_camera_looks_down_with_forward_up_and_right_to_the_right(base):
    from hivex_dsl.envs.aerial_wildfire_suppression.camera import PALETTE_FLOAT, TREE_BASE

    # heading north: pixel (row i, col j) sees forward (20.5 - i) * 5 m and right (j - 20.5) * 5 m
    ahead, right = (-2.5, 52.5), (72.5, 2.5)  # what pixels (10, 20) and (20, 35) see
    trees = [(*ahead, TreeState.BURNING), (*right, TreeState.EXISTING)]
    sim, state = world(base, [(0.0, 0.0, 90.0)], trees)
    visual = sim.observe(state)["visual"][0, 0]
    assert visual.shape == (42, 42, 3) and visual.min() >= 0.0 and visual.max() <= 1.0
    assert np.allclose(visual[10, 20], PALETTE_FLOAT[TREE_BASE + TreeState.BURNING])
    assert np.allclose(visual[20, 35], PALETTE_FLOAT[TREE_BASE + TreeState.EXISTING])
    assert np.allclose(visual[31, 20], PALETTE_FLOAT[0])  # behind the plane: bare flat ground (shade 0)
    assert np.allclose(visual[20, 6], PALETTE_FLOAT[0])  # to the left: nothing


@pytest.mark.parametrize("override, message", [
    ({"params": {"drop_radius_m": 60.0}}, "params.drop_radius_m: a drop of 4 points of 60 m over 3 m cells could wet up to"),
    ({"params": {"island_half_extent_m": 500.0}}, "generators.forest.half_extent_m: 600 m must equal the island's half extent"),
    ({"generators": {"terrain": {"extent_m": 1150.0}}}, "generators.terrain.extent_m: 1150 m does not cover the forest"),
])
def test_worlds_that_cannot_work_are_compile_errors(override, message):
    from hivex_dsl.base.errors import ScenarioError

    with pytest.raises(ScenarioError) as info:
        hivex_dsl.compile({"hivex": 1, "environment": "aerial_wildfire_suppression", **override})
    assert any(p.message.startswith(message) for p in info.value.problems), info.value.problems


@pytest.mark.parametrize("redraw", ["seed", "episode"])
def test_a_world_starting_a_new_episode_keeps_its_island_unless_told_otherwise(redraw):
    compiled = hivex_dsl.compile({"hivex": 1, "environment": "aerial_wildfire_suppression",
                                  "params": {"redraw_island": redraw, **LONE_PLANES}})
    sim = AerialWildfireSimulator(compiled)
    rng = np.random.default_rng(5)
    state = sim.reset(rng, 2)
    before_height, before_trees = state.maps.height.copy(), state.fire.trees.copy()
    for _ in range(2 * compiled.params.fire_step_interval):  # two fire steps: world 0 gets trees to clear
        state, _ = sim.step(state, act_batch(2, 3), rng)
    assert (state.fire.trees[0] != before_trees[0]).any()
    other = state.fire.trees[1].copy()
    new = sim.reset_where(state, np.array([True, False]), rng)
    kept = np.array_equal(new.maps.height[0], before_height[0])
    assert kept == (redraw == "seed")
    assert np.array_equal(new.maps.height[1], before_height[1]) and np.array_equal(new.fire.trees[1], other)
    fresh = new.fire.trees[0]
    assert not np.isin(fresh, [TreeState.BURNT, TreeState.WET]).any()
    assert np.array_equal(fresh != TreeState.NONE, new.maps.exists[0]) and (fresh == TreeState.BURNING).sum() > 15


def act_batch(batch, agents):
    return {"continuous": np.zeros((batch, agents, 1), np.float32), "discrete": np.zeros((batch, agents, 1), np.int64)}


@pytest.mark.parametrize("environment", ["aerial_wildfire_suppression", "wildfire_resource_management",
                                         "drone_based_reforestation"])
def test_by_default_every_episode_of_a_seed_stream_draws_a_new_world(environment):
    def height_map(state):  # DBR keeps its terrain in ``heights``, the island environments in ``maps``
        return (state.heights if environment == "drone_based_reforestation" else state.maps.height).copy()

    lone = {"params": LONE_PLANES} if environment == "aerial_wildfire_suppression" else {}  # worlds that do not go on
    env = hivex_dsl.parallel_env({"hivex": 1, "environment": environment, "episode_length": 5, **lone})  # DBR: 5th
    env.reset(seed=1)
    first = height_map(env.core.state)
    env.reset()  # continues the stream: a new world
    assert not np.array_equal(height_map(env.core.state), first)


def test_the_parallel_env_keeps_the_island_while_episodes_continue_a_seed_stream_when_told_to():
    env = hivex_dsl.parallel_env({"hivex": 1, "environment": "aerial_wildfire_suppression", "episode_length": 3,
                                  "params": {"redraw_island": "seed"}})
    env.reset(seed=1)
    first = env.core.state.maps.height.copy()
    env.reset()  # continues the stream: same island, a new fire
    assert np.array_equal(env.core.state.maps.height, first)
    env.reset(seed=2)  # a new seed starts a new stream: a new island
    assert not np.array_equal(env.core.state.maps.height, first)
    listed = hivex_dsl.parallel_env({"hivex": 1, "environment": "aerial_wildfire_suppression",
                                     "seeds": {"train": [1, 2], "test": 3}, "params": {"redraw_island": "seed"}})
    listed.reset()
    assert np.array_equal(listed.core.state.maps.height, first)  # the list's first seed is seed 1


def test_a_plane_whose_task_ended_stops_flying_and_changing_the_world():
    compiled = hivex_dsl.compile({"hivex": 1, "environment": "aerial_wildfire_suppression", "task": "drop_water",
                                  "agents": 2})
    sim = AerialWildfireSimulator(compiled)
    _, state = world((sim, sim.reset(np.random.default_rng(0), 1)),
                     [(0.0, 0.0, 0.0), (300.0, 300.0, 0.0)], [(15.0, 0.0, TreeState.EXISTING)])
    state = replace(state, water=np.array([[True, True]]))
    new, outcome = sim.step(state, act([0, 0], [1, 0]), np.random.default_rng(1))
    assert outcome.events["dropped_water"][0].tolist() == [True, False]
    assert new.flying[0].tolist() == [False, True]
    later, _ = sim.step(new, act([1, 1], [1, 1]), np.random.default_rng(2))
    assert np.array_equal(later.position[0, 0], new.position[0, 0])  # frozen, no second drop
    assert later.dropped[0].tolist() == [False, True]


@pytest.mark.parametrize("generators, message", [
    ({"ignition": {"min_village_distance_m": 2000.0}},
     "generators.ignition.min_village_distance_m: 2000 m leaves no candidate cell"),
    ({"ignition": {"min_burning": 100000}}, "generators.ignition.min_burning: 100000 trees can never burn"),
])
def test_ignition_that_can_never_work_is_a_compile_error(generators, message):
    from hivex_dsl.base.errors import ScenarioError

    with pytest.raises(ScenarioError) as info:
        hivex_dsl.compile({"hivex": 1, "environment": "aerial_wildfire_suppression", "generators": generators})
    assert any(p.message.startswith(message) for p in info.value.problems), info.value.problems


def test_a_forest_too_sparse_to_light_as_asked_starts_with_what_it_has():
    # trees only on a thin band of heights: the candidate blocks may hold fewer than min_burning trees, or none
    compiled = hivex_dsl.compile({"hivex": 1, "environment": "aerial_wildfire_suppression",
                                  "generators": {"forest": {"min_height_m": 90.0, "ideal_height_m": 95.0},
                                                 "ignition": {"min_burning": 5000}}})
    state = AerialWildfireSimulator(compiled).reset(np.random.default_rng(1), 2)
    burning = (state.fire.trees == TreeState.BURNING).sum(axis=(1, 2))
    assert (burning <= 5000).all()
    assert np.array_equal(state.fire.trees != TreeState.NONE, state.maps.exists)


def test_what_a_plane_saw_when_its_task_ended_does_not_depend_on_other_worlds_resetting():
    """A plane that finds fire ends its find-fire episode with that sighting in its last observation,
    whether or not another world of the batch starts a new episode in the same step."""
    sc = hivex_dsl.compile({"hivex": 1, "environment": "aerial_wildfire_suppression", "task": "find_fire",
                            "params": LONE_PLANES})  # a finder's episode ends as it finds
    env = BatchedEnv(sc, 2)
    observations = env.reset(seed=4)
    pilot = sc.entry.scripted_policy(sc)
    for _ in range(500):
        result = env.step(pilot(observations))
        observations = result.observations
        if result.terminated[0].any():
            break
    ended = result.terminated[0]
    assert ended.any() and (observations["vector"][0, ended, 7] == 1.0).all()
    after = env.reset_worlds(np.array([False, True]))
    for key in observations:
        np.testing.assert_array_equal(after[key][0], observations[key][0], err_msg=key)


@pytest.mark.parametrize("task", ["pick_up_water", "find_village"])
def test_nothing_is_paid_on_the_first_step_for_where_a_plane_happens_to_start(task):
    # issue 15: a plane without water spawning over the water ring filled up (+1, x100 in Pick Up Water) and one
    # spawning within 150 m of the village found it (+100) on the first step, whatever it did
    compiled = hivex_dsl.compile({"hivex": 1, "environment": "aerial_wildfire_suppression", "task": task,
                                  "params": LONE_PLANES})  # this toolkit's spawn keeps them away
    sim = AerialWildfireSimulator(compiled)
    state = sim.reset(np.random.default_rng(7), 64)
    gap = state.position - state.maps.village[:, None, :]
    assert (np.hypot(gap[..., 0], gap[..., 1]) >= 156.0 - 1e-9).all()  # two 3 m steps outside its 150 m
    if task == "pick_up_water":  # over the island, two 3 m steps from the ring at least
        assert (np.abs(state.position) <= 594.0).all() and not state.water.any()
    new, _ = sim.step(state, act_batch(64, 3), np.random.default_rng(1))  # one step straight on: 3 m
    assert not new.picked_up.any() and not new.found_village.any()


def test_no_plane_starts_or_respawns_with_the_fire_in_view():
    """Uniform spawns put about one plane in eleven within sight of the fire (measured with the redraw off),
    which would pay Find Fire on the first step for nothing; the fire, like the village, is found by flying (this
    toolkit's spawn; the release's keeps nothing away)."""
    compiled = hivex_dsl.compile({"hivex": 1, "environment": "aerial_wildfire_suppression", "params": LONE_PLANES})
    sim = AerialWildfireSimulator(compiled)
    rng = np.random.default_rng(3)
    state = sim.reset(rng, 128)
    assert not state.sighting.plane_found.any()
    for _ in range(3 * compiled.params.fire_step_interval):  # the fire grows: more of the island is in its sight
        state, _ = sim.step(state, act_batch(128, 3), rng)
    mask = np.zeros((128, 3), bool)
    mask[:, 0] = True
    respawned = sim.respawn_where(state, mask, rng)
    assert not respawned.sighting.plane_found[:, 0].any()
    assert np.array_equal(respawned.position[:, 1:], state.position[:, 1:])


def test_a_spawn_is_drawn_again_only_where_it_sees_the_fire(monkeypatch):
    import hivex_dsl.envs.aerial_wildfire_suppression.spawn as spawn

    compiled = hivex_dsl.compile({"hivex": 1, "environment": "aerial_wildfire_suppression", "params": LONE_PLANES})
    sim = AerialWildfireSimulator(compiled)
    monkeypatch.setattr(spawn, "SPAWN_REDRAWS", 0)
    uniform = sim.reset(np.random.default_rng(3), 128)
    sees = uniform.sighting.plane_found
    assert 0.02 < sees.mean() < 0.2  # the case exists, and is not the rule
    monkeypatch.setattr(spawn, "SPAWN_REDRAWS", 16)
    redrawn = sim.reset(np.random.default_rng(3), 128)
    assert np.array_equal(redrawn.position[~sees], uniform.position[~sees])
    assert not np.isclose(redrawn.position[sees], uniform.position[sees]).all(axis=-1).any()
