"""benchmarks/opc_life_spread.py: the original's trained vessel lives spread as steady crashes do (issue 52).

What ends the original's trained vessel-episodes near 160 decisions is not recorded (the reward table's ending
note). Its summary points scatter as much as lives spread like an exponential's would (coefficient of variation
about 1), read two ways that share no error, so no timer-like ending (lives held near their mean) made them: they
ended on crashes at a steady rate, as ours do, only more often. The estimators are checked first on lives drawn with
a known spread."""

from __future__ import annotations

import json

import numpy as np
import pytest

from ..benchmark_scripts import benchmark_script

script = benchmark_script("opc_life_spread")
MEAN_LIFE = 160.0
POINTS = 200


def lives(rng: np.random.Generator, cv: float, size) -> np.ndarray:
    """Gamma-distributed lives of mean MEAN_LIFE and coefficient of variation ``cv`` (1: an exponential's)."""
    shape = 1.0 / cv**2
    return rng.gamma(shape, MEAN_LIFE / shape, size=size)


@pytest.mark.parametrize("cv", [1.0, 0.25])
def test_the_band_ranges_read_a_known_spread(cv):
    """Three runs, each summary point the mean of the world-episodes that ended in it (5,000 / 160, about 31)."""
    rng = np.random.default_rng(0)
    worlds = round(script.WORLD_DECISIONS / MEAN_LIFE)
    points = lives(rng, cv, (3, POINTS, worlds)).mean(axis=2)
    read = script.spread_of_ranges(points.mean(axis=0), points.max(axis=0) - points.min(axis=0))
    assert read["cv"] == pytest.approx(cv, rel=0.12)


@pytest.mark.parametrize("cv", [1.0, 0.25])
def test_successive_points_read_a_known_spread(cv):
    """One run whose points pool 10 to 40 world-episodes each."""
    rng = np.random.default_rng(1)
    worlds = rng.integers(10, 41, size=POINTS)
    lengths = np.array([lives(rng, cv, n).mean() for n in worlds])
    assert script.spread_of_successive(lengths, worlds.astype(float))["cv"] == pytest.approx(cv, rel=0.12)


def test_the_originals_lives_spread_as_steady_crashes():
    """Its band's ranges (widened by any offsets between its runs) and its mean line's successive points (where
    those offsets cancel) read a coefficient of variation of 1.1-1.2 together: lives spread as an exponential's,
    four times what a timer-like ending holding them within a quarter of their mean would give."""
    spreads = script.original_spreads()
    ranges, line = spreads["ranges"]["cv"], spreads["mean_line"]["cv"]
    assert 0.8 < ranges < 1.4 and 0.8 < line < 1.4, spreads
    assert abs(ranges - line) < 0.2, spreads
    assert 150 < spreads["ranges"]["mean"] < 175


def test_the_records_lives_spread_alike_and_last_longer():
    """Every seed of the committed record spreads its lives as the original's (coefficient of variation 0.8-1.4)
    and lives longer on average: the gap is how often its vessels crash, not how their lives are spread."""
    original = script.original_spreads()["ranges"]
    spreads = script.record_spreads(json.loads(script.RECORD.read_text()))
    assert len(spreads) == 3
    for seed, spread in spreads.items():
        assert 0.8 < spread["cv"] < 1.4, (seed, spread)
        assert spread["mean"] > 1.1 * original["mean"], (seed, spread)
