"""What the towers observe, read from the curiosity module's records (issue 52, session 95; the reward table's note
'What the towers observe'). The module's inverse model guesses each of a tower's four actions from two successive
observations: where they show nothing of the actions its loss is the policy's entropy, so their gap measures what
the observations show. The original's was within 0.03 nats at every window past the first tenth of its budget; the
agent's own budget as the eighth observed value, which every add and subtract moves by 0.1, opened it to 0.35-0.44
nats and raised the forward loss and the curiosity reward 2.5 to 8 times over the original's. The record,
trained observing whether a fire is detected, keeps the original's gap and its curiosity numbers."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

from hivex_dsl.evaluation.original.compare import seed_curves
from hivex_dsl.evaluation.original.curves import original_curves

RECORD = Path(__file__).resolve().parents[2] / "benchmarks" / "baselines" / "wildfire_resource_management.json"
# agent-steps: 10-25, 25-50, 50-75 and 75-100% of the original's 450,000 (the first tenth is the untrained module's)
WINDOWS = ((45_000, 112_500), (112_500, 225_000), (225_000, 337_500), (337_500, 450_000))


def original_windows(panel: str) -> np.ndarray:
    """(4,) the original's mean curve (main task, level 1) averaged over each window."""
    curve = original_curves("wildfire_resource_management", 0, 1).panel(panel).training
    return np.array([curve.mean_at(np.linspace(low, high, 50)).mean() for low, high in WINDOWS])


def seed_windows(steps: np.ndarray, values: np.ndarray) -> np.ndarray:
    """(4,) one seed's points averaged over each window."""
    return np.array([values[(steps > low) & (steps <= high)].mean() for low, high in WINDOWS])


def test_the_original_s_inverse_model_recovered_almost_nothing_of_the_actions():
    gap = original_windows("Entropy") - original_windows("Curiosity Inverse Loss")
    assert ((gap > 0.0) & (gap < 0.035)).all(), gap


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_the_record_s_towers_show_their_actions_and_stir_the_module_as_the_original_s(seed):
    curve = seed_curves(json.loads(RECORD.read_text("utf-8")))[seed]
    windows = {panel: seed_windows(curve.steps, curve.panels[panel]) for panel in (
        "Entropy", "Curiosity Inverse Loss", "Curiosity Forward Loss", "Curiosity Reward")}
    assert (np.abs(windows["Entropy"] - windows["Curiosity Inverse Loss"]) < 0.06).all()
    forward = windows["Curiosity Forward Loss"] / original_windows("Curiosity Forward Loss")
    reward = windows["Curiosity Reward"] / original_windows("Curiosity Reward")
    assert ((forward > 0.8) & (forward < 1.7)).all(), forward
    assert ((reward > 0.8) & (reward < 2.0)).all(), reward
