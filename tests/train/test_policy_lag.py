"""policy_lag_steps: the first steps of a rollout act with the weights from before the last update, as the
environment stepped on while ML-Agents' threaded trainer updated (hivex_dsl/train/lag.py)."""

from __future__ import annotations

import pytest
import torch

import hivex_dsl
from hivex_dsl.train.config import TrainError, make_config
from hivex_dsl.train.lag import PolicyLag
from hivex_dsl.train.logs import EpisodeLog
from hivex_dsl.train.networks import ActorCritic
from hivex_dsl.train.ppo import collect, make_env, start_rollouts

TURN_LEFT, STAY, TURN_RIGHT = 0, 1, 2  # one turbine's three-way branch


def _prefer(agent: ActorCritic, choice: int) -> None:
    """Make ``agent`` pick ``choice`` all but surely (a logit 30 above the others: the rest have e^-30 each)."""
    with torch.no_grad():
        agent.logits.weight.zero_()
        agent.logits.bias.copy_(torch.nn.functional.one_hot(torch.tensor(choice), 3).float() * 30.0)


def test_the_first_steps_act_with_the_kept_weights_and_the_rest_with_the_updated_ones():
    compiled = hivex_dsl.compile({"hivex": 1, "environment": "wind_farm_control", "episode_length": 50})
    cfg = make_config("wind_farm_control", {"torch_threads": 1, "policy_lag_steps": 4})
    torch.manual_seed(0)
    env, obs, infos = make_env(compiled, 1, "train", cfg.ended_agents)
    agent = ActorCritic(env.single_observation_space, env.single_action_space, cfg)
    _prefer(agent, TURN_LEFT)
    lag = PolicyLag(agent, cfg.policy_lag_steps)
    lag.keep(agent)  # what an update starts from
    _prefer(agent, TURN_RIGHT)  # what it ends with
    state, buf = start_rollouts(obs, agent, 10, infos)
    collect(env, agent, buf, state, cfg, EpisodeLog(), lag=lag)
    turbines = compiled.agents
    assert buf.disc[:4, :, 0].tolist() == [[TURN_LEFT] * turbines] * 4
    assert buf.disc[4:, :, 0].tolist() == [[TURN_RIGHT] * turbines] * 6
    # each step's log-probability is its actor's: about 0 under its own weights, about -30 under the other's
    assert buf.logp[:4].max() > -1e-6 and buf.logp[4:].max() > -1e-6


def test_keep_copies_the_weights_so_the_update_does_not_move_them():
    compiled = hivex_dsl.compile({"hivex": 1, "environment": "wind_farm_control", "episode_length": 50})
    cfg = make_config("wind_farm_control", {"torch_threads": 1})
    env, _, _ = make_env(compiled, 1, "train", cfg.ended_agents)
    agent = ActorCritic(env.single_observation_space, env.single_action_space, cfg)
    lag = PolicyLag(agent, 3)
    _prefer(agent, STAY)
    lag.keep(agent)
    _prefer(agent, TURN_RIGHT)
    assert int(lag.before.logits.bias.argmax()) == STAY
    assert lag.actor(agent, 2) is lag.before and lag.actor(agent, 3) is agent
    assert not any(p.requires_grad for p in lag.before.parameters())


def test_a_negative_lag_is_refused_with_its_name():
    with pytest.raises(TrainError, match="policy_lag_steps"):
        make_config("wind_farm_control", {"policy_lag_steps": -1})
