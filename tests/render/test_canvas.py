"""Tests for hivex_dsl.sim.render.canvas.

Most tests use a 20 x 20 px canvas over [-10, 10]^2 m, i.e. exactly 1 px per metre, so the pixel in
row r, column c has its centre at world x = c - 9.5, y = 9.5 - r.
"""

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from hivex_dsl.sim.render.canvas import VIRIDIS_STOPS, Canvas, colormap, hue_wheel, upscale

WHITE = np.array([255, 255, 255], dtype=np.uint8)
RED = np.array([255, 0, 0], dtype=np.uint8)
BLUE = np.array([0, 0, 255], dtype=np.uint8)


def unit_canvas() -> Canvas:
    return Canvas(20, 10.0)


def painted(canvas: Canvas, background=WHITE) -> np.ndarray:
    """(H, W) bool: pixels that differ from the background."""
    return np.any(canvas.pixels != background, axis=-1)


def world_of(row: int, col: int) -> tuple[float, float]:
    """World centre of a pixel on the unit canvas."""
    return col - 9.5, 9.5 - row


# ----------------------------------------------------------------------------- coordinates
def test_to_pixel_maps_corners_and_origin():
    canvas = Canvas(40, 5.0)
    got = canvas.to_pixel(np.array([[-5.0, 5.0], [5.0, -5.0], [0.0, 0.0], [5.0, 5.0]]))
    np.testing.assert_allclose(got, [[0, 0], [40, 40], [20, 20], [40, 0]])


def test_pixel_centres_are_cached_and_consistent_with_to_pixel():
    canvas = unit_canvas()
    x, y = canvas.pixel_centres()
    assert x.shape == y.shape == (20, 20)
    assert canvas.pixel_centres()[0] is x
    assert (x[0, 0], y[0, 0]) == world_of(0, 0)
    assert (x[19, 19], y[19, 19]) == world_of(19, 19)
    assert np.all(np.diff(x, axis=1) > 0) and np.all(np.diff(y, axis=0) < 0)  # +x right, +y up
    cols_rows = canvas.to_pixel(np.stack([x.ravel(), y.ravel()], axis=1))
    rows, cols = np.divmod(np.arange(400), 20)
    np.testing.assert_allclose(cols_rows, np.stack([cols + 0.5, rows + 0.5], axis=1))


def test_background_and_image_is_a_copy():
    canvas = Canvas(8, 1.0, background=(10, 20, 30))
    image = canvas.image()
    assert image.shape == (8, 8, 3) and image.dtype == np.uint8
    assert np.all(image == [10, 20, 30])
    image[0, 0] = 0
    assert np.all(canvas.pixels[0, 0] == [10, 20, 30])


# ----------------------------------------------------------------------------- disks
def test_disk_at_origin_paints_exactly_the_pixels_within_its_radius():
    canvas = unit_canvas()
    canvas.disks(np.array([[0.0, 0.0]]), 3.0, RED)
    x, y = canvas.pixel_centres()
    expected = np.hypot(x, y) <= 3.0
    np.testing.assert_array_equal(painted(canvas), expected)
    assert np.all(canvas.pixels[9:11, 9:11] == RED)  # the four pixels around the origin
    assert np.all(canvas.pixels[9, 15] == WHITE)     # x = 5.5 m, outside the radius


def test_disk_mask_is_symmetric():
    canvas = unit_canvas()
    canvas.disks(np.array([[0.0, 0.0]]), 6.3, BLUE)
    mask = painted(canvas)
    np.testing.assert_array_equal(mask, mask[::-1])
    np.testing.assert_array_equal(mask, mask[:, ::-1])
    np.testing.assert_array_equal(mask, mask.T)


def test_positive_y_is_up():
    canvas = unit_canvas()
    canvas.disks(np.array([[0.0, 5.0]]), 2.0, RED)
    rows = np.nonzero(painted(canvas))[0]
    assert rows.size > 0 and rows.max() < 10


def test_later_disks_paint_over_earlier_ones():
    canvas = unit_canvas()
    centres = np.array([[-1.0, 0.0], [1.0, 0.0]] + [[5.0, 5.0]] * 6)
    colors = np.array([RED, BLUE] + [[k, k, 0] for k in range(10, 70, 10)])
    canvas.disks(centres, 2.0, colors)
    assert np.all(canvas.pixels[9, 9] == BLUE)   # x = -0.5: inside both, the second wins
    assert np.all(canvas.pixels[9, 7] == RED)    # x = -2.5: only inside the first
    assert np.all(canvas.pixels[4, 14] == [60, 60, 0])  # six disks at one spot: the last wins


