"""Facts about the island height maps of ``hivex_dsl.sim.procgen.terrain`` (ENVIRONMENTS.md, AWS: Terrain)."""

from __future__ import annotations

from functools import lru_cache

import numpy as np
import pytest

from hivex_dsl.sim.procgen.noise import draw_lattice, fractal2d
from hivex_dsl.sim.procgen.terrain import (
    Terrain,
    TerrainSpec,
    generate_terrain,
    height_multiplier_for_level,
    load_terrain_preset,
    terrain_spec_for_level,
)

# round(8 + (level - 1) * 22 / 9) worked by hand: 8, 10.44, 12.89, 15.33, 17.78, 20.22, 22.67, 25.11, 27.56, 30
HAND_MULTIPLIERS = [8, 10, 13, 15, 18, 20, 23, 25, 28, 30]


@lru_cache(maxsize=None)
def terrain(level: int, seed: int) -> Terrain:
    return generate_terrain(np.random.default_rng(seed), terrain_spec_for_level(level))


def grid(t: Terrain) -> tuple[np.ndarray, np.ndarray]:
    """(n, n) x and y of every cell, by the documented convention."""
    n = t.heights.shape[0]
    c = -t.extent_m / 2 + np.arange(n) * t.extent_m / (n - 1)
    return np.meshgrid(c, c)  # x varies along columns, y along rows


# --- level mapping and spec ---------------------------------------------------------------------


def test_level_multipliers_run_from_8_to_30_monotonically():
    multipliers = [height_multiplier_for_level(level) for level in range(1, 11)]
    assert multipliers[0] == 8 and multipliers[-1] == 30
    assert multipliers == HAND_MULTIPLIERS
    assert all(a < b for a, b in zip(multipliers, multipliers[1:]))
    assert terrain_spec_for_level(4).height_multiplier == 15


@pytest.mark.parametrize("level", [0, 11, -1, 1.0, "3", True])
def test_bad_levels_are_value_errors(level):
    with pytest.raises(ValueError, match="terrain level"):
        height_multiplier_for_level(level)


def test_spec_rejects_bad_values():
    with pytest.raises(ValueError, match="half the extent"):
        TerrainSpec(village_half_range_m=800.0)
    with pytest.raises(ValueError):
        TerrainSpec(size="241")  # strict: no coercion
    with pytest.raises(ValueError):
        TerrainSpec(octaves=0)
    with pytest.raises(ValueError, match="height_multiplier"):
        terrain_spec_for_level(3, height_multiplier=5)
    with pytest.raises(ValueError, match="rng"):
        generate_terrain(0, TerrainSpec())


def test_preset_matches_the_code():
    preset = load_terrain_preset()
    assert preset.defaults == TerrainSpec()
    assert preset.level_height_multipliers == [height_multiplier_for_level(level) for level in range(1, 11)]


# --- generated maps -----------------------------------------------------------------------------


def test_same_seed_is_identical_and_different_seeds_differ():
    a, b = terrain(5, 0), generate_terrain(np.random.default_rng(0), terrain_spec_for_level(5))
    assert a is not b
    np.testing.assert_array_equal(a.heights, b.heights)
    np.testing.assert_array_equal(a.village, b.village)
    c = terrain(5, 1)
    assert not np.array_equal(a.heights, c.heights)
    assert a.heights.shape == (241, 241) and a.heights.dtype == np.float64
    assert a.cell_m == pytest.approx(1666.0 / 240) and a.extent_m == 1666.0
    assert not a.heights.flags.writeable


def test_heights_are_finite_and_clamped_to_sea_level_zero():
    for seed in range(4):
        heights = terrain(10, seed).heights
        assert np.isfinite(heights).all()
        assert heights.min() == 0.0  # clamped: below-sea values become exactly 0 = sea level
        assert (heights > 0).any()


@pytest.mark.parametrize("level", [1, 10])
def test_whole_border_ring_is_sea(level):
    for seed in range(20):
        h = terrain(level, seed).heights
        ring = np.concatenate([h[0], h[-1], h[:, 0], h[:, -1]])
        assert np.all(ring <= 0.0), (level, seed)


def test_peaks_rise_with_level_and_match_the_reported_heights():
    peaks = [np.mean([terrain(level, seed).heights.max() for seed in range(8)]) for level in range(1, 11)]
    assert all(a < b for a, b in zip(peaks, peaks[1:])), peaks
    assert 56.0 / 1.6 <= peaks[0] <= 56.0 * 1.6
    assert 210.0 / 1.6 <= peaks[-1] <= 210.0 * 1.6


