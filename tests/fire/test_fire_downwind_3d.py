"""The downwind factor read in 3-D (FireSpec.downwind_angle '3d'): the release's BurnNNeighbourIndexes takes
Vector3.Angle between the tried tree's offset, heights included, and the level wind, so a target below or above
the burning tree by more than its distance on the map is never downwind. Worked by hand on a 3 m grid."""

from __future__ import annotations

import numpy as np
import pytest

from hivex_dsl.sim.fire import FireSpec, TreeState, fire_reset, fire_step

EAST = 0.0  # the wind blows to +col
# downwind is the only factor a try can have here (cool, damp, overcast; targets lower than the fire), and it makes
# the try certain
SURE = FireSpec(spread_chance_per_factor=1.0, spread_radius_cells=1, downwind_cone_deg=45.0)


def mild(world, row, col):
    return np.zeros(len(world)), np.ones(len(world)), np.ones(len(world))


def caught_east(drop_m: float, angle: str, wind: float = EAST) -> bool:
    """Whether the tree one cell (3 m) east of a lone fire, ``drop_m`` metres lower, catches in one fire step."""
    exists = np.zeros((1, 3, 3), bool)
    exists[0, 1, 1] = exists[0, 1, 2] = True
    ignite = np.zeros((1, 3, 3), bool)
    ignite[0, 1, 1] = True
    height = np.full((1, 3, 3), 50.0, np.float32)
    height[0, 1, 2] -= drop_m
    spec = SURE.model_copy(update={"downwind_angle": angle})
    fire = fire_step(fire_reset(exists, ignite), np.random.default_rng(0), spec, np.array([wind]), height, mild, 3.0)
    return bool(fire.trees[0, 1, 2] == TreeState.BURNING)


@pytest.mark.parametrize("drop_m, caught", [(0.0, True), (2.0, True), (2.9, True), (3.1, False), (4.0, False)])
def test_a_target_down_the_slope_is_downwind_while_the_slope_is_under_45_degrees(drop_m, caught):
    assert caught_east(drop_m, "3d") is caught  # atan(drop / 3 m) < 45 degrees
    assert caught_east(drop_m, "horizontal") is True  # on the map it lies straight downwind


def test_the_map_angle_and_the_slope_add_up():
    # wind 30 degrees off the target's bearing: cos(angle) = cos(30) x 3 / sqrt(9 + d^2) >= cos(45) while d <= 2.12 m
    off = np.radians(30.0)
    assert caught_east(1.9, "3d", off) and not caught_east(2.2, "3d", off)
    assert caught_east(2.2, "horizontal", off)


def test_3d_needs_the_cell_size():
    spec = SURE.model_copy(update={"downwind_angle": "3d"})
    exists = np.ones((1, 3, 3), bool)
    ignite = np.zeros((1, 3, 3), bool)
    ignite[0, 1, 1] = True
    height = np.arange(9, dtype=np.float32).reshape(1, 3, 3)
    with pytest.raises(ValueError, match="cell_m"):
        fire_step(fire_reset(exists, ignite), np.random.default_rng(0), spec, np.array([EAST]), height, mild)
