"""The networks of ``ppo.py``: observation encoders (MLP inputs, ML-Agents' simple and ResNet cameras) and
an actor-critic whose policy mixes Gaussian (Box) and categorical (Discrete/MultiDiscrete) heads.

Observations reach the networks as a dict of float tensors ``{key: (B, ...)}``: a Box observation is the
key ``"obs"``, a Dict observation keeps its keys. A key whose single space is (H, W, C) is a camera.
"""

from __future__ import annotations

import math
from contextlib import contextmanager
from contextvars import ContextVar
from dataclasses import dataclass, replace
from typing import Any, Iterator, Literal

import numpy as np
import torch
from gymnasium import spaces
from torch import nn

from .config import PPOConfig, TrainError

MIN_IMAGE = {"simple": 20, "resnet": 15}  # ML-Agents' minimum camera sizes per encoder
HALF_LOG_2PI = 0.5 * math.log(2 * math.pi)
CLOSED_LOGIT = -1e8  # a masked choice's logit, as ML-Agents' MultiCategoricalDistribution._mask_branch sets it


def observation_keys(space: spaces.Space) -> dict[str, tuple[int, ...]]:
    """Key -> single-slot shape of every observation input."""
    if isinstance(space, spaces.Dict):
        return {k: tuple(s.shape) for k, s in space.spaces.items()}
    if isinstance(space, spaces.Box):
        return {"obs": tuple(space.shape)}
    raise TrainError(f"PPO handles Box and Dict observations, not {space}")


def to_tensors(observations: Any, device: torch.device | str = "cpu") -> dict[str, torch.Tensor]:
    """Vector-env observations (an array or a dict of arrays, leading slot axis) -> float tensors."""
    items = observations.items() if isinstance(observations, dict) else [("obs", observations)]
    return {k: torch.tensor(np.asarray(v), dtype=torch.float32, device=device) for k, v in items}


@dataclass(frozen=True)
class ActionLayout:
    """A Box part of ``continuous`` dims in [low, high] and categorical parts of sizes ``nvec`` (offset ``start``)."""

    kind: str  # "discrete" | "multi_discrete" | "box" | "hybrid"
    continuous: int
    nvec: tuple[int, ...]
    start: tuple[int, ...]
    low: np.ndarray | None = None
    high: np.ndarray | None = None
    continuous_actions: Literal["ml_agents", "clip"] = "ml_agents"  # how a Gaussian sample becomes a Box action

    @classmethod
    def of(cls, space: spaces.Space) -> "ActionLayout":
        if isinstance(space, spaces.Discrete):
            return cls("discrete", 0, (int(space.n),), (int(space.start),))
        if isinstance(space, spaces.MultiDiscrete) and space.nvec.ndim == 1:
            return cls("multi_discrete", 0, tuple(map(int, space.nvec)), tuple(map(int, space.start)))
        if isinstance(space, spaces.Box) and len(space.shape) == 1:
            return cls("box", space.shape[0], (), (), space.low.astype(np.float32), space.high.astype(np.float32))
        if isinstance(space, spaces.Dict) and set(space.spaces) == {"continuous", "discrete"}:
            box, cat = ActionLayout.of(space["continuous"]), ActionLayout.of(space["discrete"])
            return cls("hybrid", box.continuous, cat.nvec, cat.start, box.low, box.high)
        raise TrainError(f"PPO handles Discrete, MultiDiscrete, Box and Dict(continuous, discrete) actions, not {space}")

    def to_env(self, continuous: torch.Tensor, discrete: torch.Tensor) -> Any:
        """Sampled (S, continuous) floats and (S, len(nvec)) indices -> the vector env's action batch.
        The unclipped sample keeps its log-probability; see :meth:`box_actions` for what the env gets."""
        cont = self.box_actions(continuous.cpu().numpy()) if self.continuous else None
        disc = discrete.cpu().numpy() + np.asarray(self.start, dtype=np.int64) if self.nvec else None
        if self.kind == "discrete":
            return disc[:, 0]
        if self.kind == "multi_discrete":
            return disc
        if self.kind == "box":
            return cont
        return {"continuous": cont, "discrete": disc}

    def box_actions(self, sample: np.ndarray) -> np.ndarray:
        """(S, continuous) Gaussian samples -> actions in [low, high]. ``ml_agents``: as ML-Agents sends them,
        clamp(sample, -3, 3) / 3 (its AgentAction.to_action_tuple), mapped linearly onto the Box, so a policy
        of log-std 0 saturates at 3 sigma; ``clip``: the sample clipped into the Box (saturating at 1 sigma)."""
        if self.continuous_actions == "clip":
            return np.clip(sample, self.low, self.high)
        unit = np.clip(sample, -3.0, 3.0) * np.float32(1.0 / 3.0)
        return np.clip(self.low + (unit + 1.0) * np.float32(0.5) * (self.high - self.low), self.low, self.high)


