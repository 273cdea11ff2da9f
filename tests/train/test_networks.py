"""The policy's hand-written log-probabilities and entropies equal torch.distributions' on the same
parameters, for every action layout (Box, Discrete, MultiDiscrete of unequal sizes, hybrid)."""

from __future__ import annotations

import numpy as np
import pytest
import torch
from gymnasium import spaces
from torch.distributions import Categorical, Normal

from hivex_dsl.train.config import make_config
from hivex_dsl.train.networks import ActorCritic

OBS = spaces.Box(-1.0, 1.0, (5,), np.float32)
LAYOUTS = {
    "box": spaces.Box(-1.0, 1.0, (2,), np.float32),
    "discrete": spaces.Discrete(3),
    "multi_discrete": spaces.MultiDiscrete([2, 4, 3]),
    "hybrid": spaces.Dict({"continuous": spaces.Box(-1.0, 1.0, (2,), np.float32),
                           "discrete": spaces.MultiDiscrete([2, 3])}),
}


def _reference(agent: ActorCritic, obs: dict, cont: torch.Tensor, disc: torch.Tensor, per_dimension: bool):
    """Log-prob and entropy from torch.distributions objects built on the agent's own head outputs: joint, or
    per action dimension with the Gaussian's entropy averaged over its dimensions (ML-Agents)."""
    hidden = agent.actor(obs, obs["obs"])
    logps, entropy = [], torch.zeros(cont.shape[0])
    if agent.mu is not None:
        normal = Normal(agent.mu(hidden), agent.log_std.exp())
        logps.append(normal.log_prob(cont))
        entropy = entropy + (normal.entropy().mean(1) if per_dimension else normal.entropy().sum(1))
    if agent.logits is not None:
        for i, chunk in enumerate(torch.split(agent.logits(hidden), agent.layout.nvec, 1)):
            cat = Categorical(logits=chunk)
            logps.append(cat.log_prob(disc[:, i])[:, None])
            entropy = entropy + cat.entropy()
    logp = torch.cat(logps, dim=1)
    return (logp if per_dimension else logp.sum(1)), entropy


@pytest.mark.parametrize("policy_loss", ["ml_agents", "joint"])
@pytest.mark.parametrize("kind", sorted(LAYOUTS))
def test_log_prob_and_entropy_match_torch_distributions(kind, policy_loss):
    torch.manual_seed(3)
    cfg = make_config("wind_farm_control", {"hidden_units": 8, "policy_loss": policy_loss})
    agent = ActorCritic(OBS, LAYOUTS[kind], cfg)
    with torch.no_grad():
        agent.log_std.copy_(torch.linspace(-0.7, 0.4, agent.log_std.numel()))
        if agent.logits is not None:  # the 0.01-gain init makes every categorical nearly uniform
            agent.logits.weight.mul_(300.0)
    obs = {"obs": torch.rand(64, 5) * 2 - 1}
    cont, disc, logp = agent.act(obs)
    got_logp, got_entropy, value = agent.evaluate(obs, cont, disc)
    want_logp, want_entropy = _reference(agent, obs, cont, disc, per_dimension=policy_loss == "ml_agents")
    torch.testing.assert_close(got_logp, want_logp)
    torch.testing.assert_close(logp, want_logp)
    torch.testing.assert_close(got_entropy, want_entropy)
    assert value.shape == (64,)
    assert disc.shape == (64, len(agent.layout.nvec))
    assert cont.shape == (64, agent.layout.continuous)


def test_sampled_categorical_frequencies_follow_the_probabilities():
    """10,000 draws of one state land on each category at its softmax probability (4-sigma band)."""
    torch.manual_seed(0)
    agent = ActorCritic(OBS, spaces.Discrete(3), make_config("wind_farm_control", {"hidden_units": 8}))
    with torch.no_grad():
        agent.logits.weight.zero_()
        agent.logits.bias.copy_(torch.tensor([0.0, 1.0, -1.0]))
    probs = torch.softmax(torch.tensor([0.0, 1.0, -1.0]), 0).numpy()
    _, disc, _ = agent.act({"obs": torch.zeros(10_000, 5)})
    freq = np.bincount(disc[:, 0].numpy(), minlength=3) / 10_000
    assert np.all(np.abs(freq - probs) < 4 * np.sqrt(probs * (1 - probs) / 10_000))


def test_deterministic_actions_are_the_modes():
    torch.manual_seed(1)
    agent = ActorCritic(OBS, LAYOUTS["hybrid"], make_config("wind_farm_control", {"hidden_units": 8}))
    obs = {"obs": torch.rand(16, 5)}
    cont, disc, _ = agent.act(obs, deterministic=True)
    hidden = agent.actor(obs, obs["obs"])
    torch.testing.assert_close(cont, agent.mu(hidden).detach())
    chunks = torch.split(agent.logits(hidden), agent.layout.nvec, 1)
    assert disc.tolist() == torch.stack([c.argmax(1) for c in chunks], 1).tolist()