def test_sub_pixel_disk_paints_the_pixel_containing_its_centre():
    canvas = unit_canvas()
    canvas.disks(np.array([[0.3, 0.3]]), 0.01, RED)
    mask = painted(canvas)
    assert mask.sum() == 1 and mask[9, 10]   # col floor(10.3) = 10, row floor(9.7) = 9


def test_per_disk_radii_and_off_canvas_disks():
    canvas = unit_canvas()
    canvas.disks(np.array([[-5.0, 0.0], [5.0, 0.0], [50.0, 50.0]]), np.array([1.0, 3.0, 4.0]), RED)
    mask = painted(canvas)
    assert mask[:, :10].sum() < mask[:, 10:].sum()
    canvas.disks(np.array([[10.0, 0.0]]), 2.0, BLUE)   # half outside the right edge
    assert np.all(canvas.pixels[9, 19] == BLUE)


def test_empty_inputs_are_a_no_op():
    canvas = unit_canvas()
    canvas.disks(np.zeros((0, 2)), 1.0, RED)
    canvas.segments(np.zeros((0, 2)), np.zeros((0, 2)), 2.0, RED)
    canvas.arrows(np.zeros((0, 2)), np.zeros((0, 2)), 2.0, RED)
    assert not painted(canvas).any()


@settings(max_examples=40, deadline=None)
@given(cx=st.floats(-9.0, 9.0), cy=st.floats(-9.0, 9.0), radius=st.floats(0.0, 5.0))
def test_disk_pixels_stay_within_radius_plus_half_a_pixel_diagonal(cx, cy, radius):
    canvas = unit_canvas()
    canvas.disks(np.array([[cx, cy]]), radius, RED)
    x, y = canvas.pixel_centres()
    distance = np.hypot(x - cx, y - cy)
    mask = painted(canvas)
    assert np.all(distance[mask] <= max(radius, np.sqrt(0.5)) + 1e-9)
    assert np.all(mask[distance <= radius])
    assert mask[int(np.floor(10.0 - cy)), int(np.floor(cx + 10.0))]  # the pixel holding the centre


# ----------------------------------------------------------------------------- rings
def test_ring_paints_the_circle_but_not_the_centre():
    canvas = unit_canvas()
    canvas.rings(np.array([[0.0, 0.0]]), 6.0, 1.5, RED)
    x, y = canvas.pixel_centres()
    expected = np.abs(np.hypot(x, y) - 6.0) <= 0.75
    np.testing.assert_array_equal(painted(canvas), expected)
    assert not painted(canvas)[9:11, 9:11].any()


# ----------------------------------------------------------------------------- segments and arrows
def test_horizontal_segment_paints_its_row_only():
    canvas = unit_canvas()
    canvas.segments(np.array([[-5.0, 0.5]]), np.array([[5.0, 0.5]]), 1.0, RED)  # y = 0.5 is row 9
    mask = painted(canvas)
    assert np.all(mask[9, 5:15])      # x centres -4.5 .. 4.5
    assert not mask[9, :4].any() and not mask[9, 16:].any()
    assert not mask[:9].any() and not mask[10:].any()


def test_thick_segment_width_is_in_pixels():
    canvas = Canvas(40, 10.0)  # 2 px per metre: width 5 px = 2.5 m
    canvas.segments(np.array([[-5.0, 0.0]]), np.array([[5.0, 0.0]]), 5.0, RED)
    x, y = canvas.pixel_centres()
    column = painted(canvas)[:, 20]
    np.testing.assert_array_equal(column, np.abs(y[:, 20]) <= 1.25)


def test_diagonal_segment_is_symmetric_about_the_diagonal():
    canvas = unit_canvas()
    canvas.segments(np.array([[-6.0, 6.0]]), np.array([[6.0, -6.0]]), 2.0, RED)
    mask = painted(canvas)
    np.testing.assert_array_equal(mask, mask.T)
    assert mask[3, 3] and mask[16, 16] and not mask[3, 16]


def test_arrow_head_is_at_the_tip_and_mirror_symmetric():
    canvas = unit_canvas()
    canvas.arrows(np.array([[-6.0, 0.5]]), np.array([[10.0, 0.0]]), 1.0, RED)  # tip at x = 4
    mask = painted(canvas)
    assert np.all(mask[9, 4:14])                  # the shaft along row 9
    head_rows, head_cols = np.nonzero(np.delete(mask, 9, axis=0))
    assert head_rows.size > 0
    head_x = head_cols - 9.5
    assert head_x.min() > -1.0 and head_x.max() <= 4.0  # head strokes lie behind the tip, near it
    np.testing.assert_array_equal(mask[8::-1][:9], mask[10:19])  # mirror about row 9