def vector_part(obs: dict[str, torch.Tensor], keys: list[str]) -> torch.Tensor | None:
    """The vector inputs ``keys`` of a batch flattened and side by side (B, width); None if there are none."""
    if not keys:
        return None
    parts = [obs[k].reshape(obs[k].shape[0], -1) for k in keys]
    return parts[0] if len(parts) == 1 else torch.cat(parts, dim=1)


def swish_mlp(inputs: int, hidden: int, layers: int) -> nn.Sequential:
    """(B, inputs) -> (B, hidden): ``layers`` Linear + Swish (SiLU) layers."""
    modules: list[nn.Module] = []
    for i in range(layers):
        modules += [nn.Linear(inputs if i == 0 else hidden, hidden), nn.SiLU()]
    return nn.Sequential(*modules)


def linear_encoder(inputs: int, num_layers: int, hidden: int) -> nn.Sequential:
    """ML-Agents' ``LinearEncoder(inputs, num_layers, hidden)``: a first and a last Swish layer whatever
    ``num_layers`` says, with ``num_layers - 2`` between, so 1 builds two layers as 2 does."""
    return swish_mlp(inputs, hidden, max(2, num_layers))


class ResidualBlock(nn.Module):
    def __init__(self, channels: int):
        super().__init__()
        self.body = nn.Sequential(nn.SiLU(), nn.Conv2d(channels, channels, 3, padding=1),
                                  nn.SiLU(), nn.Conv2d(channels, channels, 3, padding=1))

    def forward(self, x: torch.Tensor) -> torch.Tensor:
        return x + self.body(x)


def camera_encoder(kind: str, shape: tuple[int, int, int], out: int) -> nn.Module:
    """(B, H, W, C) in [0, 1] -> (B, out): ML-Agents' ``simple`` (2 conv, LeakyReLU) or ``resnet`` (IMPALA)
    encoder, layer for layer (mlagents/trainers/torch_entities/encoders.py). The ResNet's max-pools are
    unpadded (3x3, stride 2: a 25x25 camera is 12x12, 5x5, then 2x2) and its dense output is a ReLU."""
    height, width, channels = shape
    if min(height, width) < MIN_IMAGE[kind]:
        raise TrainError(f"vis_encode_type {kind!r} needs cameras of at least {MIN_IMAGE[kind]}x{MIN_IMAGE[kind]}, "
                         f"this one is {height}x{width}; choose the other encoder")
    if kind == "simple":
        convs = nn.Sequential(nn.Conv2d(channels, 16, 8, stride=4), nn.LeakyReLU(),
                              nn.Conv2d(16, 32, 4, stride=2), nn.LeakyReLU(), nn.Flatten())
        activation: nn.Module = nn.LeakyReLU()
    else:
        stack: list[nn.Module] = []
        for c_in, c_out in zip((channels, 16, 32), (16, 32, 32)):
            stack += [nn.Conv2d(c_in, c_out, 3, padding=1), nn.MaxPool2d(3, stride=2),
                      ResidualBlock(c_out), ResidualBlock(c_out)]
        convs = nn.Sequential(*stack, nn.SiLU(), nn.Flatten())
        activation = nn.ReLU()
    with torch.no_grad():
        flat = convs(torch.zeros(1, channels, height, width)).shape[1]
    # Channels-last weights keep weights and activations in the camera's own (B, H, W, C) layout, which
    # Channels() passes on as a view: the same function, about 4% faster training with DBR's ResNet
    # (tests/train/test_exact_speedups.py checks the sameness).
    return nn.Sequential(Channels(), convs, nn.Linear(flat, out), activation).to(memory_format=torch.channels_last)


