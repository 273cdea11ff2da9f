"""The curiosity reward signal: ML-Agents' reward rule, its learning, its own discount, and its masking."""

from __future__ import annotations

import json

import numpy as np
import pytest
import torch
from gymnasium import spaces

from hivex_dsl.adapters.gymnasium import HivexVectorEnv
from hivex_dsl.compiler import compile
from hivex_dsl.train.config import PPOConfig, make_config
from hivex_dsl.train.curiosity import Curiosity
from hivex_dsl.train.logs import EpisodeLog
from hivex_dsl.train.networks import ActionLayout, ActorCritic, to_tensors
from hivex_dsl.train.buffer import Rollout
from hivex_dsl.train.ppo import advantages_and_returns, collect, gae, train_curiosity

from ..benchmark_scripts import benchmark_script
from .conftest import short_scenario

OBS = spaces.Box(-1.0, 1.0, (4,), np.float32)
HYBRID = spaces.Dict({"continuous": spaces.Box(-1.0, 1.0, (1,), np.float32), "discrete": spaces.MultiDiscrete([3])})


def _module(strength=0.1, seed=0, variant="ml_agents", actions=HYBRID):
    torch.manual_seed(seed)
    cfg = make_config("ocean_plastic_collection", {"curiosity_strength": strength, "curiosity_encoding_size": 16,
                                                   "curiosity_module": variant})
    return Curiosity(OBS, ActionLayout.of(actions), cfg)


def _transitions(n=256, seed=1):
    """s' = s shifted by the discrete action (a deterministic world the forward model can learn)."""
    g = torch.Generator().manual_seed(seed)
    obs = torch.rand(n, 4, generator=g) * 2 - 1
    disc = torch.randint(0, 3, (n, 1), generator=g)
    cont = torch.rand(n, 1, generator=g)
    following = (obs + 0.3 * (disc.float() - 1)).clamp(-1, 1)
    return {"obs": obs}, {"obs": following}, cont, disc


def test_the_papers_configs_add_curiosity_and_wfc_aws_do_not():
    strengths = {env: make_config(env).curiosity_strength for env in (
        "wildfire_resource_management", "drone_based_reforestation", "ocean_plastic_collection",
        "wind_farm_control", "aerial_wildfire_suppression")}
    assert strengths == {"wildfire_resource_management": 0.02, "drone_based_reforestation": 0.1,
                         "ocean_plastic_collection": 0.1, "wind_farm_control": 0.0, "aerial_wildfire_suppression": 0.0}


def test_the_module_is_as_wide_as_ml_agents_built_it_from_the_configs_that_ran():
    """By hand from original-configs/train: DBR's and OPC's curiosity blocks name network_settings (vis_encode_type
    resnet) beside encoding_size 256, so ML-Agents' release_20 ignored encoding_size there (a deprecation warning)
    and built the module's encoder at NetworkSettings' default hidden_units, 128; WRM's block names none, so its
    encoding_size, 256, became the width. The module's encoder and forward model's output are that wide."""
    widths = {env: make_config(env).curiosity_encoding_size for env in (
        "wildfire_resource_management", "drone_based_reforestation", "ocean_plastic_collection")}
    assert widths == {"wildfire_resource_management": 256, "drone_based_reforestation": 128,
                      "ocean_plastic_collection": 128}
    module = Curiosity(OBS, ActionLayout.of(HYBRID), make_config("ocean_plastic_collection"))
    assert module.forward_model[-1].out_features == 128 and module.inverse_model[0].in_features == 2 * 128


def test_no_reward_before_the_first_update_then_min_of_strength_times_error_and_one():
    obs, following, cont, disc = _transitions()
    weak, strong = _module(0.1), _module(1.0)  # same seed: the same weights
    assert torch.equal(weak.rewards(obs, following, cont, disc), torch.zeros(256))
    weak.updated.fill_(True)
    strong.updated.fill_(True)
    with torch.no_grad():  # large errors: some of the strong module's rewards hit the cap of 1
        strong.forward_model[-1].weight.mul_(40.0)
        weak.forward_model[-1].weight.mul_(40.0)
    low, high = weak.rewards(obs, following, cont, disc), strong.rewards(obs, following, cont, disc)
    assert (high <= 1.0).all() and (high == 1.0).any() and (low >= 0).all()
    uncapped = high < 1.0
    torch.testing.assert_close(low[uncapped], 0.1 * high[uncapped])
    assert (low[~uncapped] >= 0.1 - 1e-6).all()  # capped at strength 1 means an error of at least 1


