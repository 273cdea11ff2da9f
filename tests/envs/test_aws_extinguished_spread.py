"""params.extinguished_spread wires the release's doused trees into Aerial Wildfire Suppression's drops.

The release's drop wets the burning trees under its swath but never touches the fire's burning list, which is what
spreads (tests/fire/test_fire_doused_spread.py works the engine's rule by hand). Here a plane holding water drops
straight onto the burning trees of a real world: the trees it extinguishes leave the burning list either way, and
only under the release's rule do they go on in the fire's doused list, so the world's fire goes on.
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest

import hivex_dsl
from hivex_dsl.envs.aerial_wildfire_suppression.simulator import AerialWildfireSimulator
from hivex_dsl.sim.fire import TreeState


def drop_on_the_fire(spreading: bool):
    compiled = hivex_dsl.compile({"hivex": 1, "environment": "aerial_wildfire_suppression", "agents": 1,
                                  "params": {"extinguished_spread": spreading, "terrain_cast": "step"}})
    sim = AerialWildfireSimulator(compiled)
    state = sim.reset(np.random.default_rng(3), 1)
    cells, cell_m = sim.forest_spec.cells, sim.forest_spec.spacing_m
    half = compiled.params.island_half_extent_m
    row, col = np.divmod(int(state.fire.burning[0]), cells)
    over = np.array([[[-half + (col + 0.5) * cell_m, -half + (row + 0.5) * cell_m]]])
    state = replace(state, position=over, cast_at=over.copy(), heading=np.zeros((1, 1)), water=np.ones((1, 1), bool),
                    flying=np.ones((1, 1), bool))
    burning_before = state.fire.burning.size
    drop = {"continuous": np.zeros((1, 1, 1), np.float32), "discrete": np.ones((1, 1, 1), np.int64)}
    after, _ = sim.step(state, drop, np.random.default_rng(0))
    return after, burning_before


@pytest.mark.parametrize("spreading", [False, True])
def test_extinguished_trees_leave_the_burning_list_and_go_on_spreading_only_under_the_release_rule(spreading):
    after, burning_before = drop_on_the_fire(spreading)
    extinguished = int(after.extinguished.sum())
    assert extinguished > 0 and after.fire.burning.size == burning_before - extinguished
    doused = after.fire.doused
    assert doused.size == (extinguished if spreading else 0)
    assert (after.fire.trees.reshape(-1)[doused] == TreeState.WET).all()
