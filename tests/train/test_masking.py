"""Reset transitions (NEXT_STEP autoreset) and dead slots are no experience: GAE stops at an ending and the
loss never sees them. The GAE values are computed by hand."""

from __future__ import annotations

import copy

import numpy as np
import pytest
import torch

from hivex_dsl.adapters.gymnasium import HivexVectorEnv
from hivex_dsl.compiler import compile
from hivex_dsl.train.config import make_config
from hivex_dsl.train.logs import EpisodeLog
from hivex_dsl.train.networks import ActorCritic, to_tensors
from hivex_dsl.train.buffer import Rollout
from hivex_dsl.train.ppo import acting_mask, collect, gae, ratio_stats, update

from .conftest import short_scenario

REWARDS = torch.tensor([[1.0], [2.0], [4.0]])
VALUES = torch.tensor([[10.0], [20.0], [30.0]])
NEXT = torch.tensor([40.0])


def column(*values):
    return torch.tensor(values, dtype=torch.float32)[:, None]


@pytest.mark.parametrize("terminated, done, expected", [
    # no ending: d2 = 4 + .5*40 - 30 = -6; d1 = 2 + .5*30 - 20 = -3, A1 = -3 + .25*-6; d0 = 1 + .5*20 - 10 = 1
    ((0, 0, 0), (0, 0, 0), (1 - 0.25 * 4.5, -4.5, -6.0)),
    # step 0 terminates: it bootstraps from 0 (1 - 10) and takes nothing from the reset transition after it
    ((1, 0, 0), (1, 0, 0), (-9.0, -4.5, -6.0)),
    # step 1 is truncated: it bootstraps from V(its last observation) = 30, and the recursion stops there
    ((0, 0, 0), (0, 1, 0), (1 + 0.25 * -3, -3.0, -6.0)),
])
def test_gae_by_hand(terminated, done, expected):
    advantages, returns = gae(REWARDS, VALUES, NEXT, column(*terminated), column(*done), gamma=0.5, lam=0.5)
    assert advantages[:, 0].tolist() == pytest.approx(expected)
    assert returns[:, 0].tolist() == pytest.approx([a + v for a, v in zip(expected, VALUES[:, 0].tolist())])


def test_acting_mask():
    done = np.array([False, True, False, True])
    active = np.array([True, True, False, False])
    assert acting_mask(done, active).tolist() == [True, False, False, False]


def _rollout(steps=12):
    compiled = compile(short_scenario("wind_farm_control", episode_length=5))
    cfg = make_config("wind_farm_control", {"num_worlds": 1, "hidden_units": 8, "batch_size": 16})
    env = HivexVectorEnv(compiled, num_worlds=1)
    torch.manual_seed(0)
    agent = ActorCritic(env.single_observation_space, env.single_action_space, cfg)
    obs, _ = env.reset()
    state = {"obs": to_tensors(obs), "done": np.zeros(env.num_envs, bool), "active": np.ones(env.num_envs, bool)}
    buf = Rollout(steps, env.num_envs, state["obs"], 0, 1, 1, agent.logp_columns)
    next_value = collect(env, agent, buf, state, cfg, EpisodeLog())
    return agent, cfg, buf, next_value


def test_the_step_after_an_ending_is_masked():
    _, _, buf, _ = _rollout()
    # episodes of 5 steps end at steps 4 and 10 (step 5 is the reset transition, step 6 the new episode's first)
    assert buf.done[:, 0].tolist() == [0, 0, 0, 0, 1, 0, 0, 0, 0, 0, 1, 0]
    assert buf.valid[:, 0].tolist() == [1, 1, 1, 1, 1, 0, 1, 1, 1, 1, 1, 0]
    assert buf.rewards[5].abs().sum() == 0


def test_masked_transitions_do_not_change_the_update():
    agent, cfg, buf, next_value = _rollout()
    advantages, returns = gae(buf.rewards, buf.values, next_value, buf.terminated, buf.done, cfg.gamma, cfg.lambd)
    results = []
    for garbage in (0.0, 1e6):
        twin, spoiled = copy.deepcopy(agent), copy.deepcopy(buf)
        invalid = spoiled.valid == 0
        spoiled.obs["obs"][invalid] = garbage
        spoiled.logp[invalid] = garbage
        adv, ret = advantages.clone(), returns.clone()
        adv[invalid], ret[invalid] = garbage, garbage
        optimizer = torch.optim.Adam(twin.parameters(), lr=1e-3)
        update(twin, optimizer, spoiled, adv, ret, cfg, 0.01, 0.2, np.random.default_rng(0))
        results.append(torch.cat([p.detach().flatten() for p in twin.parameters()]))
    assert torch.equal(results[0], results[1])
    assert not torch.equal(results[0], torch.cat([p.detach().flatten() for p in agent.parameters()]))


def test_every_valid_experience_is_trained_on_once_per_epoch():
    agent, cfg, buf, next_value = _rollout()
    advantages, returns = gae(buf.rewards, buf.values, next_value, buf.terminated, buf.done, cfg.gamma, cfg.lambd)
    buf.obs["obs"][..., 0] = torch.arange(buf.valid.numel(), dtype=torch.float32).reshape(buf.valid.shape)  # ids
    seen, evaluate = [], agent.evaluate

    def spy(obs, cont, disc, mask=None):
        seen.extend(obs["obs"][:, 0].tolist())
        return evaluate(obs, cont, disc, mask)

    agent.evaluate = spy
    update(agent, torch.optim.Adam(agent.parameters()), buf, advantages, returns, cfg, 0.01, 0.2,
           np.random.default_rng(0))
    valid_ids = torch.nonzero(buf.valid.flatten()).flatten().tolist()
    assert len(valid_ids) == 8 * 10 and cfg.num_epoch == 3  # 8 turbines, 10 of 12 steps valid
    assert sorted(seen) == sorted(valid_ids * cfg.num_epoch)
    epochs = [seen[i:i + len(valid_ids)] for i in range(0, len(seen), len(valid_ids))]
    assert all(sorted(epoch) == valid_ids for epoch in epochs) and epochs[0] != epochs[1]  # each shuffled anew


def test_ratio_statistics_by_hand():
    # ratios 1, 1.5, 0.5, 1.1: (r - 1) - log r = 0, 0.094535, 0.193147, 0.004690; |r - 1| > 0.2 for 1.5 and 0.5
    stats = ratio_stats(torch.log(torch.tensor([1.0, 1.5, 0.5, 1.1])), epsilon=0.2)
    assert stats["approx_kl"] == pytest.approx((0.0 + 0.094535 + 0.193147 + 0.004690) / 4, abs=1e-6)
    assert stats["clipfrac"] == 0.5
