"""Properties of the batched Perlin noise in ``hivex_dsl.sim.procgen.noise``."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from hivex_dsl.sim.procgen.noise import draw_lattice, fractal2d, perlin2d


def lattice(seed: int, batch: int = 1, period: int = 16) -> tuple[np.ndarray, np.ndarray]:
    return draw_lattice(np.random.default_rng(seed), batch, period)


def random_points(seed: int, batch: int, count: int, span: float) -> tuple[np.ndarray, np.ndarray]:
    rng = np.random.default_rng(seed)
    return rng.uniform(-span, span, (batch, count)), rng.uniform(-span, span, (batch, count))


# --- draw_lattice -------------------------------------------------------------------------------


def test_lattice_shapes_dtypes_and_permutation_structure():
    perm, grads = lattice(0, batch=3, period=8)
    assert perm.shape == (3, 16) and perm.dtype == np.int64
    assert grads.shape == (3, 8, 2) and grads.dtype == np.float64
    for row in perm:
        assert sorted(row[:8]) == list(range(8))
        np.testing.assert_array_equal(row[:8], row[8:])
    np.testing.assert_allclose(np.linalg.norm(grads, axis=-1), 1.0, atol=1e-12)


def test_lattice_rows_are_independent_draws():
    perm, grads = lattice(1, batch=2, period=64)
    assert not np.array_equal(perm[0], perm[1])
    assert not np.allclose(grads[0], grads[1])


@pytest.mark.parametrize(
    "batch, period", [(0, 16), (-1, 16), (1, 1), (1, 0), (2.0, 16), (1, 16.0), (True, 16)]
)
def test_lattice_rejects_bad_sizes(batch, period):
    with pytest.raises(ValueError):
        draw_lattice(np.random.default_rng(0), batch, period)


def test_lattice_requires_a_generator():
    with pytest.raises(ValueError, match="Generator"):
        draw_lattice(np.random.RandomState(0), 1, 16)  # type: ignore[arg-type]


# --- reproducibility ----------------------------------------------------------------------------


def test_same_seed_gives_identical_noise_and_different_seeds_differ():
    x, y = random_points(99, 2, 500, 20.0)
    a = perlin2d(*lattice(5, batch=2), x, y)
    b = perlin2d(*lattice(5, batch=2), x, y)
    c = perlin2d(*lattice(6, batch=2), x, y)
    np.testing.assert_array_equal(a, b)
    assert not np.allclose(a, c)
    np.testing.assert_array_equal(fractal2d(*lattice(5, 2), x, y), fractal2d(*lattice(5, 2), x, y))


# --- range --------------------------------------------------------------------------------------


@settings(max_examples=40, deadline=None)
@given(seed=st.integers(0, 2**32 - 1), span=st.floats(0.5, 1e4), octaves=st.integers(1, 6))
def test_values_stay_in_unit_interval(seed, span, octaves):
    perm, grads = lattice(seed, batch=3, period=32)
    x, y = random_points(seed, 3, 4000, span)
    for values in (perlin2d(perm, grads, x, y), fractal2d(perm, grads, x, y, octaves=octaves)):
        assert values.shape == (3, 4000) and values.dtype == np.float64
        assert np.all(values >= -1.0) and np.all(values <= 1.0)


def test_range_is_used_substantially():
    """Scaling by sqrt(2) must not squash the noise: some samples get well away from 0."""
    perm, grads = lattice(3, batch=4, period=64)
    x, y = random_points(3, 4, 20_000, 64.0)
    assert np.abs(perlin2d(perm, grads, x, y)).max() > 0.5


# --- hand-computed values ----------------------------------------------------------------------


def constant_gradient_lattice(gradient: tuple[float, float], period: int = 4):
    perm = np.tile(np.arange(period), 2)[None, :]
    grads = np.tile(np.asarray(gradient, dtype=float), (1, period, 1))
    return perm, grads


def test_hand_computed_value_with_constant_gradients():
    """All gradients (1, 0): n = sqrt(2) * (fx - fade(fx)), independent of y.

    fx = 0.25: fade = 0.25**3 * (10 - 15*0.25 + 6*0.25**2) = 0.015625 * 6.625 = 0.103515625,
    so n = sqrt(2) * 0.146484375.
    """
    perm, grads = constant_gradient_lattice((1.0, 0.0))
    x = np.array([[0.25, 1.25, 2.25, 0.25, 0.5]])
    y = np.array([[0.0, 0.7, 3.9, -5.3, 0.3]])
    expected = np.sqrt(2.0) * np.array([[0.146484375] * 4 + [0.0]])
    np.testing.assert_allclose(perlin2d(perm, grads, x, y), expected, atol=1e-12)


def test_cell_centre_reaches_one_when_all_gradients_point_inwards():
    """perm [0, 2, 1, 3] hashes the cell corners (0,0),(1,0),(0,1),(1,1) to gradients 0..3.

    Gradients pointing at the centre (0.5, 0.5) each give a dot product of 1/sqrt(2); after
    the sqrt(2) scaling the noise there is exactly the range maximum 1.
    """
    perm = np.array([[0, 2, 1, 3, 0, 2, 1, 3]])
    grads = np.array([[[1, 1], [-1, 1], [1, -1], [-1, -1]]], dtype=float) / np.sqrt(2.0)
    value = perlin2d(perm, grads, np.array([[0.5]]), np.array([[0.5]]))
    np.testing.assert_allclose(value, [[1.0]], atol=1e-12)
    negated = perlin2d(perm, -grads, np.array([[0.5]]), np.array([[0.5]]))
    np.testing.assert_allclose(negated, [[-1.0]], atol=1e-12)


# --- lattice points, periodicity, continuity ----------------------------------------------------


def test_zero_at_integer_lattice_points():
    perm, grads = lattice(7, batch=2, period=16)
    ix, iy = np.meshgrid(np.arange(-20, 21), np.arange(-20, 21), indexing="ij")
    x = np.stack([ix, ix + 3]).astype(float)
    y = np.stack([iy, iy - 5]).astype(float)
    assert np.all(perlin2d(perm, grads, x, y) == 0.0)
    assert np.all(fractal2d(perm, grads, x, y) == 0.0)  # integer lacunarity keeps lattice points


@pytest.mark.parametrize("period", [4, 16, 256])
def test_periodic_with_the_lattice_period(period):
    perm, grads = lattice(11, batch=2, period=period)
    x, y = random_points(11, 2, 2000, period)
    base = perlin2d(perm, grads, x, y)
    for dx, dy in [(period, 0), (0, period), (-period, 2 * period)]:
        shifted = perlin2d(perm, grads, x + dx, y + dy)
        np.testing.assert_allclose(shifted, base, atol=1e-9)
    np.testing.assert_allclose(
        fractal2d(perm, grads, x + period, y - period), fractal2d(perm, grads, x, y), atol=1e-9
    )


def test_not_periodic_with_a_shorter_shift():
    perm, grads = lattice(11, batch=1, period=16)
    x, y = random_points(12, 1, 2000, 16.0)
    assert not np.allclose(perlin2d(perm, grads, x + 8, y), perlin2d(perm, grads, x, y), atol=1e-3)


def test_continuous_under_small_steps():
    perm, grads = lattice(13, batch=2, period=32)
    x, y = random_points(13, 2, 20_000, 40.0)
    for noise in (perlin2d, fractal2d):
        base = noise(perm, grads, x, y)
        assert np.abs(noise(perm, grads, x + 1e-4, y) - base).max() < 1e-2
        assert np.abs(noise(perm, grads, x, y + 1e-4) - base).max() < 1e-2
    # Across cell borders too: points just either side of integer x.
    ix = np.arange(-10, 11, dtype=float)[None, :].repeat(2, axis=0)
    iy = np.full_like(ix, 0.37)
    left = perlin2d(perm, grads, ix - 1e-6, iy)
    right = perlin2d(perm, grads, ix + 1e-6, iy)
    assert np.abs(left - right).max() < 1e-4


# --- batching -----------------------------------------------------------------------------------


def test_batch_rows_are_evaluated_independently():
    perm, grads = lattice(17, batch=2, period=32)
    x, y = random_points(17, 2, 300, 30.0)
    both = perlin2d(perm, grads, x, y)
    for b in range(2):
        alone = perlin2d(perm[b : b + 1], grads[b : b + 1], x[b : b + 1], y[b : b + 1])
        np.testing.assert_array_equal(both[b : b + 1], alone)
    both_fractal = fractal2d(perm, grads, x, y, octaves=3)
    alone_fractal = fractal2d(perm[:1], grads[:1], x[:1], y[:1], octaves=3)
    np.testing.assert_array_equal(both_fractal[:1], alone_fractal)


def test_multidimensional_sample_shapes():
    perm, grads = lattice(19, batch=2, period=16)
    rng = np.random.default_rng(19)
    x = rng.uniform(0, 16, (2, 3, 4, 5))
    y = rng.uniform(0, 16, (2, 3, 4, 5))
    values = perlin2d(perm, grads, x, y)
    assert values.shape == (2, 3, 4, 5)
    flat = perlin2d(perm, grads, x.reshape(2, -1), y.reshape(2, -1))
    np.testing.assert_array_equal(values.reshape(2, -1), flat)


# --- fractal statistics -------------------------------------------------------------------------


def test_fractal_grid_has_zero_mean_and_real_variation():
    perm, grads = draw_lattice(np.random.default_rng(23), 4, 256)
    coords = (np.arange(256) + 0.5) / 16.0  # 16 lattice cells per side, off the lattice points
    gx, gy = np.meshgrid(coords, coords, indexing="ij")
    x = np.broadcast_to(gx, (4, 256, 256))
    y = np.broadcast_to(gy, (4, 256, 256))
    values = fractal2d(perm, grads, x, y)
    assert values.shape == (4, 256, 256)
    assert abs(values.mean()) < 0.05
    assert values.std() > 0.05


def test_single_octave_fractal_equals_perlin():
    perm, grads = lattice(29, batch=2)
    x, y = random_points(29, 2, 500, 10.0)
    np.testing.assert_array_equal(fractal2d(perm, grads, x, y, octaves=1), perlin2d(perm, grads, x, y))


def test_fractal_is_the_normalised_octave_sum():
    """Hand-assembled from perlin2d: (n(p) + 0.5 n(3p)) / 1.5 for persistence 0.5, lacunarity 3."""
    perm, grads = lattice(31, batch=2)
    x, y = random_points(31, 2, 500, 10.0)
    expected = (perlin2d(perm, grads, x, y) + 0.5 * perlin2d(perm, grads, 3 * x, 3 * y)) / 1.5
    got = fractal2d(perm, grads, x, y, octaves=2, persistence=0.5, lacunarity=3.0)
    np.testing.assert_allclose(got, expected, atol=1e-12)


def test_large_single_field_grid_works():
    perm, grads = draw_lattice(np.random.default_rng(37), 1, 256)
    coords = np.linspace(0.0, 30.0, 241)
    gx, gy = np.meshgrid(coords, coords, indexing="ij")
    values = fractal2d(perm, grads, gx[None], gy[None])
    assert values.shape == (1, 241, 241)
    assert np.isfinite(values).all()


# --- argument validation ------------------------------------------------------------------------


@pytest.mark.parametrize(
    "kwargs",
    [{"octaves": 0}, {"octaves": 1.5}, {"persistence": 0.0}, {"persistence": 1.5},
     {"lacunarity": 0.5}, {"lacunarity": float("inf")}],
)
def test_fractal_rejects_bad_parameters(kwargs):
    perm, grads = lattice(0)
    x = np.zeros((1, 3))
    with pytest.raises(ValueError):
        fractal2d(perm, grads, x, x, **kwargs)


def test_perlin_rejects_inconsistent_shapes():
    perm, grads = lattice(0, batch=2, period=16)
    good = np.zeros((2, 5))
    with pytest.raises(ValueError, match="identical shapes"):
        perlin2d(perm, grads, good, np.zeros((2, 4)))
    with pytest.raises(ValueError, match="B = 2"):
        perlin2d(perm, grads, np.zeros((3, 5)), np.zeros((3, 5)))
    with pytest.raises(ValueError, match="perm"):
        perlin2d(perm[:, :16], grads, good, good)
    with pytest.raises(ValueError, match="perm"):
        perlin2d(perm[:1], grads, good, good)
    with pytest.raises(ValueError, match="grads"):
        perlin2d(perm, grads[..., :1], good, good)
    with pytest.raises(ValueError, match="perm"):
        perlin2d(perm.astype(float), grads, good, good)
    with pytest.raises(ValueError, match="perm entries"):
        perlin2d(perm + 16, grads, good, good)
    with pytest.raises(ValueError, match="finite"):
        perlin2d(perm, grads, np.full((2, 5), np.nan), good)
    with pytest.raises(ValueError):
        perlin2d(perm, grads, np.float64(1.0), np.float64(1.0))