def test_reversed_arrow_is_the_mirror_image():
    right, left = unit_canvas(), unit_canvas()
    right.arrows(np.array([[-4.5, 0.5]]), np.array([[8.0, 0.0]]), 1.0, RED)
    left.arrows(np.array([[4.5, 0.5]]), np.array([[-8.0, 0.0]]), 1.0, RED)
    np.testing.assert_array_equal(painted(right), painted(left)[:, ::-1])


def test_arrow_grid_draws_every_arrow():
    canvas = Canvas(96, 12.0)
    g = np.linspace(-10.0, 10.0, 6)
    gx, gy = np.meshgrid(g, g)
    tails = np.stack([gx.ravel(), gy.ravel()], axis=1)
    canvas.arrows(tails, np.tile([[1.5, 0.0]], (36, 1)), 1.5, np.full((36, 3), 40))
    centres = canvas.to_pixel(tails + [0.75, 0.0]).astype(int)  # shaft midpoints
    assert np.all(canvas.pixels[centres[:, 1], centres[:, 0]] == 40)


# ----------------------------------------------------------------------------- rectangles and fill
def test_rectangle_paints_pixels_whose_centres_are_inside():
    canvas = unit_canvas()
    canvas.rectangles(np.array([[-2.0, 1.0]]), np.array([[3.0, 4.0]]), BLUE)
    x, y = canvas.pixel_centres()
    expected = (x >= -2) & (x <= 3) & (y >= 1) & (y <= 4)
    np.testing.assert_array_equal(painted(canvas), expected)
    assert painted(canvas)[:10].any() and not painted(canvas)[10:].any()


def test_tiny_rectangle_paints_one_pixel():
    canvas = unit_canvas()
    canvas.rectangles(np.array([[2.1, -3.9]]), np.array([[2.2, -3.8]]), RED)
    mask = painted(canvas)
    assert mask.sum() == 1 and mask[13, 12]  # x = 2.15 -> col 12, y = -3.85 -> row 13


def test_fill_replaces_the_whole_picture():
    canvas = Canvas(4, 1.0)
    field = np.arange(48, dtype=np.uint8).reshape(4, 4, 3)
    canvas.fill(field)
    np.testing.assert_array_equal(canvas.image(), field)


# ----------------------------------------------------------------------------- bad arguments
@pytest.mark.parametrize(
    "draw",
    [
        lambda c: c.disks(np.array([0.0, 0.0]), 1.0, RED),                     # (2,) not (N, 2)
        lambda c: c.disks(np.array([[np.nan, 0.0]]), 1.0, RED),
        lambda c: c.disks(np.zeros((2, 2)), -1.0, RED),
        lambda c: c.disks(np.zeros((2, 2)), np.ones(3), RED),
        lambda c: c.disks(np.zeros((2, 2)), 1.0, np.zeros((3, 3))),
        lambda c: c.disks(np.zeros((1, 2)), 1.0, (300, 0, 0)),
        lambda c: c.rings(np.zeros((1, 2)), 1.0, 0.0, RED),
        lambda c: c.segments(np.zeros((2, 2)), np.zeros((3, 2)), 1.0, RED),
        lambda c: c.segments(np.zeros((1, 2)), np.ones((1, 2)), -2.0, RED),
        lambda c: c.arrows(np.zeros((1, 2)), np.ones((1, 2)), 1.0, RED, head_frac=2.0),
        lambda c: c.rectangles(np.ones((1, 2)), np.zeros((1, 2)), RED),
        lambda c: c.fill(np.zeros((3, 3, 3), dtype=np.uint8)),
        lambda c: c.to_pixel(np.zeros((2, 3))),
    ],
)
def test_bad_drawing_arguments_raise_value_error(draw):
    with pytest.raises(ValueError):
        draw(unit_canvas())


@pytest.mark.parametrize("size, extent", [(0, 1.0), (2.5, 1.0), (True, 1.0), (10, 0.0), (10, float("inf"))])
def test_bad_canvas_arguments_raise_value_error(size, extent):
    with pytest.raises(ValueError):
        Canvas(size, extent)


