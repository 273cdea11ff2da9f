"""benchmarks/wrm_keeping_phases.py: the main task's keeping over training, pooled over the levels (issue 52; the
reward table's note 'Keeping over training, pooled over the levels')."""

from __future__ import annotations

import numpy as np
import pytest

from ..benchmark_scripts import benchmark_script

script = benchmark_script("wrm_keeping_phases")


def test_each_phase_pools_its_points_by_hand():
    """Points at 5%, 10%, 20%, 30%, 60%, 95% and 100% of the budget: the first tenth holds the first two (Self 1 + 3
    of 4 + 4), 10-25% the third (2 of 8), 25-50% the fourth (its Individual Performance NaN: nothing), 50-75% the
    fifth (1 of 10), the last tenth the last two (0 + 2 of 5 + 5); a recorded run reads its steps over the budget."""
    fractions = np.array([0.05, 0.1, 0.2, 0.3, 0.6, 0.95, 1.0])
    kept = np.array([1.0, 3.0, 2.0, 5.0, 1.0, 0.0, 2.0])
    individual = np.array([4.0, 4.0, 8.0, np.nan, 10.0, 5.0, 5.0])
    phases = script.phase_keeping(fractions, kept, individual)
    assert phases[0] == pytest.approx(0.5) and phases[1] == pytest.approx(0.25) and phases[3] == pytest.approx(0.1)
    assert np.isnan(phases[2]) and phases[4] == pytest.approx(0.2)
    panels = {script.SELF: list(kept), script.INDIVIDUAL: [None if np.isnan(v) else v for v in individual]}
    run = {"curve": [[f * 1000.0, 0.0] for f in fractions], "curve_panels": panels}
    assert script.recorded_phase_keeping(run, 1000.0) == pytest.approx(phases, nan_ok=True)


def test_over_the_levels_ours_gives_its_keeping_away_sooner_than_the_original():
    """The mean over the ten levels (so no one level's stream decides): the original's main task keeps 0.26 of its
    Individual Performance in the first tenth of its budget and 0.10 in the last, ours (the committed grid's seeds)
    0.19 and 0.03; at the start ours keeps three quarters of the original's, from half the budget on about half and
    less."""
    table = script.phase_table()
    assert [row[0] for row in table] == list(range(1, 11))
    theirs, ours = (np.mean([row[column] for row in table], axis=0) for column in (1, 2))
    assert 0.6 < ours[0] / theirs[0] < 0.9
    assert (ours[3:] / theirs[3:] < 0.6).all(), np.round(ours / theirs, 2)
    assert theirs[-1] / theirs[0] > 0.35 and ours[-1] / ours[0] < 0.25


def test_a_missing_grid_is_refused_with_exit_2(tmp_path, monkeypatch, capsys):
    monkeypatch.setattr(script, "GRID", tmp_path / "missing.json")
    assert script.main() == 2
    assert "missing.json" in capsys.readouterr().err
