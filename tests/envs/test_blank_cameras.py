"""The original's runs saw blank cameras (every config that ran sets no_graphics), and so does a scenario by default:
the visual observation keeps its space but holds zeros, and nothing else of the world changes with it."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
import yaml

import hivex_dsl
from hivex_dsl.evaluation.policies import make_policy
from hivex_dsl.runtime import BatchedEnv

CAMERA_ENVIRONMENTS = ("aerial_wildfire_suppression", "drone_based_reforestation")
RENDERED = {"camera_images": "rendered"}


def test_every_config_that_ran_started_unity_without_graphics(paper: Path):
    configs = sorted((paper / "original-configs").glob("*/*.yaml"))
    assert len(configs) == 13  # 5 training configs, 8 test configs
    for path in configs:
        assert yaml.safe_load(path.read_text())["engine_settings"] == {"no_graphics": True}, path.name


def _episode_start(environment: str, params: dict | None = None, steps: int = 12, seed: int = 3):
    """Observations, rewards and vector observations of ``steps`` random steps of one world (B = 1)."""
    compiled = hivex_dsl.compile({"hivex": 1, "environment": environment, "params": params or {}})
    core = BatchedEnv(compiled, batch=1, split="test")
    policy = make_policy("random", compiled, core.sim.action_space, core.shape, seed=seed)
    observations = [core.reset(seed)]
    rewards = []
    for _ in range(steps):
        outcome = core.step(policy(observations[-1]))
        observations.append(outcome.observations)
        rewards.append(outcome.rewards)
    return compiled, core, observations, np.array(rewards)


@pytest.mark.parametrize("environment", CAMERA_ENVIRONMENTS)
def test_a_blank_camera_keeps_its_space_and_sends_zeros(environment):
    compiled, core, observations, _ = _episode_start(environment)
    assert compiled.params.camera_images == "blank"
    visual_space = core.sim.observation_space["visual"]
    for obs in observations:
        assert obs["visual"].shape == core.shape + visual_space.shape and obs["visual"].dtype == np.float32
        assert visual_space.contains(obs["visual"][0, 0]) and not obs["visual"].any()


@pytest.mark.parametrize("environment", CAMERA_ENVIRONMENTS)
def test_a_rendered_camera_sees_the_world_and_only_the_picture_differs(environment):
    _, _, blank, blank_rewards = _episode_start(environment)
    _, _, rendered, rendered_rewards = _episode_start(environment, RENDERED)
    assert all(obs["visual"].any() for obs in rendered)  # (a drone on its pad sees the pad alone, all one grey)
    assert np.ptp([obs["visual"] for obs in rendered]) > 0.05
    np.testing.assert_array_equal(blank_rewards, rendered_rewards)
    for b, r in zip(blank, rendered):
        np.testing.assert_array_equal(b["vector"], r["vector"])


def test_a_blind_scripted_drone_pilot_still_plants():
    compiled = hivex_dsl.compile({"hivex": 1, "environment": "drone_based_reforestation", "task": "main"})
    core = BatchedEnv(compiled, batch=1, split="test")
    policy = make_policy("scripted", compiled, core.sim.action_space, core.shape)
    observations = core.reset()
    while core.alive.any():
        observations = core.step(policy(observations)).observations
    # without sight it drops each seed 60 m out on its spiral, flies home for another and drops again
    assert core.state.new_count[0] >= 2 * compiled.agents


@pytest.mark.parametrize("environment", CAMERA_ENVIRONMENTS)
def test_a_lock_written_before_the_cameras_went_blank_still_draws_them(environment):
    """A lock (or a checkpoint: the same resolved scenario) from before ``camera_images`` has every other param and
    drew its cameras: it compiles to rendered cameras with the fingerprint it was written with; a lock of today's
    default keeps its blank ones, under a fingerprint of its own."""
    drawn = hivex_dsl.compile({"hivex": 1, "environment": environment, "params": RENDERED})
    blank = hivex_dsl.compile({"hivex": 1, "environment": environment})
    assert blank.fingerprint != drawn.fingerprint
    older = drawn.to_lock()
    del older["scenario"]["params"]["camera_images"]
    assert "camera_images" not in older["scenario"]["params"] and len(older["scenario"]["params"]) > 10
    again = hivex_dsl.compile(older)
    assert again.params.camera_images == "rendered" and again.fingerprint == older["fingerprint"] == drawn.fingerprint
    assert hivex_dsl.compile(blank.to_lock()).params.camera_images == "blank"
    # a scenario a person writes is not resolved: there the default stands
    assert hivex_dsl.compile({"hivex": 1, "environment": environment, "params": {}}).params.camera_images == "blank"
