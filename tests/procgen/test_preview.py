"""The sample figures tile the generators' output the way their captions say."""

from __future__ import annotations

import numpy as np
import pytest

from hivex_dsl.sim.procgen.preview import SEA, pollution_figure, resample, terrain_figure, tile


def test_tile_places_images_row_by_row_with_gaps():
    red, blue = np.zeros((2, 3, 3), np.uint8), np.zeros((2, 3, 3), np.uint8)
    red[..., 0], blue[..., 2] = 255, 255
    sheet = tile([red, blue, red], columns=2, gap=1)
    assert sheet.shape == (1 + 2 * 3, 1 + 2 * 4, 3)
    assert tuple(sheet[1, 1]) == (255, 0, 0) and tuple(sheet[1, 5]) == (0, 0, 255) and tuple(sheet[4, 1]) == (255, 0, 0)
    assert tuple(sheet[4, 5]) == (255, 255, 255) and tuple(sheet[0, 0]) == (255, 255, 255)
    with pytest.raises(ValueError):
        tile([red, np.zeros((3, 3, 3), np.uint8)], columns=2)


def test_resample_puts_high_y_rows_at_the_top():
    field = np.arange(4.0).reshape(2, 2)  # row 1 is y high
    view = resample(field, 2)
    np.testing.assert_array_equal(view, [[2.0, 3.0], [0.0, 1.0]])


def test_terrain_figure_has_sea_borders_and_one_tile_per_level_and_seed():
    sheet = terrain_figure(levels=(1, 10), seeds=(0, 1, 2), size_px=40)
    assert sheet.shape == (2 + 2 * 42, 2 + 3 * 42, 3)
    corner = sheet[2:42, 2:42][0, 0]
    np.testing.assert_array_equal(corner, SEA)


def test_pollution_figure_grid():
    sheet = pollution_figure(seeds=(0, 1), size_px=50)
    assert sheet.shape == (4 + 1 * 54, 4 + 5 * 54, 3)
