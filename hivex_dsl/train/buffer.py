"""The storage of one PPO rollout, its rows flattened for the update, and the row gathers of the update's shuffles.

Both avoid copies of the camera observations, which dominate the memory traffic of the visual environments'
updates (tens of MB a rollout), without changing a number: see ``tests/train/test_exact_speedups.py``.
"""

from __future__ import annotations

from typing import Any, Callable

import numpy as np
import torch

CHUNK = 4096  # rows per no-grad pass over a whole rollout: big enough for efficient kernels, small enough for memory


def in_chunks(fn: Callable[[dict[str, torch.Tensor]], torch.Tensor], rows: dict[str, torch.Tensor]) -> torch.Tensor:
    """``fn`` (a no-grad network pass) over ``rows`` (N, ...) per key, CHUNK rows at a time; -> its outputs
    concatenated (N, ...). On the CPU a row's output does not depend on the chunk it is in (the tests check)."""
    total = next(iter(rows.values())).shape[0]
    return torch.cat([fn({k: v[start:start + CHUNK] for k, v in rows.items()}) for start in range(0, total, CHUNK)])


def merge_steps(tensor: torch.Tensor) -> torch.Tensor:
    """(T, S, ...) -> (T * S, ...)."""
    return tensor.reshape((tensor.shape[0] * tensor.shape[1],) + tensor.shape[2:])


class Rollout:
    """(T, S) storage of one rollout; observations as a dict of (T, S, ...) tensors; log-probabilities (T, S),
    or (T, S, logp_columns) with one per action dimension; with ``mask_width`` the action masks the policy acted
    under, (T, S, mask_width) bool (``mask``; None without).

    The observations live in (T + 1, S, ...) frames whose last row is the observation after the rollout's
    last step, so the observations (rows :T) and the next observations (rows 1:) are both views, never copies
    (a camera buffer is tens of MB)."""

    def __init__(self, steps: int, slots: int, first_obs: dict[str, torch.Tensor], continuous: int, discrete: int,
                 signals: int = 1, logp_columns: int = 0, mask_width: int = 0):
        self.capacity = steps
        self._frames = {k: torch.zeros((steps + 1,) + v.shape, dtype=v.dtype) for k, v in first_obs.items()}
        self._stepwise = {
            "cont": torch.zeros(steps, slots, continuous),
            "disc": torch.zeros(steps, slots, discrete, dtype=torch.int64),
            "logp": torch.zeros((steps, slots) + ((logp_columns,) if logp_columns else ())),
            "rewards": torch.zeros(steps, slots),
            "values": torch.zeros((steps, slots) + ((signals,) if signals > 1 else ())),  # one column per signal
            **{name: torch.zeros(steps, slots) for name in ("terminated", "done", "valid")}}
        if mask_width:
            self._stepwise["mask"] = torch.ones(steps, slots, mask_width, dtype=torch.bool)
        self.mask: torch.Tensor | None = None
        self.limit(steps)
        self.end(first_obs)
        self.gathered = RowBuffers()

    def limit(self, steps: int) -> None:
        """Use the first ``steps`` (1 to ``capacity``) of the storage as the rollout: every array a view of that
        many steps, the frames of one more (a rollout that ends early, or the run's last, shorter one)."""
        self.frames = {k: v[:steps + 1] for k, v in self._frames.items()}
        self.obs = {k: v[:steps] for k, v in self.frames.items()}
        for name, full in self._stepwise.items():
            setattr(self, name, full[:steps])

    @property
    def last_obs(self) -> dict[str, torch.Tensor]:
        """The observation after the rollout's last step (S, ...) per key, a view of the frames' last row."""
        return {k: v[-1] for k, v in self.frames.items()}

    def end(self, last_obs: dict[str, torch.Tensor]) -> None:
        """Record the observation after the rollout's last step."""
        for k, v in last_obs.items():
            self.frames[k][-1] = v

    def flat(self, name: str) -> torch.Tensor:
        return merge_steps(getattr(self, name))

    def flat_obs(self) -> dict[str, torch.Tensor]:
        return {k: merge_steps(v) for k, v in self.obs.items()}

    def flat_frames(self) -> dict[str, torch.Tensor]:
        """Every frame flat ((T + 1) * S, ...): the observations, then the one after the last step."""
        return {k: merge_steps(v) for k, v in self.frames.items()}

    def flat_next_obs(self) -> dict[str, torch.Tensor]:
        """The observation each step returned, flat (T * S, ...): in NEXT_STEP mode an ending step's is the
        episode's last observation, so every valid transition's s' is right."""
        return {k: merge_steps(v[1:]) for k, v in self.frames.items()}


