"""What a training run reports: per-agent episode summaries, TensorBoard scalars and a progress bar."""

from __future__ import annotations

import sys
import time
from typing import Any, Callable

import numpy as np

from ..sim.statistics import pooled

LINE_EVERY_S = 30.0  # off a terminal, a progress line this often
EVENTS = "events.out.tfevents.*"  # the names SummaryWriter gives its event files
EPISODE_KEYS = (("hivex_episode", "_hivex_episode"), ("episode", "_episode"))


def episode_summaries(infos: dict[str, Any]) -> dict[str, Any] | None:
    """The vector env's per-agent summaries of episodes that ended this step, restricted to those slots:
    ``{"return": (n,), "length": (n,), "reward_terms": {name: (n,)}, "statistics": {name: (n,)},
    "running": {name: {"sums": (n,), "counts": (n,)}}}`` (``running``: the running-mean statistics' parts).
    Reads ``hivex_episode`` (the new name) or ``episode`` (the old one). ``length`` counts decisions, as
    ML-Agents' episode length does: a summary's ``decisions``, or its ``length`` where it has none (a summary
    of before decision periods, whose steps were all decisions)."""
    for key, mask_key in EPISODE_KEYS:
        if key in infos:
            summary = infos[key]
            length = np.asarray(summary["decisions"] if "decisions" in summary else summary["length"])
            # a slot restarting on the very step its world ends reports an empty episode: no experience
            ended = np.asarray(infos[mask_key], dtype=bool) & (length > 0)
            return {"return": np.asarray(summary["return"])[ended], "length": length[ended],
                    "reward_terms": {k: np.asarray(v)[ended] for k, v in summary.get("reward_terms", {}).items()},
                    "statistics": {k: np.asarray(v)[ended] for k, v in summary.get("statistics", {}).items()},
                    "running": {k: {part: np.asarray(v[part])[ended] for part in ("sums", "counts")}
                                for k, v in summary.get("running", {}).items()}}
    return None


