"""The update's speed-ups change no number, from the same seed and weights, against a plain reference.

- Copies avoided (next observations as views of the rollout's frames, each epoch's shuffle gathered into kept
  buffers; the reference concatenates and gathers afresh): the same bytes, so losses and weights equal to the bit.
- Camera encoders in channels-last layout (the reference: torch's default layout): the same float32 function
  in another memory order, equal up to rounding.
- Blank cameras (all zeros, the default in AWS and DBR) encoded once a batch and repeated (the reference
  encodes every row): the same function of the same inputs, equal up to rounding. While acting (a rollout, an
  evaluation) once a block of fixed weights: the same pass of the same image, so the same bits.
- Network passes batched (the critic values every frame after the rollout instead of one slot batch a step with
  the actions, curiosity encodes each frame once instead of a transition's two observations apart): the same
  float32 function of the same inputs, so equal up to the order BLAS sums in. On this machine that order depends
  on the batch only where its rows are not a multiple of 4 (so every bundled default, 24 or more slots, gives the
  same bits; the small tests' 6 slots differ in the last bit): the comparison allows float32 rounding.
"""

from __future__ import annotations

import contextlib

import numpy as np
import pytest
import torch

from hivex_dsl.compiler import compile
from hivex_dsl.train import buffer, networks, ppo
from hivex_dsl.train.config import make_config
from hivex_dsl.train.curiosity import Curiosity
from hivex_dsl.train.logs import EpisodeLog
from hivex_dsl.train.networks import ActorCritic

from .conftest import short_scenario


def reference_minibatches(data, valid, batch_size, rng, buffers=None):
    """The same order as ``ppo.minibatches`` (one permutation per epoch), each minibatch indexed on its own."""
    order = torch.as_tensor(valid[rng.permutation(valid.size)])

    def rows(tree, index):
        return {k: rows(v, index) if isinstance(v, dict) else v[index] for k, v in tree.items()}

    for start in range(0, valid.size, batch_size):
        yield rows(data, order[start:start + batch_size])


def reference_next_obs(buf):
    return {k: buffer.merge_steps(torch.cat([v[1:], buf.last_obs[k][None].clone()])) for k, v in buf.obs.items()}


def reference_rollout_values(agent, buf, cfg):
    """The critic run one slot batch a step, as the rollout first did beside the actor (the weights do not
    change during a rollout, so after it is the same)."""
    with torch.no_grad():
        for t in range(buf.values.shape[0]):
            buf.values[t] = agent.get_value({k: v[t] for k, v in buf.obs.items()})
        return agent.get_value(buf.last_obs)


def reference_rollout_rewards(self, frames, cont, disc):
    """Curiosity's rewards with each transition's observation and next observation encoded apart."""
    slots = next(iter(frames.values())).shape[0] - cont.shape[0]
    return self.rewards({k: v[:-slots] for k, v in frames.items()}, {k: v[slots:] for k, v in frames.items()},
                        cont, disc)


def two_updates(environment: str, curiosity: bool) -> tuple[list[dict[str, float]], torch.Tensor]:
    """The losses of two rollouts and updates, and every trained weight after them."""
    torch.manual_seed(0)
    # the fixed rollout of 48 experiences whatever the environment's file fills by: two short updates
    cfg = make_config(environment, {"num_worlds": 2, "buffer_fill": "rollout", "buffer_size": 48, "batch_size": 16,
                                    "num_epoch": 2, "hidden_units": 16,
                                    "curiosity_strength": 0.01 if curiosity else 0.0})
    env, obs, infos = ppo.make_env(compile(short_scenario(environment)), cfg.num_worlds, "train")
    agent = ActorCritic(env.single_observation_space, env.single_action_space, cfg)
    optimizer = ppo.make_optimizer(agent, cfg.learning_rate)
    module = None
    if curiosity:
        module = Curiosity(env.single_observation_space, agent.layout, cfg)
        module = (module, ppo.make_optimizer(module, cfg.curiosity_learning_rate))
    state, buf = ppo.start_rollouts(obs, agent, cfg.rollout_length(env.num_envs), infos)
    rng, episodes, losses = np.random.default_rng(0), EpisodeLog(), []
    for _ in range(2):
        next_value = ppo.collect(env, agent, buf, state, cfg, episodes)
        advantages, returns, _ = ppo.advantages_and_returns(buf, next_value, cfg, module and module[0])
        losses.append(ppo.update(agent, optimizer, buf, advantages, returns, cfg, cfg.beta, cfg.epsilon, rng, module))
    weights = [p.detach().flatten() for p in agent.parameters()]
    weights += [p.detach().flatten() for p in module[0].parameters()] if module else []
    return losses, torch.cat(weights)


