"""The test protocol plays the same whole episodes as the random and scripted levels: a network that always
picks action 0 scores exactly what the all-zeros policy scores, episode by episode, in an environment whose
episodes end early (WRM: when the fire goes out), where counting the first episodes to end would not."""

from __future__ import annotations

import numpy as np
import pytest
import torch
import yaml

from hivex_dsl.adapters.gymnasium import HivexVectorEnv
from hivex_dsl.compiler import compile
from hivex_dsl.evaluation.rollout import rollout
from hivex_dsl.train.config import make_config
from hivex_dsl.train.evaluate import play
from hivex_dsl.train.networks import ActorCritic

from .conftest import SCENARIOS


def test_a_network_that_always_picks_zero_scores_as_the_zeros_policy():
    compiled = compile(SCENARIOS / "wildfire_resource_management" / "main.yaml")
    env = HivexVectorEnv(compiled, num_worlds=1)
    agent = ActorCritic(env.single_observation_space, env.single_action_space,
                        make_config("wildfire_resource_management", {"hidden_units": 8}))
    with torch.no_grad():
        agent.logits.weight.zero_()
        agent.logits.bias.copy_(torch.tensor([5.0, 0.0, 0.0] * len(agent.layout.nvec)))
    played = play(compiled, agent, episodes=3, split="test", deterministic=True)
    zeros = rollout(compiled, "zeros", 3, "test")
    assert len(set(zeros.lengths[:, 0].tolist())) > 1  # episodes of different lengths (fires go out)
    np.testing.assert_allclose(played["return"], zeros.returns.reshape(-1))
    for name, sums in zeros.statistics.items():
        np.testing.assert_allclose(played["statistics"][name], sums.reshape(-1))


def test_the_network_plays_on_the_threads_asked_for_and_torch_keeps_its_own(monkeypatch):
    compiled = compile(dict(yaml.safe_load((SCENARIOS / "wind_farm_control" / "main.yaml").read_text()),
                            episode_length=4))
    env = HivexVectorEnv(compiled, num_worlds=1)
    agent = ActorCritic(env.single_observation_space, env.single_action_space,
                        make_config("wind_farm_control", {"hidden_units": 8}))
    seen, act = [], agent.act
    monkeypatch.setattr(agent, "act", lambda *a, **k: seen.append(torch.get_num_threads()) or act(*a, **k))
    before = torch.get_num_threads()
    try:
        torch.set_num_threads(2)
        play(compiled, agent, episodes=1)
        assert set(seen) == {1} and torch.get_num_threads() == 2
        seen.clear()
        play(compiled, agent, episodes=1, torch_threads=3)
        assert set(seen) == {3} and torch.get_num_threads() == 2
    finally:
        torch.set_num_threads(before)


def test_a_level_sweep_s_checkpoint_is_its_one_run_at_that_level(tmp_path):
    from hivex_dsl.train.config import TrainError
    from hivex_dsl.train.evaluate import level_checkpoint

    for index, level in enumerate((1, 10)):
        run = tmp_path / f"{index:03d}-aws-main-levels_terrain_level={level}"
        run.mkdir()
        (run / "checkpoint.pt").write_bytes(b"")
    # level 1 is not level 10's prefix match: a folder ends with its level
    assert level_checkpoint(tmp_path, 1).parent.name.endswith("terrain_level=1")
    assert level_checkpoint(tmp_path, 10).parent.name.endswith("terrain_level=10")
    with pytest.raises(TrainError, match="expected one run of terrain level 3 with a checkpoint.pt, found 0"):
        level_checkpoint(tmp_path, 3)