class EpisodeLog:
    """Gathers per-agent episode summaries between two reports, and the episode sums of the trainer's own reward
    signals (:meth:`record_signal`)."""

    def __init__(self) -> None:
        self._parts: list[dict[str, Any]] = []
        self._running: dict[str, np.ndarray] = {}  # signal -> (S,) each slot's sum over its episode so far
        self._signal_sums: dict[str, list[np.ndarray]] = {}  # signal -> the sums of episodes ended since a drain
        self._open: np.ndarray | None = None  # (S, 1 + K) each slot's open trajectory: experiences, then value sums
        self._estimates: list[np.ndarray] = []  # (n, K) the mean value estimates of trajectories cut since a drain
        self._heads: tuple[str, ...] = ()
        self._losses: dict[str, list[float]] = {}  # loss -> each update's value since a drain

    def record(self, infos: dict[str, Any]) -> None:
        summary = episode_summaries(infos)
        if summary is not None and summary["return"].size:
            self._parts.append(summary)

    def record_signal(self, name: str, rewards: np.ndarray, ended: np.ndarray) -> None:
        """Add one rollout's rewards (T, S) of a reward signal the trainer computes (curiosity's, weighted by its
        strength) to each slot's episode sum; where ``ended`` (T, S) marks an episode's last experience, its sum is
        kept for the next drain and the slot's sum starts again. ML-Agents reports the same sum at an agent's
        episode end as ``Policy/<Signal> Reward``."""
        running = self._running.setdefault(name, np.zeros(rewards.shape[1]))
        sums = self._signal_sums.setdefault(name, [])
        for reward, end in zip(np.asarray(rewards, np.float64), np.asarray(ended, bool)):
            running += reward
            if end.any():
                sums.append(running[end].copy())
                running[end] = 0.0

    def record_estimates(self, heads: tuple[str, ...], values: np.ndarray, valid: np.ndarray, done: np.ndarray,
                         time_horizon: int) -> None:
        """Add one rollout's value estimates (T, S, K), one column per value head named in ``heads``, of the
        experiences where ``valid`` (T, S). A slot's trajectory is cut where its episode ends (``done`` (T, S)) or once
        it holds ``time_horizon`` experiences, as ML-Agents' AgentProcessor cuts it; each cut trajectory's mean value
        is kept for the next drain, as ML-Agents' trainer reports ``Policy/<Signal> Value Estimate`` (the mean of
        the critic's estimates over a trajectory, when it processes it)."""
        values = np.asarray(values, np.float64).reshape(valid.shape + (len(heads),))
        if self._open is None or self._open.shape != (valid.shape[1], 1 + len(heads)):
            self._open, self._heads = np.zeros((valid.shape[1], 1 + len(heads))), tuple(heads)
        for value, experience, end in zip(values, np.asarray(valid, bool), np.asarray(done, bool)):
            self._open[experience] += np.concatenate([np.ones((experience.sum(), 1)), value[experience]], axis=1)
            cut = (self._open[:, 0] > 0) & ((self._open[:, 0] >= time_horizon) | end)
            if cut.any():
                self._estimates.append(self._open[cut, 1:] / self._open[cut, :1])
                self._open[cut] = 0.0

    def record_losses(self, losses: dict[str, float]) -> None:
        """Add one update's losses (``update``'s means over its minibatches: ``entropy``, ``curiosity_forward``,
        ...); a drain reports each one's mean over the updates since the last, as ML-Agents' StatsReporter reports
        ``Policy/Entropy`` and ``Losses/...`` at a summary point."""
        for name, value in losses.items():
            self._losses.setdefault(name, []).append(float(value))

    def values(self) -> dict[str, Any]:
        """Every recorded summary concatenated (same layout as one summary); {} if none."""
        if not self._parts:
            return {}
        cat = lambda key: np.concatenate([p[key] for p in self._parts])  # noqa: E731
        nested = lambda key: {name: np.concatenate([p[key][name] for p in self._parts if name in p[key]])  # noqa: E731
                              for name in self._parts[-1][key]}
        running = {name: {part: np.concatenate([p["running"][name][part] for p in self._parts
                                                if name in p.get("running", {})]) for part in ("sums", "counts")}
                   for name in self._parts[-1].get("running", {})}
        return {"return": cat("return"), "length": cat("length"), "reward_terms": nested("reward_terms"),
                "statistics": nested("statistics"), "running": running}

    def drain(self) -> dict[str, Any]:
        """Means since the last drain: ``{"return", "length", "episodes", "reward_terms", "statistics", "signals",
        "estimates", "losses"}`` (``signals``: each trainer signal's mean episode sum, where an episode ended with
        one; ``estimates``: each value head's mean over the trajectories cut, :meth:`record_estimates`; ``losses``:
        each loss's mean over the updates recorded, :meth:`record_losses`). A
        running-mean statistic is pooled, as the original's TensorBoard point is: every value added in any of the
        episodes weighs the same (:func:`hivex_dsl.sim.statistics.pooled`), not each episode's mean."""
        values = self.values()
        signals = {name: float(np.concatenate(sums).mean()) for name, sums in self._signal_sums.items() if sums}
        if not values:  # no point without an ended episode; the cut trajectories' estimates wait for the next one
            self._signal_sums = {}
            return {}
        estimates = dict(zip(self._heads, np.concatenate(self._estimates).mean(0).tolist())) if self._estimates else {}
        losses = {name: float(np.mean(values)) for name, values in self._losses.items()}
        self._parts, self._signal_sums, self._estimates, self._losses = [], {}, [], {}
        mean = lambda group: {k: float(v.mean()) for k, v in group.items() if v.size}  # noqa: E731
        pooled_means = {name: pooled(parts["sums"], parts["counts"]) for name, parts in values["running"].items()
                        if parts["sums"].size}
        return {"return": float(values["return"].mean()), "length": float(values["length"].mean()),
                "episodes": int(values["return"].size), "reward_terms": mean(values["reward_terms"]),
                "statistics": mean(values["statistics"]) | pooled_means, "signals": signals,
                "estimates": estimates, "losses": losses}


