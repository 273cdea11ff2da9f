"""benchmarks/opc_neighbour_sight.py: a collector blind to its neighbours crashes at the original's trained rate.

The original's trained worlds end on crashes at a steady rate, about once every 160 decisions (the reward table's
ending note); ours, seeing their closest neighbour, learn to outlive that. The scripted skipper, a collector that
steers for dense water and turns away from a vessel it sees close ahead, lives near the time limit when it sees its
neighbour and, blind to it (params.neighbour_sight_m 0), meets the others by chance where the plastic draws them all:
its lives fall within the original's trained band, nearly all ended by collisions. Uniform random play reads
nothing, so the sight cannot move it."""

from __future__ import annotations

from hivex_dsl.evaluation.original import compare

from ..benchmark_scripts import benchmark_script

script = benchmark_script("opc_neighbour_sight")
WORLDS = 12


def original_trained_band() -> tuple[float, float]:
    """The original's Episode Length band (its three runs' least and greatest) from a quarter of its budget (the
    curve's last step) on."""
    training = compare.original_cell(script.ENV, 0, None).panel("Episode Length").training
    late = training.band_steps >= 0.25 * training.band_steps.max()
    return float(training.lower[late].min()), float(training.upper[late].max())


def test_a_blind_skipper_lives_as_the_originals_trained_vessels_and_a_seeing_one_far_longer():
    lower, upper = original_trained_band()
    seeing, blind = script.lives(None, "scripted", WORLDS), script.lives(0.0, "scripted", WORLDS)
    assert lower <= blind["decisions"] <= upper, (blind, (lower, upper))
    assert seeing["decisions"] > 2 * upper  # it keeps clear of what it sees and lives near the 1,000-decision limit
    assert blind["collision"] > 0.5 > seeing["collision"]  # what ends the blind worlds is meeting each other
    assert blind["border"] == seeing["border"] == 0.0  # it still knows where it is


def test_the_sight_does_not_move_random_play():
    assert script.lives(None, "random", 4) == script.lives(0.0, "random", 4)

