"""Learning curves as PNG (matplotlib, the ``plots`` extra): the training return over agent-steps with the
random, scripted and published-PPO levels on the test seeds drawn as horizontal lines."""

from __future__ import annotations

from pathlib import Path
from typing import Any

from .config import TrainError

LEVELS = (("random", "random policy", "tab:gray", ":"), ("scripted", "scripted policy", "tab:green", "--"))


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
    ax.plot(steps, [row[2] for row in data["curve"]], color="tab:blue", label="PPO (this toolkit), training return")
    if data.get("test_curve"):
        points = data["test_curve"]
        ax.errorbar([r[0] for r in points], [r[2] for r in points], yerr=[r[3] for r in points], fmt="s", ms=3,
                    color="tab:purple", capsize=2, label=f"checkpoints on test seeds ({data['test_curve_episodes']} episodes)")
    test = data["test"]["return"]
    ax.errorbar([data["agent_steps"]], [test["mean"]], yerr=[test["std"]], fmt="o", color="tab:blue",
                capsize=4, label=f"PPO test seeds ({data['test']['episodes']} episodes)")
    for key, label, color, style in LEVELS:
        ax.axhline(data[key]["mean"], color=color, linestyle=style, label=f"{label} (test seeds)")
    if data["published"]:
        ax.axhline(data["published"]["return"]["mean"], color="tab:red", linestyle="-.", label="published PPO (paper)")
    ax.set_xlabel("agent-steps")
    ax.set_ylabel("per-agent episode return")
    ax.set_title(f"{data['environment']} · {data['task']}")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8, loc="lower right")
    fig.tight_layout()
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path, metadata={"Software": None})
    plt.close(fig)
    return path