def test_training_lowers_the_forward_error_of_seen_transitions():
    module = _module(0.1)
    optimizer = torch.optim.Adam(module.parameters(), lr=3e-3)
    obs, following, cont, disc = _transitions()
    batch = {"obs": obs, "next_obs": following, "cont": cont, "disc": disc}
    first = [train_curiosity(module, optimizer, batch, PPOConfig()) for _ in range(3)][0]
    for _ in range(300):
        last = train_curiosity(module, optimizer, batch, PPOConfig())
    assert last[0] < 0.2 * first[0]  # forward loss
    assert last[1] < 0.5 * first[1]  # inverse loss: the action is readable from (s, s')
    assert bool(module.updated)


def test_each_signal_is_discounted_with_its_own_gamma():
    rewards = torch.tensor([[[1.0, 0.5]], [[2.0, 0.0]], [[4.0, 1.0]]])  # (T=3, S=1, K=2)
    values = torch.tensor([[[10.0, 1.0]], [[20.0, 2.0]], [[30.0, 3.0]]])
    next_value, terminated, done = torch.tensor([[40.0, 4.0]]), torch.zeros(3, 1), torch.tensor([[0.0], [1.0], [0.0]])
    adv, ret = gae(rewards, values, next_value, terminated, done, torch.tensor([0.5, 0.9]), 0.8)
    for k, gamma in enumerate((0.5, 0.9)):
        alone, alone_ret = gae(rewards[..., k], values[..., k], next_value[:, k], terminated, done, gamma, 0.8)
        torch.testing.assert_close(adv[..., k], alone)
        torch.testing.assert_close(ret[..., k], alone_ret)


def test_a_rollout_with_curiosity_has_two_value_columns_and_masks_reset_transitions():
    compiled = compile(short_scenario("wildfire_resource_management", episode_length=5))
    cfg = make_config("wildfire_resource_management", {"num_worlds": 1, "hidden_units": 8, "curiosity_encoding_size": 8})
    env = HivexVectorEnv(compiled, num_worlds=1)
    torch.manual_seed(0)
    agent = ActorCritic(env.single_observation_space, env.single_action_space, cfg)
    module = Curiosity(env.single_observation_space, agent.layout, cfg)
    module.updated.fill_(True)
    obs, _ = env.reset()
    state = {"obs": to_tensors(obs), "done": np.zeros(env.num_envs, bool), "active": np.ones(env.num_envs, bool)}
    buf = Rollout(12, env.num_envs, state["obs"], 0, len(agent.layout.nvec), agent.signals, agent.logp_columns)
    next_value = collect(env, agent, buf, state, cfg, EpisodeLog())
    assert agent.signals == 2 and buf.values.shape == (12, env.num_envs, 2) and next_value.shape == (env.num_envs, 2)
    episodes = EpisodeLog()
    advantages, returns, charts = advantages_and_returns(buf, next_value, cfg, module, episodes)
    assert advantages.shape == (12, env.num_envs) and returns.shape == (12, env.num_envs, 2)
    assert charts["curiosity_reward"] > 0
    # the step after each 5-step episode is a reset transition: valid 0, so its curiosity reward is 0
    assert buf.valid[5].sum() == 0 and buf.valid[11].sum() == 0
    flat = module.rewards(buf.flat_obs(), buf.flat_next_obs(), buf.flat("cont"), buf.flat("disc"))
    masked = flat.reshape(12, env.num_envs) * buf.valid
    assert masked[5].abs().sum() == 0 and masked[4].abs().sum() > 0
    # each agent-episode's sum (steps 0-4 and 6-10), as ML-Agents reports Policy/Curiosity Reward
    sums = torch.cat([masked[0:5].sum(0), masked[6:11].sum(0)])
    ended = {"hivex_episode": {"return": np.zeros(1), "length": np.ones(1)}, "_hivex_episode": np.ones(1, bool)}
    episodes.record(ended)  # a drain reports only where an episode ended
    assert episodes.drain()["signals"]["curiosity"] == pytest.approx(float(sums.mean()), rel=1e-6)


@pytest.mark.parametrize("strength", [0.0, 0.02])
def test_the_critic_has_one_head_per_signal(strength):
    cfg = make_config("wildfire_resource_management", {"hidden_units": 8, "curiosity_strength": strength})
    agent = ActorCritic(OBS, spaces.MultiDiscrete([3, 3]), cfg)
    value = agent.get_value({"obs": torch.zeros(5, 4)})
    assert value.shape == ((5,) if strength == 0 else (5, 2))