class Channels(nn.Module):
    """(B, H, W, C) -> (B, C, H, W)."""

    def forward(self, x: torch.Tensor) -> torch.Tensor:
        return x.permute(0, 3, 1, 2)


class RunningNorm(nn.Module):
    """Running mean and variance of a vector input (ML-Agents' ``normalize``); a no-op when disabled."""

    def __init__(self, size: int, enabled: bool):
        super().__init__()
        self.enabled = enabled
        self.register_buffer("mean", torch.zeros(size))
        self.register_buffer("var", torch.ones(size))
        self.register_buffer("count", torch.tensor(1e-4))

    def update(self, x: torch.Tensor) -> None:
        if not self.enabled:
            return
        batch_mean, batch_var, n = x.mean(0), x.var(0, unbiased=False), x.shape[0]
        delta, total = batch_mean - self.mean, self.count + n
        self.var.copy_((self.var * self.count + batch_var * n + delta.square() * self.count * n / total) / total)
        self.mean.add_(delta * n / total)
        self.count.copy_(total)

    def forward(self, x: torch.Tensor) -> torch.Tensor:
        return ((x - self.mean) / torch.sqrt(self.var + 1e-8)).clamp(-5, 5) if self.enabled else x


class Body(nn.Module):
    """Cameras through their encoders, vectors concatenated, then ML-Agents' ``LinearEncoder`` of ``num_layers``
    x ``hidden_units`` (Swish; at least two layers, as there)."""

    def __init__(self, keys: dict[str, tuple[int, ...]], cfg: PPOConfig):
        super().__init__()
        self.cameras = nn.ModuleDict({k: camera_encoder(cfg.vis_encode_type, s, cfg.hidden_units)
                                      for k, s in keys.items() if len(s) == 3})
        self.vectors = [k for k, s in keys.items() if len(s) != 3]
        width = sum(int(np.prod(keys[k])) for k in self.vectors) + cfg.hidden_units * len(self.cameras)
        self.mlp = linear_encoder(width, cfg.num_layers, cfg.hidden_units)

    def init_like_ml_agents(self) -> None:
        """ML-Agents' initialisation: its LinearEncoder's Kaiming-normal (linear) layers, and the cameras' dense
        layer with the ReLU gain 1.41 (the convolutions keep torch's defaults, as in ML-Agents)."""
        for layer in self.mlp:
            if isinstance(layer, nn.Linear):
                ml_agents_linear(layer, "kaiming", 1.0)
        for encoder in self.cameras.values():
            ml_agents_linear(encoder[2], "kaiming", 1.41)

    def forward(self, obs: dict[str, torch.Tensor], vector: torch.Tensor | None) -> torch.Tensor:
        parts = [encode(encoder, obs[k]) for k, encoder in self.cameras.items()]
        if vector is not None:
            parts.append(vector)
        return self.mlp(parts[0] if len(parts) == 1 else torch.cat(parts, dim=1))