class FinishedTrajectories:
    """ML-Agents' update trigger over the slots of a rollout: a slot's trajectory is finished when it holds
    ``time_horizon`` experiences or its episode ends (ML-Agents' AgentProcessor hands it to the trainer then), and
    the trainer updates once its buffer holds more than ``buffer_size`` experiences of finished trajectories."""

    def __init__(self, slots: int, time_horizon: int, buffer_size: int) -> None:
        self.open = np.zeros(slots, np.int64)  # experiences of each slot's unfinished trajectory
        self.finished = 0
        self.time_horizon, self.buffer_size = time_horizon, buffer_size

    def step(self, valid: np.ndarray, done: np.ndarray) -> bool:
        """Count one step of every slot (``valid``: the slots whose step was an experience, ``done``: whose episode
        ended there, both (S,) bool); -> whether an update is due."""
        self.open += valid
        ends = (self.open >= self.time_horizon) | (done & (self.open > 0))
        self.finished += int(self.open[ends].sum())
        self.open[ends] = 0
        return self.finished > self.buffer_size


class RowBuffers:
    """Destination tensors kept from one shuffle to the next: gathering rows into memory already touched is
    several times faster than into a fresh allocation (a 87 MB camera buffer: 10 ms against 54 ms on CPU),
    and the copy is the same bytes, so the update is unchanged."""

    def __init__(self) -> None:
        self._tensors: dict[str, torch.Tensor] = {}

    def take(self, data: dict[str, Any], index: torch.Tensor, prefix: str = "") -> dict[str, Any]:
        """``data`` (tensors, and nested dicts of them) at rows ``index`` (N,), each a view of a kept buffer."""
        return {k: self.take(v, index, f"{prefix}{k}/") if isinstance(v, dict) else self._rows(prefix + k, v, index)
                for k, v in data.items()}

    def _rows(self, key: str, source: torch.Tensor, index: torch.Tensor) -> torch.Tensor:
        kept = self._tensors.get(key)
        if kept is None or kept.shape[1:] != source.shape[1:] or kept.shape[0] < index.numel() \
                or kept.dtype != source.dtype or kept.device != source.device:
            kept = self._tensors[key] = torch.empty((source.shape[0],) + source.shape[1:], dtype=source.dtype,
                                                    device=source.device)
        return torch.index_select(source, 0, index.to(source.device), out=kept[:index.numel()])


def update_data(buf: Rollout, advantages: torch.Tensor, returns: torch.Tensor, with_next_obs: bool = False
                ) -> tuple[dict[str, Any], np.ndarray]:
    """The rollout flat (T * S rows) for the update, advantages normalised over the valid rows; -> (data, the
    valid rows' indices). Masked rows stay in ``data`` (copying the valid ones out costs a camera copy)."""
    valid = np.flatnonzero(buf.flat("valid").numpy() > 0)
    data = {"obs": buf.flat_obs(), "cont": buf.flat("cont"), "disc": buf.flat("disc"), "old_logp": buf.flat("logp"),
            "old_values": buf.flat("values"), "returns": merge_steps(returns), "adv": advantages.reshape(-1)}
    if buf.mask is not None:
        data["mask"] = buf.flat("mask")
    if with_next_obs:
        data["next_obs"] = buf.flat_next_obs()
    if valid.size:
        valid_adv = data["adv"][valid]
        data["adv"] = (data["adv"] - valid_adv.mean()) / (valid_adv.std(unbiased=False) + 1e-8)
    return data, valid


def minibatches(data: dict[str, Any], valid: np.ndarray, batch_size: int, rng: np.random.Generator,
                buffers: RowBuffers | None = None):
    """One epoch over the ``valid`` rows of ``data`` in a fresh random order: minibatches of ``batch_size`` rows.

    The rows are shuffled with one gather per epoch (cameras make it the costly copy), into ``buffers`` when
    given (kept from one epoch to the next), and the minibatches are slices of it, views: a gather per minibatch
    costs more small ops in the update's hot loop."""
    order = torch.as_tensor(valid[rng.permutation(valid.size)])
    shuffled = (buffers or RowBuffers()).take(data, order)
    for start in range(0, valid.size, batch_size):
        yield _slice_rows(shuffled, start, start + batch_size)


def _slice_rows(data: dict[str, Any], start: int, stop: int) -> dict[str, Any]:
    """Rows ``start:stop`` of ``data`` (tensors, and nested dicts of them), as views."""
    return {k: _slice_rows(v, start, stop) if isinstance(v, dict) else v[start:stop] for k, v in data.items()}
