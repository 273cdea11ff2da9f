"""PPO's masked categorical, as ML-Agents' (MultiCategoricalDistribution with its action masks): a closed choice is
never sampled, the open ones share the probability as a softmax over them, a closed choice adds no entropy, and the
update evaluates an experience under the mask it was taken with. By hand against ML-Agents' formulas."""

from __future__ import annotations

import numpy as np
import pytest
import torch
from gymnasium import spaces

import hivex_dsl
from hivex_dsl.train.checkpoint import older_defaults
from hivex_dsl.train.config import make_config
from hivex_dsl.train.evaluate import network_policy
from hivex_dsl.train.logs import EpisodeLog
from hivex_dsl.train.networks import ActorCritic
from hivex_dsl.train.ppo import collect, make_env, start_rollouts

OBS = spaces.Box(-1.0, 1.0, (5,), np.float32)
HYBRID = spaces.Dict({"continuous": spaces.Box(-1.0, 1.0, (2,), np.float32), "discrete": spaces.MultiDiscrete([3, 2])})
LOGITS = torch.tensor([0.5, 1.0, 2.0, 0.3, -0.4])  # branch 0: three choices, branch 1: two
ML_AGENTS_EPSILON = 1e-7  # ML-Agents' CategoricalDistInstance adds it inside its logs


def fixed_agent(**overrides) -> ActorCritic:
    """A hybrid policy whose categorical logits are LOGITS whatever the observation, log-std 0."""
    agent = ActorCritic(OBS, HYBRID, make_config("wind_farm_control", {"hidden_units": 8, **overrides}))
    with torch.no_grad():
        agent.logits.weight.zero_()
        agent.logits.bias.copy_(LOGITS)
    return agent


def ml_agents_branch(logits: list[float], allow: list[bool]) -> tuple[np.ndarray, float]:
    """ML-Agents' masked branch by its formulas: logits * mask - 1e8 * (1 - mask), softmax; entropy
    -sum p log(p + 1e-7). -> (probabilities, entropy)."""
    masked = np.where(allow, logits, 0.0) - 1e8 * (1 - np.asarray(allow, float))
    probs = np.exp(masked - masked.max())
    probs /= probs.sum()
    return probs, float(-(probs * np.log(probs + ML_AGENTS_EPSILON)).sum())


ROWS = [[True, True, False, True, False],  # branch 0 closes its third choice, branch 1 its second
        [True, True, True, True, True],
        [False, True, False, True, True]]  # branch 0 down to one choice: certain, no entropy


@pytest.mark.parametrize("row", range(len(ROWS)))
def test_log_probabilities_and_entropy_are_ml_agents_masked_ones(row):
    agent = fixed_agent()
    allow = ROWS[row]
    mask = torch.tensor([allow] * 6)
    # every action of the two branches, the closed ones included (an experience is never one, but the formula holds)
    disc = torch.tensor([[a, b] for a in range(3) for b in range(2)])
    cont = torch.zeros(6, 2)
    with torch.no_grad():
        logp, entropy, _ = agent.evaluate({"obs": torch.zeros(6, 5)}, cont, disc, mask)
    p0, h0 = ml_agents_branch(LOGITS[:3].tolist(), allow[:3])
    p1, h1 = ml_agents_branch(LOGITS[3:].tolist(), allow[3:])
    gaussian = 0.5 + 0.5 * np.log(2 * np.pi)  # the mean over its dimensions at log-std 0
    np.testing.assert_allclose(entropy.numpy(), gaussian + h0 + h1, atol=1e-5)
    for i, (a, b) in enumerate(disc.tolist()):
        if allow[a] and allow[3 + b]:
            # ML-Agents' per-branch log-probabilities, the policy loss's columns after the Gaussian's two
            np.testing.assert_allclose(logp[i, 2:].numpy(), [np.log(p0[a]), np.log(p1[b])], atol=1e-5)


def test_a_closed_choice_is_never_sampled_and_the_mode_is_the_best_open_one():
    torch.manual_seed(0)
    agent = fixed_agent()
    mask = torch.tensor([ROWS[0]] * 20_000)
    _, disc, _ = agent.act({"obs": torch.zeros(20_000, 5)}, mask=mask)
    assert set(disc[:, 0].tolist()) == {0, 1} and set(disc[:, 1].tolist()) == {0}
    # the open choices keep their softmax ratio (4-sigma band)
    p0, _ = ml_agents_branch(LOGITS[:3].tolist(), ROWS[0][:3])
    share = float((disc[:, 0] == 1).float().mean())
    assert abs(share - p0[1]) < 4 * np.sqrt(p0[1] * (1 - p0[1]) / 20_000)
    # the unmasked mode of branch 0 is choice 2 (logit 2.0); closed, the mode is choice 1
    _, modes, _ = agent.act({"obs": torch.zeros(1, 5)}, deterministic=True, mask=mask[:1])
    assert modes.tolist() == [[1, 0]]
    _, free, _ = agent.act({"obs": torch.zeros(1, 5)}, deterministic=True)
    assert free.tolist() == [[2, 0]]