def encode(encoder: nn.Module, images: torch.Tensor) -> torch.Tensor:
    """``encoder`` over images (B, H, W, C) -> (B, out). A batch of blank images only (all zeros: the blank
    camera the original's runs observed, the default in AWS and DBR) is encoded once and repeated: every row of
    the full pass is that one row (the encoders treat rows apart), and the repeat's backward sums its rows'
    gradients as the full pass's does, so the same function up to float rounding, at a fraction of the cost (half
    of a blind AWS minibatch's update; benchmarks/train_throughput.py). Inside :func:`fixed_weights` the row is
    encoded once for the whole block. Checked in tests/train/test_exact_speedups.py."""
    if images.shape[0] > 0 and _blank(images):
        return _blank_row(encoder, images).expand(images.shape[0], -1)
    return encoder(images)


_BLANK_ROWS: ContextVar[dict | None] = ContextVar("blank_rows", default=None)


@contextmanager
def fixed_weights() -> Iterator[None]:
    """A block in which no network's weights change (a rollout's acting, an evaluation's episodes): each camera
    encoder's blank row is encoded once for the block instead of once a step, a policy pass at batch 3 spending
    most of its time there otherwise. Only passes without gradients use it; the rows go when the block ends, so
    the next block sees the weights an update left."""
    token = _BLANK_ROWS.set({})
    try:
        yield
    finally:
        _BLANK_ROWS.reset(token)


def _blank_row(encoder: nn.Module, images: torch.Tensor) -> torch.Tensor:
    """``encoder`` of one blank image shaped as ``images``' rows -> (1, out), from the block's rows where one is open
    (:func:`fixed_weights`) and the pass keeps no gradient."""
    rows = _BLANK_ROWS.get()
    if rows is None or torch.is_grad_enabled():
        return encoder(images[:1])
    key = (id(encoder), tuple(images.shape[1:]), images.dtype, images.device, torch.is_autocast_enabled())
    if key not in rows:
        rows[key] = encoder(images[:1])
    return rows[key]


def _blank(images: torch.Tensor) -> bool:
    """Whether every value of ``images`` is 0 (NaN is not). One fused pass: ``not images.any()`` costs about five
    times as much on a CPU minibatch of AWS's cameras."""
    low, high = torch.aminmax(images)
    return bool(low == 0) and bool(high == 0)


def _head(inputs: int, outputs: int, gain: float) -> nn.Linear:
    layer = nn.Linear(inputs, outputs)
    nn.init.orthogonal_(layer.weight, gain)
    nn.init.zeros_(layer.bias)
    return layer


def ml_agents_linear(layer: nn.Linear, kind: Literal["kaiming", "xavier"], gain: float = 1.0) -> None:
    """Re-initialise ``layer`` as ML-Agents' ``linear_layer`` does: Kaiming-normal for a linear activation
    (std 1 / sqrt(fan_in)) or Xavier-uniform, times ``gain``, and a zero bias."""
    with torch.no_grad():
        if kind == "kaiming":
            nn.init.kaiming_normal_(layer.weight, nonlinearity="linear")
        else:
            nn.init.xavier_uniform_(layer.weight)
        layer.weight.mul_(gain)
        layer.bias.zero_()


VALUE_HEADS = ("extrinsic", "curiosity")  # the critic's value heads in column order, named as ML-Agents' signals