# ----------------------------------------------------------------------------- colormap
def luminance(rgb: np.ndarray) -> np.ndarray:
    return rgb.astype(float) @ np.array([0.2126, 0.7152, 0.0722])


def test_default_stops_run_dark_blue_to_yellow():
    assert 5 <= len(VIRIDIS_STOPS) <= 8
    first, last = VIRIDIS_STOPS[0].astype(int), VIRIDIS_STOPS[-1].astype(int)
    assert first[2] > first[1] and luminance(VIRIDIS_STOPS[0]) < 40
    assert last[0] > 200 and last[1] > 200 and last[2] < 100


def test_colormap_endpoints_and_clipping():
    out = colormap(np.array([-3.0, 0.0, 1.0, 7.0]))
    np.testing.assert_array_equal(out, VIRIDIS_STOPS[[0, 0, -1, -1]])
    ranged = colormap(np.array([10.0, 20.0]), low=10.0, high=20.0)
    np.testing.assert_array_equal(ranged, VIRIDIS_STOPS[[0, -1]])


def test_colormap_interpolates_custom_stops_linearly():
    stops = np.array([[0, 0, 0], [200, 100, 40]])
    np.testing.assert_array_equal(colormap(np.array([0.25, 0.5]), stops=stops), [[50, 25, 10], [100, 50, 20]])


def test_colormap_default_luminance_is_monotone_and_shape_is_kept():
    ramp = colormap(np.linspace(0.0, 1.0, 1001))
    assert np.all(np.diff(luminance(ramp)) >= -1.0)  # allowing for uint8 rounding
    assert luminance(ramp[-1]) - luminance(ramp[0]) > 150
    assert colormap(np.zeros((2, 3, 4))).shape == (2, 3, 4, 3)
    assert colormap(np.zeros((2, 3))).dtype == np.uint8


def test_colormap_bad_arguments():
    with pytest.raises(ValueError):
        colormap(np.zeros(3), low=1.0, high=1.0)
    with pytest.raises(ValueError):
        colormap(np.zeros(3), stops=np.zeros((1, 3)))
    with pytest.raises(ValueError):
        colormap(np.zeros(3), stops=np.zeros((4, 2)))


# ----------------------------------------------------------------------------- hue wheel
def test_hue_wheel_is_periodic_and_pastel():
    angles = np.linspace(-np.pi, np.pi, 50)
    np.testing.assert_array_equal(hue_wheel(angles), hue_wheel(angles + 2.0 * np.pi))
    np.testing.assert_array_equal(hue_wheel(np.array(0.0)), hue_wheel(np.array(2.0 * np.pi)))
    colours = hue_wheel(np.linspace(0.0, 2.0 * np.pi, 97))
    assert colours.min() >= int(255 * 0.95 * 0.65) and colours.max() <= round(255 * 0.95)


def test_hue_wheel_primary_directions_and_grey():
    rgb = hue_wheel(np.array([0.0, 2.0 * np.pi / 3.0, 4.0 * np.pi / 3.0]), saturation=1.0, value=1.0)
    np.testing.assert_array_equal(rgb, [[255, 0, 0], [0, 255, 0], [0, 0, 255]])
    grey = hue_wheel(np.linspace(0.0, 6.0, 7), saturation=0.0, value=0.5)
    assert np.all(grey == 128)
    assert hue_wheel(np.zeros((4, 5))).shape == (4, 5, 3)


def test_hue_wheel_bad_arguments():
    with pytest.raises(ValueError):
        hue_wheel(np.zeros(2), saturation=1.5)
    with pytest.raises(ValueError):
        hue_wheel(np.array([np.inf]))


# ----------------------------------------------------------------------------- upscale
def test_upscale_repeats_each_pixel_in_a_block():
    image = np.arange(2 * 3 * 3, dtype=np.uint8).reshape(2, 3, 3)
    big = upscale(image, 4)
    assert big.shape == (8, 12, 3) and big.dtype == np.uint8
    np.testing.assert_array_equal(big[4:8, 8:12], np.broadcast_to(image[1, 2], (4, 4, 3)))
    np.testing.assert_array_equal(big[::4, ::4], image)
    np.testing.assert_array_equal(upscale(image, 1), image)


@pytest.mark.parametrize("factor", [0, -2, 2.0, True])
def test_upscale_bad_factor(factor):
    with pytest.raises(ValueError):
        upscale(np.zeros((2, 2, 3), dtype=np.uint8), factor)


def test_upscale_bad_shape():
    with pytest.raises(ValueError):
        upscale(np.zeros((2, 2), dtype=np.uint8), 2)
