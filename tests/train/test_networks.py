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


def _reference(agent: ActorCritic, obs: dict, cont: torch.Tensor, disc: torch.Tensor):
    """Log-prob and entropy from torch.distributions objects built on the agent's own head outputs."""
    hidden = agent.actor(obs, obs["obs"])
    logp, entropy = torch.zeros(cont.shape[0]), torch.zeros(cont.shape[0])
    if agent.mu is not None:
        normal = Normal(agent.mu(hidden), agent.log_std.exp())
        logp, entropy = logp + normal.log_prob(cont).sum(1), entropy + normal.entropy().sum(1)
    if agent.logits is not None:
        for i, chunk in enumerate(torch.split(agent.logits(hidden), agent.layout.nvec, 1)):
            cat = Categorical(logits=chunk)
            logp, entropy = logp + cat.log_prob(disc[:, i]), entropy + cat.entropy()
    return logp, entropy


@pytest.mark.parametrize("kind", sorted(LAYOUTS))
def test_log_prob_and_entropy_match_torch_distributions(kind):
    torch.manual_seed(3)
    agent = ActorCritic(OBS, LAYOUTS[kind], make_config("wind_farm_control", {"hidden_units": 8}))
    with torch.no_grad():
        agent.log_std.copy_(torch.linspace(-0.7, 0.4, agent.log_std.numel()))
        if agent.logits is not None:  # the 0.01-gain init makes every categorical nearly uniform
            agent.logits.weight.mul_(300.0)
    obs = {"obs": torch.rand(64, 5) * 2 - 1}
    cont, disc, logp = agent.act(obs)
    got_logp, got_entropy, value = agent.evaluate(obs, cont, disc)
    want_logp, want_entropy = _reference(agent, obs, cont, disc)
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