class ActorCritic(nn.Module):
    """Separate actor and critic bodies (as ML-Agents), shared by every slot (parameter sharing)."""

    def __init__(self, observation_space: spaces.Space, action_space: spaces.Space, cfg: PPOConfig):
        super().__init__()
        keys = observation_keys(observation_space)
        self.layout = replace(ActionLayout.of(action_space), continuous_actions=cfg.continuous_actions)
        self.actor, self.critic = Body(keys, cfg), Body(keys, cfg)
        vector_width = sum(int(np.prod(keys[k])) for k in self.actor.vectors)
        self.norm = RunningNorm(vector_width, cfg.normalize)
        hidden = cfg.hidden_units
        # one value head per reward signal (ML-Agents): extrinsic, and curiosity when the config adds it
        self.signals = 2 if cfg.curiosity_strength > 0 else 1
        self.value = _head(hidden, self.signals, 1.0)
        self.logits = _head(hidden, sum(self.layout.nvec), 0.01) if self.layout.nvec else None
        self.mu = _head(hidden, self.layout.continuous, 0.01) if self.layout.continuous else None
        self.log_std = nn.Parameter(torch.zeros(self.layout.continuous))
        # ML-Agents' policy loss takes one probability ratio per action dimension; "joint" one for them all
        self.per_dimension = cfg.policy_loss == "ml_agents"
        # ML-Agents' masked categorical: a closed choice's logit is set to -1e8, so it is never sampled and adds
        # nothing to the entropy; without the key's choice (or a branch) the masks given are ignored
        self.takes_masks = cfg.action_masks and bool(self.layout.nvec)
        self.logp_columns = self.layout.continuous + len(self.layout.nvec) if self.per_dimension else 0
        if cfg.weight_init == "ml_agents":
            self._init_like_ml_agents()

    def _init_like_ml_agents(self) -> None:
        """ML-Agents' heads: value Xavier-uniform; Gaussian means and categorical branches Kaiming-normal with
        gains 0.2 and 0.1 (mlagents/trainers/torch_entities/distributions.py, decoders.py); log-std 0 either way."""
        self.actor.init_like_ml_agents()
        self.critic.init_like_ml_agents()
        ml_agents_linear(self.value, "xavier")
        if self.logits is not None:
            ml_agents_linear(self.logits, "kaiming", 0.1)
        if self.mu is not None:
            ml_agents_linear(self.mu, "kaiming", 0.2)

    def _vector(self, obs: dict[str, torch.Tensor]) -> torch.Tensor | None:
        return vector_part(obs, self.actor.vectors)

    def _here(self, *tensors):
        """Inputs moved to the network's device (rollouts stay in CPU memory; outputs come back there)."""
        device = self.value.weight.device
        return [{k: v.to(device) for k, v in t.items()} if isinstance(t, dict) else None if t is None else t.to(device)
                for t in tensors]

    def observe(self, obs: dict[str, torch.Tensor]) -> None:
        """Update the running normaliser with a rollout batch of observations."""
        (obs,) = self._here(obs)
        vector = self._vector(obs)
        if vector is not None:
            self.norm.update(vector)

    def _value(self, obs: dict[str, torch.Tensor], vector: torch.Tensor | None) -> torch.Tensor:
        value = self.value(self.critic(obs, vector))
        return value.squeeze(-1) if self.signals == 1 else value

    def get_value(self, obs: dict[str, torch.Tensor]) -> torch.Tensor:
        """-> V(obs) on the CPU: (B,), or (B, signals) with more than the extrinsic reward signal."""
        (obs,) = self._here(obs)
        return self._value(obs, self._normalised(obs)).cpu()

    def _normalised(self, obs: dict[str, torch.Tensor]) -> torch.Tensor | None:
        vector = self._vector(obs)
        return None if vector is None else self.norm(vector)

    def _heads(self, obs: dict[str, torch.Tensor], vector: torch.Tensor | None, mask: torch.Tensor | None = None):
        """-> the Gaussian means (B, c) or None, and each categorical part's log-probabilities [(B, n_i)], the
        choices that ``mask`` (B, sum(nvec)) bool closes at probability 0 (where :attr:`takes_masks`).

        Written out rather than built from ``torch.distributions`` objects: their construction costs more
        than the small networks themselves in PPO's hot loop (see benchmarks/train_throughput.py)."""
        hidden = self.actor(obs, vector)
        mu = self.mu(hidden) if self.mu is not None else None
        if self.logits is None:
            return mu, []
        logits = self.logits(hidden)
        if mask is not None and self.takes_masks:
            logits = logits.masked_fill(~mask, CLOSED_LOGIT)
        return mu, [torch.log_softmax(chunk, dim=1) for chunk in torch.split(logits, self.layout.nvec, 1)]

    def act(self, obs: dict[str, torch.Tensor], deterministic: bool = False, mask: torch.Tensor | None = None):
        """-> continuous (B, c), discrete (B, d) int64, log-prob (B,) (see :meth:`_log_prob_entropy`): sampled, or
        the modes if deterministic; ``mask`` (B, sum(nvec)) bool, the environment's open choices (optional). The
        critic's values come apart (:meth:`get_value`): a rollout's are computed after it, in big batches
        (``ppo.rollout_values``)."""
        obs, mask = self._here(obs, mask)
        vector = self._normalised(obs)
        mu, log_probs = self._heads(obs, vector, mask)
        batch = next(iter(obs.values())).shape[0]
        device = self.value.weight.device
        if mu is None:
            cont = torch.zeros(batch, 0, device=device)
        else:
            cont = mu if deterministic else mu + self.log_std.exp() * torch.randn_like(mu)
        if log_probs:
            disc = torch.stack([lp.argmax(1) if deterministic else torch.multinomial(lp.exp(), 1).squeeze(1)
                                for lp in log_probs], 1)
        else:
            disc = torch.zeros(batch, 0, dtype=torch.int64, device=device)
        logp, _ = self._log_prob_entropy(mu, log_probs, cont, disc)
        return cont.cpu(), disc.cpu(), logp.cpu()

    def evaluate(self, obs: dict[str, torch.Tensor], cont: torch.Tensor, disc: torch.Tensor,
                 mask: torch.Tensor | None = None):
        """-> log-prob (B,) or (B, logp_columns), entropy (B,), value (B,) of given actions, under the ``mask`` they
        were taken with (optional, as :meth:`act`)."""
        obs, cont, disc, mask = self._here(obs, cont, disc, mask)
        vector = self._normalised(obs)
        mu, log_probs = self._heads(obs, vector, mask)
        logp, entropy = self._log_prob_entropy(mu, log_probs, cont, disc)
        return logp.cpu(), entropy.cpu(), self._value(obs, vector).cpu()

    def _log_prob_entropy(self, mu: torch.Tensor | None, log_probs: list[torch.Tensor], cont: torch.Tensor,
                          disc: torch.Tensor) -> tuple[torch.Tensor, torch.Tensor]:
        """The log-probability of (cont, disc) and the policy's entropy (B,), for a diagonal Gaussian with
        state-independent log-std times independent categoricals.

        ``policy_loss: ml_agents``: one log-probability per action dimension, (B, c + len(nvec)), the Gaussian's
        dimensions first, and the Gaussian part's entropy the mean over its dimensions (ML-Agents'
        GaussianDistInstance.entropy); ``joint``: the joint log-probability (B,) and every entropy summed."""
        logps, entropies = [], []  # one term per action part, summed (no zeros to start from: a hot path)
        if mu is not None:
            log_std = self.log_std.expand_as(mu)
            per_dimension = -0.5 * ((cont - mu) / log_std.exp()).square() - log_std - HALF_LOG_2PI
            logps.append(per_dimension if self.per_dimension else per_dimension.sum(1))
            entropy = 0.5 + HALF_LOG_2PI + log_std
            entropies.append(entropy.mean(1) if self.per_dimension else entropy.sum(1))
        for i, lp in enumerate(log_probs):
            chosen = lp.gather(1, disc[:, i:i + 1])
            logps.append(chosen if self.per_dimension else chosen.squeeze(1))
            entropies.append(-(lp.exp() * lp).sum(1))
        if not self.per_dimension:
            return sum(logps[1:], logps[0]), sum(entropies[1:], entropies[0])
        logp = torch.cat(logps, dim=1) if len(logps) > 1 else logps[0]
        return logp, sum(entropies[1:], entropies[0])