class ScalarLog:
    """TensorBoard event files under ``run.root/tb`` (torch's SummaryWriter; needs the tensorboard package), each
    recorded in the run's manifest as it grows (:meth:`hivex_dsl.train.rundir.RunDir.appended`)."""

    def __init__(self, run: Any):
        from torch.utils.tensorboard import SummaryWriter

        folder = run.root / "tb"
        before = set(folder.glob(EVENTS)) if folder.is_dir() else set()
        self.run = run
        self.writer = SummaryWriter(log_dir=str(folder))  # opens its event file at once
        self.files = sorted(set(folder.glob(EVENTS)) - before)
        self.flush()

    def write(self, step: int, episodes: dict[str, Any], losses: dict[str, float], charts: dict[str, float]) -> None:
        scalars: dict[str, float] = {}
        if episodes:
            scalars |= {"episode/return": episodes["return"], "episode/length": episodes["length"]}
            scalars |= {f"reward_terms/{k}": v for k, v in episodes["reward_terms"].items()}
            scalars |= {f"statistics/{k}": v for k, v in episodes["statistics"].items()}
            scalars |= {f"episode/{k}_reward": v for k, v in episodes.get("signals", {}).items()}
            scalars |= {f"policy/{k}_value_estimate": v for k, v in episodes.get("estimates", {}).items()}
        scalars |= {f"losses/{k}": v for k, v in losses.items()}
        scalars |= {f"charts/{k}": v for k, v in charts.items()}
        for tag, value in scalars.items():
            self.writer.add_scalar(tag, value, step)

    def flush(self) -> None:
        """Write what is buffered, and record the event files as they are now."""
        self.writer.flush()
        for path in self.files:
            self.run.appended(path)

    def close(self) -> None:
        self.writer.close()
        for path in self.files:
            self.run.appended(path)


class Progress:
    """The shared bar (:func:`hivex_dsl.evaluation.progress.bar`) over agent-steps: rate, time left, and the latest mean
    episode return, where stderr is a terminal. Elsewhere (a log file, a pipe, a batch job) it prints a line every
    ``every`` seconds instead, and a last one when closed, so a long run is never silent."""

    def __init__(self, total: int, enabled: bool, label: str, start: int = 0, every: float = LINE_EVERY_S,
                 clock: Callable[[], float] = time.monotonic):
        from ..evaluation.progress import bar

        self.bar = bar(total, label, unit="step", enabled=enabled, initial=min(start, total), unit_scale=True,
                       leave=True)
        self.last_return: float | None = None
        self.total, self.label, self.done, self.start = total, label, min(start, total), min(start, total)
        self.lines, self.every, self.clock = enabled and self.bar.disable, every, clock
        self.began = self.last_line = clock()

    def advance(self, steps: int, episode_return: float | None) -> None:
        if episode_return is not None:
            self.last_return = episode_return
            self.bar.set_postfix(ret=f"{episode_return:.1f}", refresh=False)
        steps = min(steps, self.total - self.done)
        self.done += steps
        self.bar.update(steps)
        if self.lines and self.clock() - self.last_line >= self.every:
            self._line()

    def _line(self) -> None:
        self.last_line = now = self.clock()
        rate = (self.done - self.start) / max(now - self.began, 1e-9)
        shown = "" if self.last_return is None else f", mean episode return {self.last_return:.2f}"
        print(f"{self.label}: {self.done:,} / {self.total:,} agent-steps ({100 * self.done / max(self.total, 1):.0f}%),"
              f" {rate:,.0f} agent-steps/s{shown}", file=sys.stderr, flush=True)

    def close(self) -> None:
        self.bar.close()
        if self.lines:
            self._line()
