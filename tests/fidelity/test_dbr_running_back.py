"""Incremental Running Back's d_init against the original's Drop Seed record (issue 52; the reward table's note
"Incremental Running Back's d_init").

The paper's r_rb = r_p * rbm / (d_init - d_charge / s) names d_0 "in incremental steps" and d_init "the initial
distance to the drone station". Drop Seed's drones drop about one seed each and fly home, the return ending the
episode and paying its 100, so every increment between the drop and the station is paid there: what its published
return leaves beside the drops and the 100 is the whole run back (less a little energy). This toolkit read d_init
as the drop's increment until issue 52, so a run home paid the whole r_p * rbm (3.4-3.7 at the published drop
rewards); the published cells leave 1.0-1.2, what d_init in metres pays.
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest

import hivex_dsl
from hivex_dsl.evaluation.published import cell

ENV = "drone_based_reforestation"
DROP_SEED = 4  # the published results' key of the original's Drop Seed (this toolkit's task 4)


def run_home(distance_m: float, rbm: float) -> float:
    """Incremental Running Back paid to a drone that drops a seed ``distance_m`` from the station (flat ground, 2 m
    up, the drop's multiplier set to ``rbm``) and flies straight home at full throttle, until it is docked."""
    compiled = hivex_dsl.compile({"hivex": 1, "environment": ENV, "task": "drop_seed", "agents": 1})
    sim = compiled.entry.make_simulator(compiled)
    state = sim.reset(np.random.default_rng(0), 1)
    flat = np.zeros_like(state.heights)
    state = replace(state, heights=flat, station=np.zeros((1, 3)), position=np.array([[[distance_m, 0.0, 2.0]]]),
                    heading=np.full((1, 1), np.pi), ground=np.zeros((1, 1)), inside=np.zeros((1, 1), bool),
                    away=np.ones((1, 1), bool), holding=np.ones((1, 1), bool))
    drop = {"continuous": np.zeros((1, 1, 3), np.float32), "discrete": np.ones((1, 1, 1), np.int64)}
    home = {"continuous": np.array([[[1.0, 0.0, 0.0]]], np.float32), "discrete": np.zeros((1, 1, 1), np.int64)}
    state, _ = sim.step(state, drop, np.random.default_rng(0))
    assert state.dropped[0, 0] and state.back_active[0, 0]
    state = replace(state, back_multiplier=np.full((1, 1), rbm))
    paid, term = 0.0, compiled.entry.terms["incremental_running_back"]
    while not state.inside[0, 0]:
        prev = state
        state, _ = sim.step(state, home, np.random.default_rng(0))
        paid += float(term(prev, state, home, compiled.params)[0, 0])
    return paid


@pytest.mark.parametrize("level", range(1, 11))
def test_drop_seed_s_published_return_leaves_what_d_init_in_metres_pays_for_the_run_home(level):
    published = cell(ENV, DROP_SEED, level)
    stat = lambda name: published.statistic(name)[0]  # noqa: E731 (mean of a logged statistic)
    drops = stat("Tree Drop Count")
    drop_rewards = stat("Cumulative Tree Drop Reward") + stat("Cumulative Distance Reward")
    left = published.return_mean - drop_rewards - 100.0 * drops  # the runs home, less the battery's 0.2-0.3
    # the mean drop: its station distance (r_d / 10 is sdd / 200) and its running-back multiplier (r_s + r_d) / 30
    distance_m = stat("Cumulative Normalized Distance Until Tree Drop") / drops * 200.0
    rbm = drop_rewards / drops / 30.0
    paid = run_home(distance_m, rbm) * drops
    assert 0.9 < left < 1.3
    assert paid == pytest.approx(left, abs=0.3)
    assert 20.0 * rbm * drops > left + 2.0  # the whole r_p * rbm a run home, d_init read as an increment