def assert_losses_within_rounding(fast_losses, plain_losses):
    """Every update's losses, name by name, equal up to float32 rounding. The policy loss is a mean of advantage
    times ratio that nearly cancels (about 1e-4 here), so its rounding is that of the values the advantages are
    made of, not of itself: float32's 1.2e-7 of values up to about 100 (AWS's returns) moves a row's advantage by
    about 1e-5 and a minibatch's mean by up to about 1e-6 (1.4e-7 seen on an AVX-512 machine, under 1e-7 on an
    AVX2 one). The rollout's values rolled by one step move AWS's second policy loss by 8.5e-5."""
    assert len(fast_losses) == len(plain_losses)
    for fast, plain in zip(fast_losses, plain_losses):
        assert fast.keys() == plain.keys()
        for name in fast:
            assert fast[name] == pytest.approx(plain[name], rel=1e-4, abs=1e-6 if name == "policy" else 1e-7), name


@pytest.mark.parametrize("environment,curiosity", [("ocean_plastic_collection", True),
                                                   ("aerial_wildfire_suppression", False),
                                                   ("wind_farm_control", False)])
def test_the_copies_avoided_change_no_bit(environment, curiosity, monkeypatch):
    fast_losses, fast_weights = two_updates(environment, curiosity)
    monkeypatch.setattr(ppo, "minibatches", reference_minibatches)
    monkeypatch.setattr(buffer.Rollout, "flat_next_obs", reference_next_obs)
    plain_losses, plain_weights = two_updates(environment, curiosity)
    assert fast_losses == plain_losses
    assert torch.equal(fast_weights, plain_weights)
    assert len(fast_losses) == 2 and all(np.isfinite(v) for losses in fast_losses for v in losses.values())


@pytest.mark.parametrize("environment,curiosity", [("ocean_plastic_collection", True),
                                                   ("aerial_wildfire_suppression", False),
                                                   ("wind_farm_control", False)])
def test_the_batched_passes_change_nothing_but_rounding(environment, curiosity, monkeypatch):
    monkeypatch.setattr(buffer, "CHUNK", 7)  # chunks that cut across a step's slots: a row's output is its own
    fast_losses, fast_weights = two_updates(environment, curiosity)
    monkeypatch.setattr(ppo, "rollout_values", reference_rollout_values)
    monkeypatch.setattr(Curiosity, "rollout_rewards", reference_rollout_rewards)
    plain_losses, plain_weights = two_updates(environment, curiosity)
    assert_losses_within_rounding(fast_losses, plain_losses)
    # no weight comparison: Adam turns a last-bit difference of a near-zero gradient into a step of +-lr


@pytest.mark.parametrize("environment", ["drone_based_reforestation", "ocean_plastic_collection"])
def test_channels_last_cameras_change_nothing_but_rounding(environment, monkeypatch):
    """The ResNet cameras (DBR's 16x16, OPC's 25x25) with curiosity: the losses of two updates in the
    channels-last layout against the same networks in torch's default layout."""
    fast_losses, _ = two_updates(environment, curiosity=True)
    encoder = networks.camera_encoder

    def default_layout(*args, **kwargs):
        return encoder(*args, **kwargs).to(memory_format=torch.contiguous_format)

    monkeypatch.setattr(networks, "camera_encoder", default_layout)
    plain_losses, _ = two_updates(environment, curiosity=True)
    assert_losses_within_rounding(fast_losses, plain_losses)


@pytest.mark.parametrize("environment", ["aerial_wildfire_suppression", "drone_based_reforestation"])
def test_blank_cameras_encoded_once_change_nothing_but_rounding(environment, monkeypatch):
    """AWS's simple encoder and DBR's ResNet on their default blank cameras: two updates' losses with each blank
    batch encoded once against every row encoded."""
    encode, once = networks.encode, []

    def counting(encoder, images):
        once.append(images.shape[0] > 1 and not images.any())
        return encode(encoder, images)

    monkeypatch.setattr(networks, "encode", counting)
    fast_losses, _ = two_updates(environment, curiosity=environment == "drone_based_reforestation")
    assert once and all(once)  # the default camera is blank, so every batch of more than one row took the shortcut
    monkeypatch.setattr(networks, "encode", lambda encoder, images: encoder(images))
    plain_losses, _ = two_updates(environment, curiosity=environment == "drone_based_reforestation")
    assert_losses_within_rounding(fast_losses, plain_losses)