@pytest.mark.parametrize("kind, size, flat", [
    ("resnet", 25, 32 * 2 * 2),   # OPC: ML-Agents' pool_out_shape, (h - 3) // 2 + 1: 25 -> 12 -> 5 -> 2
    ("resnet", 16, 32 * 1 * 1),   # DBR: 16 -> 7 -> 3 -> 1
    ("resnet", 15, 32 * 1 * 1),   # ML-Agents' smallest ResNet camera: 15 -> 7 -> 3 -> 1
    ("simple", 84, 32 * 9 * 9),   # conv 8/4 then 4/2: 84 -> 20 -> 9
    ("simple", 20, 32 * 1 * 1),   # the smallest simple camera: 20 -> 4 -> 1
])
def test_camera_encoders_have_ml_agents_shapes(kind, size, flat):
    from hivex_dsl.train.networks import camera_encoder

    encoder = camera_encoder(kind, (size, size, 2), 128)
    dense = [m for m in encoder.modules() if isinstance(m, torch.nn.Linear)]
    assert [(d.in_features, d.out_features) for d in dense] == [(flat, 128)]
    convs = [m for m in encoder.modules() if isinstance(m, torch.nn.Conv2d)]
    assert len(convs) == (15 if kind == "resnet" else 2)  # 3 stacks of a conv and 2 residual blocks of 2 convs
    out = encoder(torch.rand(64, size, size, 2))
    assert out.shape == (64, 128)
    if kind == "resnet":  # ML-Agents ends the ResNet with a ReLU, the simple encoder with a LeakyReLU
        assert out.min() >= 0
    else:
        assert out.min() < 0


def test_cameras_below_the_encoders_minimum_are_refused():
    from hivex_dsl.train.config import TrainError
    from hivex_dsl.train.networks import camera_encoder

    with pytest.raises(TrainError, match="at least 15x15"):
        camera_encoder("resnet", (14, 20, 1), 8)
    with pytest.raises(TrainError, match="at least 20x20"):
        camera_encoder("simple", (19, 19, 1), 8)


@pytest.mark.parametrize("num_layers, layers", [(1, 2), (2, 2), (3, 3), (4, 4)])
def test_num_layers_counts_as_ml_agents_linear_encoder(num_layers, layers):
    """ML-Agents' LinearEncoder builds a first and a last layer with num_layers - 2 between, so 1 means two."""
    cfg = make_config("wind_farm_control", {"hidden_units": 16, "num_layers": num_layers})
    agent = ActorCritic(OBS, LAYOUTS["discrete"], cfg)
    for body in (agent.actor, agent.critic):
        linears = [m for m in body.mlp if isinstance(m, torch.nn.Linear)]
        assert [(m.in_features, m.out_features) for m in linears] == [(5, 16)] + [(16, 16)] * (layers - 1)
        assert sum(isinstance(m, torch.nn.SiLU) for m in body.mlp) == layers


@pytest.mark.parametrize("mode, expected", [
    ("ml_agents", [-1.0, -0.5, 0.0, 0.5, 1.0]),  # clamp(sample, -3, 3) / 3, as ML-Agents sends it
    ("clip", [-1.0, -1.0, 0.0, 1.0, 1.0]),
])
def test_gaussian_samples_become_box_actions_as_the_mode_says(mode, expected):
    from dataclasses import replace

    from hivex_dsl.train.networks import ActionLayout

    sample = torch.tensor([[-4.0], [-1.5], [0.0], [1.5], [4.0]])
    unit = replace(ActionLayout.of(spaces.Box(-1.0, 1.0, (1,), np.float32)), continuous_actions=mode)
    np.testing.assert_allclose(unit.to_env(sample, torch.zeros(5, 0, dtype=torch.int64)).ravel(), expected)
    wide = replace(ActionLayout.of(spaces.Box(0.0, 10.0, (1,), np.float32)), continuous_actions=mode)
    onto_wide = {"ml_agents": [0.0, 2.5, 5.0, 7.5, 10.0], "clip": [0.0, 0.0, 0.0, 1.5, 4.0]}[mode]
    np.testing.assert_allclose(wide.to_env(sample, torch.zeros(5, 0, dtype=torch.int64)).ravel(), onto_wide, atol=1e-6)


@pytest.mark.parametrize("mode, saturated", [("ml_agents", 0.0027), ("clip", 0.3173)])
def test_a_fresh_gaussian_policy_saturates_the_box_at_three_or_one_sigma(mode, saturated):
    """With log-std 0 and means near 0, P(|z| >= 3) = 0.27% of ML-Agents' actions sit at the Box's edge,
    P(|z| >= 1) = 31.7% of clipped ones."""
    torch.manual_seed(0)
    cfg = make_config("aerial_wildfire_suppression", {"hidden_units": 16, "continuous_actions": mode})
    agent = ActorCritic(OBS, LAYOUTS["hybrid"], cfg)
    with torch.no_grad():
        cont, disc, _ = agent.act({"obs": torch.zeros(20_000, 5)})
    actions = agent.layout.to_env(cont, disc)["continuous"]
    assert actions.min() >= -1.0 and actions.max() <= 1.0
    assert np.mean(np.abs(actions) >= 1.0) == pytest.approx(saturated, abs=0.01)
