"""Learning curves as PNG (matplotlib, the ``plots`` extra): the training return over agent-steps with the
random, scripted and published-PPO levels on the test seeds drawn as horizontal lines."""

from __future__ import annotations

from pathlib import Path
from typing import Any

from .config import TrainError

LEVELS = (("random", "random policy", "tab:gray", ":"), ("scripted", "scripted policy", "tab:green", "--"))


def running_mean(values: list[float], window: int) -> list[float]:
    """The mean of each value and the up to ``window - 1`` before it."""
    out, total = [], 0.0
    for i, value in enumerate(values):
        total += value - (values[i - window] if i >= window else 0.0)
        out.append(total / min(i + 1, window))
    return out


def learning_curve(data: dict[str, Any], path: Path) -> Path:
    """``data`` is a baseline record (see baselines.py): its ``curve`` rows are (agent-steps, wall s, return)."""
    try:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        raise TrainError("learning curves need matplotlib: pip install 'hivex-dsl[plots]'") from None
    fig, ax = plt.subplots(figsize=(7, 4), dpi=100)
    steps = [row[0] for row in data["curve"]]
    returns = [row[2] for row in data["curve"]]
    window = max(1, len(returns) // 50)
    if window > 1:  # a few episodes per update make the raw curve noisy: draw it faint under its running mean
        ax.plot(steps, returns, color="tab:blue", alpha=0.2, linewidth=0.8)
    ax.plot(steps, running_mean(returns, window), color="tab:blue", marker="o" if len(steps) < 20 else None,
            label="PPO (this toolkit), training return" + (f" (mean of {window} updates)" if window > 1 else ""))
    if data.get("test_curve"):
        points = data["test_curve"]
        ax.errorbar([r[0] for r in points], [r[2] for r in points], yerr=[r[3] for r in points], fmt="s", ms=3,
                    color="tab:purple", capsize=2, label=f"checkpoints on test seeds ({data['test_curve_episodes']} episodes)")
    test = data["test"]["return"]
    ax.errorbar([data["agent_steps"]], [test["mean"]], yerr=[test["std"]], fmt="o", color="tab:blue",
                capsize=4, label=f"PPO test seeds ({data['test']['episodes']} episodes)")
    if data.get("other_seeds"):
        others = data["other_seeds"]
        ax.errorbar([e["agent_steps"] for e in others], [e["return"]["mean"] for e in others],
                    yerr=[e["return"]["std"] for e in others], fmt="D", ms=4, color="tab:orange", capsize=3,
                    label=f"other training seeds ({', '.join(str(e['seed']) for e in others)}), test seeds")
    for key, label, color, style in LEVELS:
        ax.axhline(data[key]["mean"], color=color, linestyle=style, label=f"{label} (test seeds)")
    if data["published"]:
        ax.axhline(data["published"]["return"]["mean"], color="tab:red", linestyle="-.", label="published PPO (paper)")
    ax.set_xlabel("agent-steps")
    ax.set_ylabel("per-agent episode return")
    ax.set_title(f"{data['environment']} · {data['task']}")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8, loc="best")
    fig.tight_layout()
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path, metadata={"Software": None})
    plt.close(fig)
    return path