def recipe_height_value(t: Terrain, seed: int) -> tuple[np.ndarray, np.ndarray]:
    """(n, n) the recipe's height value t = clip(noise normalised over the map - falloff, 0, 1), recomputed with the
    same noise draws (rng: lattice first), and (n, n) bool the cells more than 100 m from the village."""
    perm, grads = draw_lattice(np.random.default_rng(seed), 1, 256)
    cols, rows = np.meshgrid(np.arange(241) / 40.0, np.arange(241) / 40.0)
    noise = fractal2d(perm, grads, cols[None], rows[None], 4, 0.3, 2.2)[0]
    x, y = grid(t)
    v = np.maximum(np.abs(x), np.abs(y)) / 833.0
    falloff = v**5 / (v**5 + (2.5 - 2.5 * v) ** 5)
    local = (noise - noise.min()) / (noise.max() - noise.min())
    far = np.hypot(x - t.village[0], y - t.village[1]) > 100.0 + 1e-6
    return np.clip(local - falloff, 0, 1), far


def test_heights_follow_the_documented_recipe_away_from_the_village():
    """Recomputed from ENVIRONMENTS.md's recipe: t^2 x multiplier 13 (level 3) x 7 m."""
    t = terrain(3, 0)
    value, far = recipe_height_value(t, 0)
    np.testing.assert_allclose(t.heights[far], (value**2 * 13 * 7.0)[far], rtol=1e-12, atol=1e-12)


@pytest.mark.parametrize("level", [1, 10])
def test_village_in_range_on_land_and_flat(level):
    for seed in range(6):
        t = terrain(level, seed)
        assert np.all(np.abs(t.village) <= 450.0)
        assert t.height_at(t.village) > 0.0
        x, y = grid(t)
        near = np.hypot(x - t.village[0], y - t.village[1]) <= 60.0
        assert near.sum() > 100 and np.ptp(t.heights[near]) < 1.0
        angles = np.linspace(0, 2 * np.pi, 16)
        ring = t.village + (60.0 - t.cell_m * np.sqrt(2)) * np.stack([np.cos(angles), np.sin(angles)], -1)
        assert np.ptp(t.height_at(ring)) < 1.0


def test_village_falls_back_to_the_highest_cell_in_range():
    # b tiny: the falloff is ~1 everywhere except the very centre, so one random try misses land
    spec = TerrainSpec(falloff_b=0.01, village_tries=1, height_multiplier=30)
    t = generate_terrain(np.random.default_rng(3), spec)
    j, i = np.rint((t.village + t.extent_m / 2) / t.cell_m).astype(int)
    np.testing.assert_allclose(t.village, -833.0 + np.array([j, i]) * t.cell_m, atol=1e-9)  # a cell centre
    assert t.heights[i, j] == t.heights.max() > 0.0


# --- interpolation on hand-built maps -----------------------------------------------------------


def small() -> Terrain:
    heights = np.array([[0.0, 1.0, 2.0], [4.0, 8.0, 0.0], [1.0, 1.0, 1.0]])  # x, y in {-1, 0, 1}
    return Terrain(heights=heights, cell_m=1.0, extent_m=2.0, village=np.zeros(2))


def test_height_at_reproduces_the_grid_and_is_bilinear_between_cells():
    t = small()
    xs, ys = np.meshgrid([-1.0, 0.0, 1.0], [-1.0, 0.0, 1.0])
    np.testing.assert_array_equal(t.height_at(np.stack([xs, ys], -1)), t.heights)
    assert t.height_at(np.array([-0.5, -1.0])) == pytest.approx(0.5)
    assert t.height_at(np.array([-0.5, -0.5])) == pytest.approx((0 + 1 + 4 + 8) / 4)
    # x = -0.75, y = -0.25 in the cell with corners 0, 1 (y = -1) and 4, 8 (y = 0):
    # bottom 0 + 0.25 * 1 = 0.25, top 4 + 0.25 * 4 = 5, then 0.25 + 0.75 * (5 - 0.25) = 3.8125
    assert t.height_at(np.array([-0.75, -0.25])) == pytest.approx(3.8125)
    assert t.height_at(np.array([0.5, 0.5])) == pytest.approx((8 + 0 + 1 + 1) / 4)
    assert t.height_at(np.array([-5.0, -5.0])) == 0.0 and t.height_at(np.array([5.0, 0.0])) == 0.0


def test_height_at_is_continuous_across_cell_edges_and_keeps_leading_shape():
    t = small()
    for edge in ([0.0, -0.3], [0.4, 0.0], [0.0, 0.0]):
        e = np.array(edge)
        around = e + 1e-9 * np.array([[1, 0], [-1, 0], [0, 1], [0, -1]])
        np.testing.assert_allclose(t.height_at(around), t.height_at(e), atol=1e-7)
    assert t.height_at(np.zeros((3, 4, 2))).shape == (3, 4)
    with pytest.raises(ValueError, match=r"\(\.\.\., 2\)"):
        t.height_at(np.zeros((3, 3)))


