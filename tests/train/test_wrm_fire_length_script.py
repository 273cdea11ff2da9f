"""benchmarks/wrm_fire_length.py: Episode Length averaged as ML-Agents logs it, by hand, and its bad input."""

from __future__ import annotations

import numpy as np
import pytest

from hivex_dsl.base.errors import HivexError

from .conftest import benchmark_script

script = benchmark_script("wrm_fire_length")


def test_each_window_averages_the_episodes_that_ended_in_it():
    """World 0 ends fires on steps 100 (100 long), 350 (250) and 600 (250); world 1 one on step 500 (500): windows
    are steps 1-500 and 501-1000 of each world, so (100 + 250) / 2 = 175 and 250 for world 0, 500 for world 1
    (step 500 is still the first window); the mean over windows, 308.3, is above the mean over episodes, 275."""
    worlds, ends = np.array([0, 0, 0, 1]), np.array([100, 350, 600, 500])
    lengths = np.array([100.0, 250.0, 250.0, 500.0])
    np.testing.assert_allclose(script.window_means(worlds, ends, lengths), [175.0, 250.0, 500.0])
    assert script.window_means(worlds, ends, lengths).mean() == pytest.approx(925 / 3)


def test_params_are_read_as_json_values_and_bad_ones_are_refused():
    assert script.parse_params(["spread_chance_per_factor=0.5", "redraw_island=\"seed\""]) == {
        "spread_chance_per_factor": 0.5, "redraw_island": "seed"}
    with pytest.raises(HivexError, match="expected NAME=VALUE"):
        script.parse_params(["0.5"])
    with pytest.raises(HivexError, match="must be a number"):
        script.parse_params(["spread_chance_per_factor=x"])


def test_too_short_a_stream_is_refused_with_exit_2(capsys):
    assert script.main(["--steps", "100"]) == 2
    assert "--steps >= 500" in capsys.readouterr().err
