"""benchmarks/opc_territory.py: how far apart vessels keep and how widely each roams, read from their positions."""

from __future__ import annotations

import numpy as np
import pytest

from ..benchmark_scripts import benchmark_script

script = benchmark_script("opc_territory")


def test_pair_distances_and_strays_by_hand():
    # one decision, three vessels on a 3-4-5 line: pairs (0, 1), (0, 2), (1, 2)
    line = np.array([[[0.0, 0.0], [3.0, 4.0], [6.0, 8.0]]])
    np.testing.assert_allclose(script.pair_distances(line), [[5.0, 10.0, 5.0]])
    # vessel 0 goes from (0, 0) to (2, 0): 1 m either side of its mean; vessel 1 holds still
    moving = np.array([[[0.0, 0.0], [9.0, 9.0]], [[2.0, 0.0], [9.0, 9.0]]])
    assert script.strays(moving) == pytest.approx([1.0, 0.0])


def test_the_uniform_references_hold_on_the_unit_square():
    rng = np.random.default_rng(3)
    points = rng.uniform(size=(400_000, 2, 2))
    assert np.linalg.norm(points[:, 0] - points[:, 1], axis=-1).mean() == pytest.approx(
        script.PAIR_MEAN_OF_SIDE, rel=0.005)
    assert np.linalg.norm(points[:, 0] - 0.5, axis=-1).mean() == pytest.approx(script.CENTRE_MEAN_OF_SIDE, rel=0.005)


def test_a_policy_is_read_at_every_decision_of_every_world():
    """Random play on two test worlds: every logged decision belongs to an episode (the script checks the count),
    and the readings are positions on the map: pairs farther apart on average than the 10 m that crashes them and
    nearer than the diagonal, strays under it."""
    compiled = script.main_task({})
    row = script.territory(compiled, script.named_policy("random", compiled), 2)
    assert row["life"] > 1 and 0 < row["crashes"] < 1000
    assert 10.0 < row["pair_m"] < 2 * 200.0 * np.sqrt(2) and 0.0 <= row["near"] <= 1.0
    assert 0.0 < row["stray_m"] < 200.0 * np.sqrt(2)
