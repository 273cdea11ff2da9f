"""When the original's drones could drop a seed, read from its Entropy panels (issue 52; the reward table's note
"Read (issue 52, session 30): the untrained flight"; tests/fidelity/test_dbr_untrained_flight.py
sets this toolkit's initial policy beside it).

ML-Agents logs the policy's entropy as the sum over its action distributions (ActionModel: the Gaussian's entropy
averaged over the continuous dimensions, plus each discrete branch's), and a masked option's probability is
zeroed, so a branch whose every other option is masked adds nothing. Drone-Based Reforestation's first training
point (6,000 agent-steps, before the first update of a 8,192 buffer) is the initial policy: a unit Gaussian,
0.5 ln(2 pi e) = 1.418939, and a uniform drop branch {do nothing, drop}, ln 2 where a drop is available. So the
first point's excess over 1.418939 is ln 2 times the share of decisions on which a drop was available.
"""

from __future__ import annotations

import math

import pytest

from hivex_dsl.evaluation.original.curves import original_curves

ENV = "drone_based_reforestation"
UNIT_GAUSSIAN = 0.5 * math.log(2 * math.pi * math.e)
SEEDED_PAGES = {0: "main", 3: "Drop Seed"}  # the configs' task indices whose drones start with a seed
SEEDLESS_PAGES = (1, 2, 4, 5, 6)


def first(page: int, level: int, panel: str) -> float:
    """The original's first training point of ``panel`` (the three runs agree there: one initial policy)."""
    curve = original_curves(ENV, page, level).panel(panel).training
    assert curve.lower[0] == pytest.approx(curve.upper[0], abs=2e-5)
    return float(curve.lower[0])


@pytest.mark.parametrize("level", [1, 5, 10])
def test_a_drone_without_a_seed_has_no_drop_to_choose(level):
    """Where no drone holds a seed the first point is the unit Gaussian's entropy to the page's resolution: the
    drop branch is masked without a seed (it adds nothing), not a no-op that the policy samples half the time."""
    for page in SEEDLESS_PAGES:
        assert first(page, level, "Entropy") == pytest.approx(UNIT_GAUSSIAN, abs=2e-5), page


@pytest.mark.parametrize("level", [1, 5, 10])
def test_a_seed_holder_can_drop_on_only_a_few_decisions_of_an_episode(level):
    """Where drones start with a seed the excess is small: a drop was available on 0.56% of the main task's
    decisions and 1.16% of Drop Seed's, about 2.0 and 2.8 decisions a drone-episode (Episode Length 354 and 239),
    2.4 and 4.4 a drop (0.81 and 0.63 drops). Holding a seed alone would make it available from the first decision
    until the drop; a uniform branch drops within about 2 available decisions, on the pad. So the original masked
    the drop on most decisions of a seed holder too (where it was available its untrained drones dropped about 20 m
    from the station after a path of about 30 m: Cumulative Distance Until Tree Drop 24.2 over 0.81 drops). The
    first points are the same at every terrain level (one initial policy, the same spawns): the mask does not read
    the terrain."""
    decisions = {}
    for page in SEEDED_PAGES:
        share = (first(page, level, "Entropy") - UNIT_GAUSSIAN) / math.log(2)
        length, drops = first(page, level, "Episode Length"), first(page, level, "Tree Drop Count")
        decisions[page] = share * length
        assert 0.004 < share < 0.013, (page, share)
        assert 1.5 < decisions[page] < 3.0 and 2.0 < decisions[page] / drops < 5.0, (page, decisions[page], drops)
        for panel in ("Entropy", "Tree Drop Count", "Recharge Energy Count", "Episode Length"):
            assert first(page, level, panel) == pytest.approx(first(page, 1, panel), rel=1e-5), (page, panel)
    assert decisions[0] == pytest.approx(2.0, abs=0.1) and decisions[3] == pytest.approx(2.8, abs=0.1)