def test_slope_of_a_plane_is_its_gradient():
    c = np.linspace(-2.0, 2.0, 9)
    x, y = np.meshgrid(c, c)
    plane = Terrain(heights=2 * x + 3 * y, cell_m=0.5, extent_m=4.0, village=np.zeros(2))
    points = np.random.default_rng(0).uniform(-2.0, 2.0, (50, 2))
    np.testing.assert_allclose(plane.slope_at(points), np.tile([2.0, 3.0], (50, 1)), atol=1e-12)
    np.testing.assert_allclose(plane.height_at(points), 2 * points[:, 0] + 3 * points[:, 1], atol=1e-12)


def test_slope_matches_central_differences_of_height_at():
    t = terrain(5, 0)
    points = np.random.default_rng(1).uniform(-500.0, 500.0, (200, 2))
    eps = 1e-4
    dx = (t.height_at(points + [eps, 0]) - t.height_at(points - [eps, 0])) / (2 * eps)
    dy = (t.height_at(points + [0, eps]) - t.height_at(points - [0, eps])) / (2 * eps)
    np.testing.assert_allclose(t.slope_at(points), np.stack([dx, dy], -1), atol=1e-5)


def test_terrain_rejects_inconsistent_arrays():
    with pytest.raises(ValueError, match="square"):
        Terrain(heights=np.zeros((3, 4)), cell_m=1.0, extent_m=2.0, village=np.zeros(2))
    with pytest.raises(ValueError, match="extent_m"):
        Terrain(heights=np.zeros((3, 3)), cell_m=1.0, extent_m=3.0, village=np.zeros(2))
    with pytest.raises(ValueError, match="village"):
        Terrain(heights=np.zeros((3, 3)), cell_m=1.0, extent_m=2.0, village=np.zeros(3))


# The release's assets (Aerial Wildfire Suppression's build; the reward table's note 'The release's terrain assets'):
# TerrainData 'Default Terrain' holds uniformScale 7 and meshHeightCurve's two keyframes (time, value, in and out
# slopes), and the mesh spans mapChunkSize 239 - 1 units of a noise map of 239 + 2 samples.
RELEASE_UNIFORM_SCALE = 7.0
RELEASE_CURVE_KEYS = ((0.0, 0.0, 0.0, 0.0), (1.0, 1.0, 2.0, 2.0))
RELEASE_MAP_CHUNK_SIZE = 239


def unity_curve(t: np.ndarray, keys=RELEASE_CURVE_KEYS) -> np.ndarray:
    """Unity's AnimationCurve between its two unweighted keys: the cubic Hermite of their values and slopes."""
    (t0, v0, _, out0), (t1, v1, in1, _) = keys
    span = t1 - t0
    s = (np.asarray(t, dtype=np.float64) - t0) / span
    h00, h10, h01, h11 = 2 * s**3 - 3 * s**2 + 1, s**3 - 2 * s**2 + s, -2 * s**3 + 3 * s**2, s**3 - s**2
    return h00 * v0 + h10 * span * out0 + h01 * v1 + h11 * span * in1


def test_the_release_s_curve_keys_make_the_height_curve_t_squared():
    t = np.linspace(0.0, 1.0, 101)
    np.testing.assert_allclose(unity_curve(t), t ** TerrainSpec().height_exponent, atol=1e-12)
    # a key's slope changed is another curve: the check reads the keys, not the exponent alone
    assert not np.allclose(unity_curve(t, ((0.0, 0.0, 0.0, 1.0), (1.0, 1.0, 1.0, 1.0))), t**2)


def test_the_map_is_the_release_s_mesh_scaled_by_its_uniform_scale():
    spec = TerrainSpec()
    assert spec.size == RELEASE_MAP_CHUNK_SIZE + 2
    assert spec.extent_m == pytest.approx((RELEASE_MAP_CHUNK_SIZE - 1) * RELEASE_UNIFORM_SCALE)
    assert spec.metres_per_multiplier == RELEASE_UNIFORM_SCALE


def test_land_stands_at_the_release_s_curve_times_the_multiplier_times_its_uniform_scale():
    """Recomputed with the curve evaluated from the release's keys and its scale (the noise normalised over the map,
    the release's normalizeMode Local)."""
    seed, level = 1, 7
    t = terrain(level, seed)
    value, far = recipe_height_value(t, seed)
    expected = unity_curve(value) * HAND_MULTIPLIERS[level - 1] * RELEASE_UNIFORM_SCALE
    np.testing.assert_allclose(t.heights[far], expected[far], rtol=1e-9, atol=1e-9)