def test_acting_and_evaluating_under_one_mask_agree():
    torch.manual_seed(1)
    agent = fixed_agent()
    mask = torch.tensor(ROWS * 100)
    obs = {"obs": torch.rand(300, 5) * 2 - 1}
    cont, disc, logp = agent.act(obs, mask=mask)
    again, _, _ = agent.evaluate(obs, cont, disc, mask)
    torch.testing.assert_close(again, logp)  # the first epoch's ratio is 1, as in ML-Agents


def test_with_action_masks_false_a_mask_is_ignored():
    agent = fixed_agent(action_masks=False)
    assert not agent.takes_masks
    mask = torch.tensor([ROWS[0]])
    _, modes, _ = agent.act({"obs": torch.zeros(1, 5)}, deterministic=True, mask=mask)
    assert modes.tolist() == [[2, 0]]
    with torch.no_grad():
        _, entropy, _ = agent.evaluate({"obs": torch.zeros(1, 5)}, torch.zeros(1, 2), modes, mask)
    _, h0 = ml_agents_branch(LOGITS[:3].tolist(), [True] * 3)
    _, h1 = ml_agents_branch(LOGITS[3:].tolist(), [True] * 2)
    assert float(entropy) == pytest.approx(0.5 + 0.5 * np.log(2 * np.pi) + h0 + h1, abs=1e-5)


def test_a_rollout_keeps_the_masks_its_actions_were_taken_under_and_never_drops_where_closed():
    """A DBR world-episode of an untrained policy whose drop logit is raised: where the drop was open it drops
    almost always, where it was closed never (unmasked, it would drop at most decisions)."""
    compiled = hivex_dsl.compile({"hivex": 1, "environment": "drone_based_reforestation", "episode_length": 600})
    cfg = make_config("drone_based_reforestation", {"torch_threads": 1})
    torch.manual_seed(0)
    env, obs, infos = make_env(compiled, 1, "train", cfg.ended_agents)
    agent = ActorCritic(env.single_observation_space, env.single_action_space, cfg)
    with torch.no_grad():
        agent.logits.bias.copy_(torch.tensor([0.0, 6.0]))  # drop at 99.8% where open
    state, buf = start_rollouts(obs, agent, compiled.episode_decisions, infos)
    assert buf.mask is not None and buf.mask.shape[-1] == 2
    first = torch.as_tensor(infos["action_mask"], dtype=torch.bool)
    collect(env, agent, buf, state, cfg, EpisodeLog())
    assert torch.equal(buf.mask[0], first)  # the reset's mask, for the first decision
    valid = buf.valid > 0
    dropped = buf.disc[..., 0] == 1
    open_ = buf.mask[..., 1]
    assert not (dropped & ~open_ & valid).any()
    assert (open_ & valid).any() and (~open_ & valid).sum() > 100
    assert float((dropped & open_ & valid).sum()) / float((open_ & valid).sum()) > 0.9


def test_an_evaluated_network_gets_the_environment_s_mask():
    agent = fixed_agent()
    with torch.no_grad():
        agent.logits.bias.copy_(torch.tensor([0.0, 0.0, 5.0, 0.0, 5.0]))
    policy = network_policy(agent, 2, deterministic=True)
    assert policy.takes_action_mask
    observations = np.zeros((1, 2, 5), np.float32)
    closed = np.array([[[1, 1, 0, 1, 0], [1, 1, 1, 1, 1]]], np.int8)
    assert policy(observations, closed)["discrete"].tolist() == [[[0, 0], [2, 1]]]
    assert policy(observations)["discrete"].tolist() == [[[2, 1], [2, 1]]]
    assert not network_policy(fixed_agent(action_masks=False), 2).takes_action_mask


def test_a_checkpoint_from_before_the_key_ignored_its_environment_s_masks():
    assert older_defaults({"seed": 3}, HYBRID, masks_actions=True)["action_masks"] is False
    assert "action_masks" not in older_defaults({"seed": 3}, HYBRID)  # no masks there: nothing changes
    assert older_defaults({"action_masks": True}, HYBRID, masks_actions=True)["action_masks"] is True