@pytest.mark.parametrize("variant, hidden", [("ml_agents", 2), ("hivex_v1", 1)])
def test_the_models_hidden_layers_are_ml_agents_linear_encoder_or_the_first_module_s(variant, hidden):
    """ML-Agents' LinearEncoder(inputs, 1, 256) is two Swish layers of 256 (its loop always adds a last one),
    then a linear output; hivex_v1, which the WRM, DBR and OPC records trained with, has one."""
    module = _module(variant=variant)
    actions = 1 + 3  # HYBRID: one continuous dimension and one branch of 3, one-hot
    for model, inputs, outputs in ((module.inverse_model, 2 * 16, actions), (module.forward_model, 16 + actions, 16)):
        linears = [layer for layer in model if isinstance(layer, torch.nn.Linear)]
        assert [(layer.in_features, layer.out_features) for layer in linears] == \
            [(inputs, 256)] + [(256, 256)] * (hidden - 1) + [(256, outputs)]
        assert sum(isinstance(layer, torch.nn.SiLU) for layer in model) == hidden


@pytest.mark.parametrize("variant, scale", [("ml_agents", 1.0), ("hivex_v1", 0.5)])
def test_the_inverse_loss_of_continuous_actions_is_their_summed_squared_error(variant, scale):
    """ML-Agents: mean over the batch of sum_j (a_j - predicted_j)^2; hivex_v1 halved it."""
    module = _module(variant=variant, actions=spaces.Box(-1.0, 1.0, (2,), np.float32))
    with torch.no_grad():  # the inverse model predicts (0.5, -0.25) whatever it sees
        module.inverse_model[-1].weight.zero_()
        module.inverse_model[-1].bias.copy_(torch.tensor([0.5, -0.25]))
    obs, following, _, _ = _transitions(n=3)
    cont = torch.tensor([[0.5, 0.75], [-0.5, -0.25], [1.5, 0.75]])
    # by hand: per transition (0 + 1), (1 + 0), (1 + 1) -> mean 4/3
    _, _, inverse = module.loss(obs, following, cont, torch.zeros(3, 0, dtype=torch.int64))
    assert float(inverse) == pytest.approx(scale * 4.0 / 3.0)


def test_training_logs_each_agent_episode_s_curiosity_sum_as_the_original_s_panel(tiny, tmp_path):
    from hivex_dsl.evaluation.original.compare import from_points
    from hivex_dsl.train import ppo

    compiled = compile(short_scenario("wildfire_resource_management", episode_length=8))
    cfg = make_config("wildfire_resource_management", tiny, {"curiosity_encoding_size": 8, "curiosity_strength": 0.5})
    ppo.train(compiled, cfg, tmp_path, progress=False)
    points = json.loads((tmp_path / "curve.json").read_text())
    sums = [p["curiosity_reward"] for p in points]
    # each step's reward is min(strength x error, 1), so an episode's sum lies within [0, its decisions]
    assert all(0.0 <= s <= p["length"] for s, p in zip(sums, points)) and max(sums) > 0
    assert from_points(points).panels["Curiosity Reward"].tolist() == sums
    # each value head's mean estimate too, as the original's Extrinsic and Curiosity Value Estimate panels
    for key, panel in (("extrinsic_value_estimate", "Extrinsic Value Estimate"),
                       ("curiosity_value_estimate", "Curiosity Value Estimate")):
        assert from_points(points).panels[panel].tolist() == [p[key] for p in points]
    # the updates' losses as the original's Entropy and Curiosity Forward and Inverse Loss panels: four three-way
    # branches hold at most 4 ln 3 nats, and the inverse model's cross-entropy starts near it
    for key, panel in (("entropy", "Entropy"), ("curiosity_forward", "Curiosity Forward Loss"),
                       ("curiosity_inverse", "Curiosity Inverse Loss")):
        assert from_points(points).panels[panel].tolist() == [p["losses"][key] for p in points]
    assert all(0.0 < p["losses"]["entropy"] <= 4 * np.log(3) + 1e-6 for p in points)
    assert all(p["losses"]["curiosity_forward"] >= 0.0 for p in points)
    assert 0.5 * 4 * np.log(3) < points[0]["losses"]["curiosity_inverse"] < 2 * 4 * np.log(3)
    cfg = make_config("wildfire_resource_management", tiny, {"curiosity_strength": 0.0})
    ppo.train(compiled, cfg, tmp_path / "plain", progress=False)
    plain = json.loads((tmp_path / "plain" / "curve.json").read_text())
    assert not any("curiosity_reward" in p or "curiosity_value_estimate" in p for p in plain)
    assert all(np.isfinite(p["extrinsic_value_estimate"]) for p in plain)
    assert {"Curiosity Reward", "Curiosity Value Estimate", "Curiosity Forward Loss",
            "Curiosity Inverse Loss"}.isdisjoint(from_points(plain).panels)
    assert "Entropy" in from_points(plain).panels