@pytest.mark.parametrize("kind,shape", [("simple", (42, 42, 3)), ("resnet", (16, 16, 1))])
def test_a_blank_batch_is_encoded_once_and_a_seen_one_row_by_row(kind, shape):
    """Values and gradients of a blank batch equal every row's own pass; one lit pixel anywhere in the batch
    sends the whole batch through the full pass (its blank rows still equal the blank image's encoding)."""
    torch.manual_seed(0)
    encoder = networks.camera_encoder(kind, shape, 8)
    blank = torch.zeros(5, *shape)
    out = networks.encode(encoder, blank)
    (out * torch.arange(1.0, 9.0)).sum().backward()
    fast_grads = [p.grad.clone() for p in encoder.parameters()]
    encoder.zero_grad()
    rows = torch.cat([encoder(blank[i:i + 1]) for i in range(5)])
    (rows * torch.arange(1.0, 9.0)).sum().backward()
    torch.testing.assert_close(out, rows, rtol=1e-5, atol=1e-6)
    for fast, plain in zip(fast_grads, [p.grad for p in encoder.parameters()]):
        torch.testing.assert_close(fast, plain, rtol=1e-4, atol=1e-5)
    seen = blank.clone()
    seen[3, 2, 1, 0] = 1.0
    with torch.no_grad():
        lit = networks.encode(encoder, seen)
        assert not torch.allclose(lit[3], rows[0].detach(), rtol=1e-5, atol=1e-6)  # the lit row is its own
        torch.testing.assert_close(lit[[0, 1, 2, 4]], rows[:4].detach(), rtol=1e-5, atol=1e-6)


def test_a_block_of_fixed_weights_encodes_the_blank_row_once_without_gradients():
    """Inside ``fixed_weights`` a pass without gradients encodes the blank row once for every batch size; a pass
    with gradients, a lit batch and any pass outside the block encode afresh, and the next block sees new weights."""
    torch.manual_seed(0)
    encoder = networks.camera_encoder("simple", (42, 42, 3), 8)
    calls = []
    encoder.register_forward_hook(lambda module, inputs, output: calls.append(inputs[0].shape[0]))
    blank = torch.zeros(6, 42, 42, 3)
    with torch.no_grad():
        plain = networks.encode(encoder, blank[:3])
    assert calls == [1]
    with networks.fixed_weights(), torch.no_grad():
        first = networks.encode(encoder, blank[:3])
        again = networks.encode(encoder, blank)
        lit = blank.clone()
        lit[0, 0, 0, 0] = 1.0
        networks.encode(encoder, lit)
    assert calls == [1, 1, 6]  # the row once, then the lit batch whole
    assert torch.equal(first, plain) and torch.equal(again, plain[:1].expand(6, -1))
    with networks.fixed_weights():
        networks.encode(encoder, blank).sum().backward()  # with gradients: a fresh row, its graph kept
    assert calls == [1, 1, 6, 1] and all(p.grad is not None for p in encoder.parameters())
    with torch.no_grad():
        for parameter in encoder.parameters():
            parameter.add_(0.1)
        with networks.fixed_weights():
            moved = networks.encode(encoder, blank[:3])
        fresh = encoder(blank[:1])
    assert calls[-2:] == [1, 1] and torch.equal(moved[0], fresh[0]) and not torch.equal(moved, plain)


@pytest.mark.parametrize("environment", ["aerial_wildfire_suppression", "drone_based_reforestation"])
def test_acting_on_blank_cameras_encodes_once_a_rollout_and_changes_no_bit(environment, monkeypatch):
    """The acting passes of a rollout share one blank row (an encoder call a rollout instead of one a step): two
    updates' losses and weights are those of acting without the block, bit for bit."""
    calls, acts = [], []
    forward, act = torch.nn.Sequential.forward, ActorCritic.act

    def counted(self, images):
        if isinstance(self[0], networks.Channels):  # a camera encoder's pass (its first layer reorders channels)
            calls.append(images.shape[0])
        return forward(self, images)

    def counted_act(self, *args, **kwargs):
        acts.append(1)
        return act(self, *args, **kwargs)

    monkeypatch.setattr(torch.nn.Sequential, "forward", counted)
    monkeypatch.setattr(ActorCritic, "act", counted_act)
    fast_losses, fast_weights = two_updates(environment, curiosity=False)
    fast_calls = len(calls)
    monkeypatch.setattr(ppo, "fixed_weights", contextlib.nullcontext)
    calls.clear()
    acts.clear()
    plain_losses, plain_weights = two_updates(environment, curiosity=False)
    assert fast_losses == plain_losses and torch.equal(fast_weights, plain_weights)
    # the same passes but the acting steps', which shrink to one a rollout
    assert len(calls) - fast_calls == len(acts) - 2 and len(acts) > 2


