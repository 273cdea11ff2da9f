"""The drop's action mask of Drone-Based Reforestation and Aerial Wildfire Suppression (issue 52): which decisions
may drop, as the release's agents wrote it for ML-Agents (AWS: HivexAgent.WriteDiscreteActionMask read from the
release's IL; DBR: where a drop can plant, read from the original's Entropy panels), and what an untrained masked
policy's entropy then is against the original's first training point."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest
import torch

import hivex_dsl
from hivex_dsl.compiler import registry
from hivex_dsl.envs.aerial_wildfire_suppression import SEA_LEVEL_M
from hivex_dsl.envs.aerial_wildfire_suppression.simulator import MASK_TERRAIN_M
from hivex_dsl.envs.island import SEA
from hivex_dsl.evaluation.original.curves import original_curves
from hivex_dsl.runtime.contract import MasksActions
from hivex_dsl.train.config import make_config
from hivex_dsl.train.logs import EpisodeLog
from hivex_dsl.train.networks import ActorCritic
from hivex_dsl.train.ppo import collect, make_env, start_rollouts

AWS, DBR = "aerial_wildfire_suppression", "drone_based_reforestation"
AWS_CELL, AWS_HALF = 3.0, 600.0
GAUSSIAN_ENTROPY = 0.5 + 0.5 * np.log(2 * np.pi)  # a unit Gaussian's, ML-Agents' mean over its dimensions


def simulator(environment: str, **fields):
    compiled = hivex_dsl.compile({"hivex": 1, "environment": environment, **fields})
    sim = compiled.entry.make_simulator(compiled)
    return sim, sim.reset(np.random.default_rng(0), 1)


def test_only_the_two_environments_with_a_drop_mask_their_actions():
    masking = {env for env in registry.environments()
               if isinstance(simulator(env)[0], MasksActions)}
    assert masking == {AWS, DBR}


def aws_world(sim, state, planes, water=True, flying=True):
    """Planes at [(x, y)] over a sea floor at 0 m, a low shore of 3 m (x in [0, 100)) and high ground of 20 m
    (x in [100, 300)), each having last cast its ray where it is placed (either terrain_cast reads the same)."""
    height = np.zeros_like(state.maps.height)
    cols = (np.arange(height.shape[-1]) + 0.5) * AWS_CELL - AWS_HALF
    height[..., (cols >= 0) & (cols < 100)] = 3.0
    height[..., (cols >= 100) & (cols < 300)] = 20.0
    ground = np.where(height > SEA_LEVEL_M, 0, SEA).astype(state.maps.ground.dtype)
    shape = (1, len(planes))
    position = np.array([planes], float)
    return replace(state, maps=replace(state.maps, height=height, ground=ground),
                   position=position, cast_at=position.copy(), heading=np.zeros(shape),
                   water=np.broadcast_to(np.asarray(water), shape).copy(),
                   flying=np.broadcast_to(np.asarray(flying), shape).copy())


def test_the_aws_drop_opens_over_terrain_as_the_release_wrote_it_and_drops_only_over_high_ground():
    sim, state = simulator(AWS, agents=4)
    state = aws_world(sim, state, [(50.0, 0.0), (200.0, 0.0), (-200.0, 0.0), (200.0, 50.0)],
                      water=[True, True, True, False])
    mask = sim.action_mask(state)
    assert mask.shape == (1, 4, 2) and mask.dtype == bool
    assert mask[0, :, 0].all()  # doing nothing is always open
    # low shore (3 m >= 0.02): open; high ground: open; sea floor (0 m): closed; no water: closed
    assert mask[0, :, 1].tolist() == [True, True, False, False]
    assert 0.0 < MASK_TERRAIN_M < 3.0 < SEA_LEVEL_M < 20.0
    # a drop asked for everywhere: over the shore the open branch does nothing (the release's DropWater needs
    # higher ground than its mask), over high ground it drops
    actions = {"continuous": np.zeros((1, 4, 1), np.float32), "discrete": np.ones((1, 4, 1), np.int64)}
    after, outcome = sim.step(state, actions, np.random.default_rng(0))
    assert outcome.events["dropped_water"][0].tolist() == [False, True, False, False]
    assert sim.action_mask(after)[0, :, 1].tolist() == [True, False, False, False]  # the shore plane keeps its water


def test_the_mask_knows_no_task_so_find_task_planes_keep_their_water_and_an_open_branch():
    sim, state = simulator(AWS, agents=2, task="find_fire")
    state = aws_world(sim, state, [(200.0, 0.0), (-200.0, 0.0)])
    assert not sim.handles_water
    assert sim.action_mask(state)[0, :, 1].tolist() == [True, False]


def test_the_dbr_drop_opens_to_a_living_seed_holder_at_least_the_drop_distance_from_its_station():
    sim, state = simulator(DBR, agents=5)
    far = sim.params.drop_min_distance_m
    station = state.station[0]
    offsets = [(far + 0.5, 0.0, 0.0), (far - 0.5, 0.0, 0.0), (0.0, far * 0.8, far * 0.8), (far + 5, 0.0, 0.0),
               (far + 5, 0.0, 0.0)]
    position = (station + np.array(offsets))[None]
    state = replace(state, position=position, holding=np.array([[True, True, True, False, True]]),
                    alive=np.array([[True, True, True, True, False]]))
    mask = sim.action_mask(state)
    assert mask[0, :, 0].all()
    # 3D distance: the third drone is 1.13 x the drop distance away, up and out
    assert mask[0, :, 1].tolist() == [True, False, True, False, False]


def untrained_entropy(environment: str, task: str, level: int, action_masks: bool = True) -> float:
    """The mean policy entropy of an untrained network (ML-Agents' initialisation, seed 0) over every decision of
    one world-episode of the trainer's protocol: the original's first training point is one world-episode
    (9,000 plane-steps in AWS, 6,000 in DBR) of its untrained policy."""
    compiled = hivex_dsl.compile({"hivex": 1, "environment": environment, "task": task, "terrain_level": level})
    cfg = make_config(environment, {"action_masks": action_masks})
    torch.manual_seed(0)
    env, obs, infos = make_env(compiled, 1, "train", cfg.ended_agents)
    agent = ActorCritic(env.single_observation_space, env.single_action_space, cfg)
    state, buf = start_rollouts(obs, agent, compiled.episode_decisions, infos)
    collect(env, agent, buf, state, cfg, EpisodeLog())
    mask = None if buf.mask is None else buf.flat("mask")
    with torch.no_grad():
        _, entropy, _ = agent.evaluate(buf.flat_obs(), buf.flat("cont"), buf.flat("disc"), mask)
    return float(entropy[buf.flat("valid") > 0].mean())


def original_first_entropy(environment: str, task_index: int, level: int) -> float:
    return float(original_curves(environment, task_index, level).panel("Entropy").training.mean[0])


@pytest.mark.parametrize("environment, task, level, tolerance", [
    (DBR, "main", 1, 0.005),  # the branch open about one decision in 300 there (0.0014 of entropy), here as seldom
    # the original's branch open about 9.6% of decisions (1.486); ours 6.0% (1.460) under today's defaults, the
    # release's plane rules, frame cast, whole drop mask and fire (6.7%, 1.466, under this toolkit's fire start and
    # age-kept burning list at 22 steps, the defaults until session 89, in this one world-episode; 5.6% under the
    # mask open to flying planes alone, the default until session 47; 2.7% under the per-step cast; 7% under the
    # lone planes): the 7 m sea that stands for the release's 10 m drop threshold makes a drop over 7-10 m ground
    # work, and close the branch, where the release's planes kept their water and the branch open there (the reward
    # table's note 'What the cameras see past the border ...'); 0.025 short of the original's entropy (0.020 under
    # the fire before), 'flying' 0.028 short
    (AWS, "main", 1, 0.03),
])
def test_an_untrained_masked_policy_starts_at_the_original_s_entropy(environment, task, level, tolerance):
    first = original_first_entropy(environment, 0, level)
    masked = untrained_entropy(environment, task, level)
    assert abs(masked - first) < tolerance, (masked, first)


def test_without_masks_the_untrained_policy_starts_far_above_the_original():
    """Every choice open: the Gaussian's entropy and ln 2 of a near-uniform drop branch at every decision, 2.112,
    which no point of the original's DBR curves reaches (they stay within 1.29-1.47)."""
    unmasked = untrained_entropy(DBR, "main", 1, action_masks=False)
    assert unmasked == pytest.approx(GAUSSIAN_ENTROPY + np.log(2), abs=2e-3)
    assert unmasked - original_first_entropy(DBR, 0, 1) > 0.6


def ring_terrain(sim, state, metres: float = 1.0, start_x: float = 610.0, end_x: float = 720.0):
    """``state`` with its whole terrain at 0 m but for ``metres`` under the water ring at x in [start_x, end_x]."""
    grid = sim.terrain_grid
    x = grid.origin + np.arange(grid.n) * grid.cell
    terrain = np.zeros_like(state.maps.terrain)
    terrain[..., (x >= start_x) & (x <= end_x)] = metres
    return replace(state, maps=replace(state.maps, terrain=terrain))


@pytest.mark.parametrize("drop_mask, opened", [("flying", [True, False, False, False]),
                                               ("release", [True, True, True, False])])
def test_the_release_s_mask_opens_to_waiting_planes_and_over_the_ring_s_seabed(drop_mask, opened):
    """params.drop_mask 'release': the release's WriteDiscreteActionMask tests neither the freeze flag nor the
    island's edge. Planes holding water: flying over high ground; waiting over high ground; flying over the ring
    (650 m) above 1 m of seabed; waiting past the border (760 m) above 0 m. None of the drops it opens does
    anything (a waiting plane does not drop; the ring is no land), and reading the mask changes nothing."""
    sim, state = simulator(AWS, agents=4, params={"drop_mask": drop_mask})
    state = aws_world(sim, state, [(200.0, 0.0), (200.0, 30.0), (650.0, 0.0), (760.0, 0.0)],
                      flying=[True, False, True, False])
    state = ring_terrain(sim, state)
    water = state.water.copy()
    assert sim.action_mask(state)[0, :, 1].tolist() == opened
    np.testing.assert_array_equal(state.water, water)
    actions = {"continuous": np.zeros((1, 4, 1), np.float32), "discrete": np.ones((1, 4, 1), np.int64)}
    after, outcome = sim.step(state, actions, np.random.default_rng(0))
    assert outcome.events["dropped_water"][0].tolist() == [True, False, False, False]
    assert after.water[0].tolist() == [False, True, True, True]


def test_the_whole_terrain_is_the_generator_s_map_and_the_island_s_heights_are_read_from_it():
    """The maps keep the terrain generator's whole height map (241 nodes over 1,666 m), and the forest grid's
    heights are that map's bilinear surface at the cells' centres."""
    from hivex_dsl.sim.grids import sample_bilinear

    sim, state = simulator(AWS)
    grid = sim.terrain_grid
    assert state.maps.terrain.shape == (1, 241, 241)
    assert (grid.origin, grid.n) == (-833.0, 241) and grid.cell == pytest.approx(1666.0 / 240)
    centres = (np.arange(400) + 0.5) * AWS_CELL - AWS_HALF
    rows = np.array([7, 200, 391])
    points = np.stack(np.broadcast_arrays(centres[None, :], centres[rows][:, None]), -1).reshape(1, -1, 2)
    read = sample_bilinear(state.maps.terrain, grid, points).reshape(len(rows), 400)
    np.testing.assert_allclose(read, state.maps.height[0, rows], atol=1e-3)