def test_the_losses_benchmark_reads_a_set_param_as_yaml_does():
    script = benchmark_script("curiosity_losses")
    params = script.scenario_params(["turn_rate_deg=18", "camera_images=rendered"])
    assert params == {"turn_rate_deg": 18, "camera_images": "rendered"}
    _, obs, following, cont, _, _ = script.random_transitions("drone_based_reforestation", params, decisions=3,
                                                              worlds=1)
    assert cont.shape == (len(obs["vector"]), 3) and following["vector"].shape == obs["vector"].shape


def test_the_losses_benchmark_s_noise_follows_a_frame_into_the_older_stack():
    script = benchmark_script("curiosity_losses")
    obs = {"vector": torch.tensor([[1.0, 2.0, 3.0, 4.0], [5.0, 6.0, 0.0, 0.0]]), "visual": torch.zeros(2, 1)}
    following = {"vector": torch.tensor([[7.0, 8.0, 1.0, 2.0], [9.0, 1.0, 5.0, 6.0]]), "visual": torch.ones(2, 1)}
    noisy, later = script.with_noise(obs, following, 0.5)
    # the frame obs shows newest is the one following shows older: the same noise on both
    shown_newest = noisy["vector"][:, :2] - obs["vector"][:, :2]
    assert torch.equal(shown_newest, later["vector"][:, 2:] - following["vector"][:, 2:])
    assert not torch.equal(noisy["vector"][:, :2], obs["vector"][:, :2])
    assert torch.equal(noisy["vector"][1, 2:], torch.zeros(2))  # a first observation's older stack stays zeros
    assert (later["vector"][:, :2] - following["vector"][:, :2]).abs().gt(0).all()
    assert torch.equal(obs["vector"][0], torch.tensor([1.0, 2.0, 3.0, 4.0]))  # the inputs are not changed
    assert noisy["visual"] is obs["visual"]
    with pytest.raises(ValueError, match="two stacks"):
        script.with_noise(obs, following, 0.5, stacks=3)


def test_the_along_episodes_benchmark_keeps_each_agent_episode_s_decisions_once(tiny, tmp_path):
    """A drone-episode of the short scenario ends at its time limit, 8 decisions (40 physics steps at period 5),
    so 2 episodes of the world's 3 drones are 6 x 8 transitions, each decision index 0-7 six times: no step across a
    reset and none of a third episode is kept."""
    from hivex_dsl.train import ppo

    compiled = compile(short_scenario("drone_based_reforestation", episode_length=40))
    assert compiled.episode_decisions == 8 and compiled.agents == 3
    ppo.train(compiled, make_config("drone_based_reforestation", tiny, {"curiosity_encoding_size": 8}), tmp_path,
              progress=False)
    found = benchmark_script("curiosity_along_episodes").play(tmp_path, episodes=2)
    assert found.episodes == 6
    assert np.bincount(found.index).tolist() == [6] * 8
    assert found.error.shape == (48,) and (found.error >= 0).all() and found.change.shape == (48, 20)


def test_the_along_episodes_benchmark_bins_the_capped_reward_by_decision_index():
    script = benchmark_script("curiosity_along_episodes")
    found = script.Transitions(index=np.array([0, 1, 5]), error=np.array([1.0, 20.0, 3.0]),
                               change=np.array([[0.0, 2.0], [2.0, 0.0], [1.0, 1.0]]), episodes=2, strength=0.1)
    first, second = script.by_index(found, [0, 2, 10, 20])  # the empty last bin is left out
    # rewards min(0.1 e, 1): 0.1 and 1 (20 capped) in the first bin, 0.3 in the second; over 2 agent-episodes
    assert (first["transitions"], first["mean_error"], first["median_error"]) == (2, 10.5, 10.5)
    assert first["reward_per_episode"] == pytest.approx(0.55) and first["change"].tolist() == [1.0, 1.0]
    assert (second["from"], second["to"], second["transitions"]) == (2, 10, 1)
    assert second["reward_per_episode"] == pytest.approx(0.15)