def test_camera_convolutions_hold_their_weights_channels_last():
    encoder = networks.camera_encoder("resnet", (16, 16, 1), 8)
    convs = [m for m in encoder.modules() if isinstance(m, torch.nn.Conv2d)]
    assert len(convs) == 15 and all(c.weight.is_contiguous(memory_format=torch.channels_last) for c in convs)
    image = torch.rand(3, 16, 16, 1)
    plain = networks.camera_encoder("resnet", (16, 16, 1), 8).to(memory_format=torch.contiguous_format)
    plain.load_state_dict(encoder.state_dict())
    torch.testing.assert_close(encoder(image), plain(image), rtol=1e-5, atol=1e-6)


def test_the_rollout_values_and_curiosity_rewards_are_the_step_by_step_ones():
    """One rollout: the critic's values of every frame and curiosity's rewards, batched, against the same
    networks run a step (or a transition) at a time, within float32 rounding."""
    torch.manual_seed(0)
    # OPC trains on whole trajectories: its storage holds time_horizon + buffer_size / slots + 1 steps of every
    # slot, 25 here (the paper's horizon, 10,240, made this one test minutes long); its episodes of 5 decisions
    # end inside it, so frames after a reset are compared too
    cfg = make_config("ocean_plastic_collection", {"num_worlds": 2, "buffer_size": 48, "batch_size": 16,
                                                   "time_horizon": 16, "hidden_units": 16,
                                                   "curiosity_strength": 0.01})
    env, obs, infos = ppo.make_env(compile(short_scenario("ocean_plastic_collection")), cfg.num_worlds, "train")
    agent = ActorCritic(env.single_observation_space, env.single_action_space, cfg)
    state, buf = ppo.start_rollouts(obs, agent, cfg.rollout_length(env.num_envs), infos)
    next_value = ppo.collect(env, agent, buf, state, cfg, EpisodeLog())
    assert len(buf.values) == 25 and buf.done.any()
    with torch.no_grad():
        stepwise = torch.stack([agent.get_value({k: v[t] for k, v in buf.obs.items()}) for t in range(len(buf.values))])
        last = agent.get_value(buf.last_obs)
    torch.testing.assert_close(buf.values, stepwise, rtol=1e-5, atol=1e-6)
    torch.testing.assert_close(next_value, last, rtol=1e-5, atol=1e-6)
    assert buf.values.abs().sum() > 0
    module = Curiosity(env.single_observation_space, agent.layout, cfg)
    module.updated.fill_(True)
    cont, disc = buf.flat("cont"), buf.flat("disc")
    batched = module.rollout_rewards(buf.flat_frames(), cont, disc)
    apart = module.rewards(buf.flat_obs(), buf.flat_next_obs(), cont, disc)
    torch.testing.assert_close(batched, apart, rtol=1e-6, atol=1e-7)
    assert batched.shape == (cont.shape[0],) and batched.abs().sum() > 0


def test_the_next_observations_are_the_frames_after_each_step():
    """Row t of the next observations is row t + 1 of the observations, and the last is what the rollout ended
    on; both are views of one storage (written once per step)."""
    first = {"cam": torch.zeros(2, 3)}
    buf = buffer.Rollout(steps=4, slots=2, first_obs=first, continuous=1, discrete=0)
    for t in range(4):
        buf.obs["cam"][t] = t + 1
    buf.end({"cam": torch.full((2, 3), 9.0)})
    nxt = buf.flat_next_obs()["cam"].reshape(4, 2, 3)
    assert nxt[:, 0, 0].tolist() == [2, 3, 4, 9]
    assert buf.flat_obs()["cam"].reshape(4, 2, 3)[:, 1, 2].tolist() == [1, 2, 3, 4]
    assert nxt.data_ptr() == buf.frames["cam"][1].data_ptr()  # a view, not a copy


def test_kept_buffers_hold_no_stale_rows():
    """A later, shorter gather reads only its own rows; the buffer is reused, not reallocated."""
    buffers = buffer.RowBuffers()
    data = {"x": torch.arange(10.0)[:, None].repeat(1, 3), "obs": {"cam": torch.arange(10.0)}}
    first = buffers.take(data, torch.tensor([9, 8, 7, 6, 5]))
    assert first["x"][:, 0].tolist() == [9, 8, 7, 6, 5] and first["obs"]["cam"].tolist() == [9, 8, 7, 6, 5]
    second = buffers.take(data, torch.tensor([1, 2]))
    assert second["x"][:, 2].tolist() == [1, 2] and second["obs"]["cam"].tolist() == [1, 2]
    assert second["x"].data_ptr() == first["x"].data_ptr()
