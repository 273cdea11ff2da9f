"""Geometry guarantees of the Wind Farm Control turbine layouts in ``hivex_dsl.sim.procgen.layouts``."""

from __future__ import annotations

import itertools

import numpy as np
import pytest

from hivex_dsl.sim.procgen.layouts import PATTERN_NAMES, layout_problem, turbine_layout

SPACING = 70.0  # simulator defaults
HALF_EXTENT = 600.0
RANDOM = 8
DETERMINISTIC = range(8)
ALL_COUNTS = range(1, 17)


def min_pair_distance(points: np.ndarray) -> float:
    gaps = np.linalg.norm(points[:, None, :] - points[None, :, :], axis=-1)
    return float(gaps[np.triu_indices(len(points), k=1)].min()) if len(points) > 1 else np.inf


def layout(pattern: int, n: int, seed: int | None = 0, **kwargs) -> np.ndarray:
    rng = None if seed is None else np.random.default_rng(seed)
    args = {"spacing": SPACING, "half_extent": HALF_EXTENT, **kwargs}
    return turbine_layout(pattern, n, args["spacing"], args["half_extent"], rng)


def sorted_rows(points: np.ndarray) -> np.ndarray:
    return points[np.lexsort((points[:, 1], points[:, 0]))]


def test_pattern_names():
    assert PATTERN_NAMES == (
        "default", "grid", "chain", "circle", "square", "cross", "two_rows", "field", "random"
    )


# --- guarantees for every pattern and count at the defaults --------------------------------------


@pytest.mark.parametrize("pattern", range(9), ids=PATTERN_NAMES)
def test_every_count_fits_the_defaults_with_min_spacing(pattern):
    for n in ALL_COUNTS:
        assert layout_problem(pattern, n, SPACING, HALF_EXTENT) is None
        points = layout(pattern, n, seed=n)
        assert points.shape == (n, 2) and points.dtype == np.float64
        assert min_pair_distance(points) >= SPACING - 1e-9, (pattern, n)
        assert np.all(np.abs(points) <= HALF_EXTENT), (pattern, n)


@pytest.mark.parametrize("pattern", DETERMINISTIC, ids=PATTERN_NAMES[:8])
def test_deterministic_patterns_ignore_rng_and_are_centred(pattern):
    for n in ALL_COUNTS:
        reference = layout(pattern, n, seed=None)
        for seed in (0, 1, 12345):
            np.testing.assert_array_equal(layout(pattern, n, seed=seed), reference)
        box_centre = (reference.min(axis=0) + reference.max(axis=0)) / 2
        np.testing.assert_allclose(box_centre, 0.0, atol=1e-9)
        assert np.all(np.abs(reference.mean(axis=0)) <= SPACING), (pattern, n)


def test_single_turbine_sits_at_the_origin_for_deterministic_patterns():
    for pattern in DETERMINISTIC:
        np.testing.assert_allclose(layout(pattern, 1, seed=None), [[0.0, 0.0]], atol=1e-12)


@pytest.mark.parametrize("n", [8] + list(range(2, 17)))
def test_deterministic_patterns_are_mutually_distinct(n):
    shapes = {p: sorted_rows(layout(p, n, seed=None)) for p in DETERMINISTIC}
    for a, b in itertools.combinations(DETERMINISTIC, 2):
        assert not np.allclose(shapes[a], shapes[b], atol=1e-6), (PATTERN_NAMES[a], PATTERN_NAMES[b])


# --- hand-computed geometry ----------------------------------------------------------------------


def test_chain_is_a_row_at_exact_spacing():
    np.testing.assert_allclose(layout(2, 3), [[-70, 0], [0, 0], [70, 0]], atol=1e-9)
    points = layout(2, 16)
    assert np.ptp(points[:, 0]) == pytest.approx(15 * 70.0) and np.all(points[:, 1] == 0)


def test_grid_of_four_is_a_square_at_one_and_a_half_spacings():
    expected = [[-52.5, -52.5], [-52.5, 52.5], [52.5, -52.5], [52.5, 52.5]]
    np.testing.assert_allclose(sorted_rows(layout(1, 4)), expected, atol=1e-9)


def test_grid_uses_ceil_sqrt_columns():
    for n, columns in [(2, 2), (5, 3), (9, 3), (10, 4), (16, 4)]:
        assert len(np.unique(layout(1, n)[:, 0].round(6))) == columns


def test_default_staggers_rows_of_four():
    points = layout(0, 8)  # two rows of 4: pitch 140 m, second row shifted by 70 m
    rows = sorted(np.unique(points[:, 1].round(6)))
    np.testing.assert_allclose(rows, [-70.0, 70.0], atol=1e-9)
    lower = np.sort(points[points[:, 1] < 0, 0])
    upper = np.sort(points[points[:, 1] > 0, 0])
    np.testing.assert_allclose(np.diff(lower), 140.0)
    np.testing.assert_allclose(upper - lower, 70.0)


def test_circle_points_are_equidistant_from_their_centre_and_evenly_spaced():
    for n in range(3, 17):
        points = layout(3, n)
        radii = np.linalg.norm(points - points.mean(axis=0), axis=1)
        np.testing.assert_allclose(radii, radii[0], rtol=1e-9)
        neighbours = np.linalg.norm(points - np.roll(points, 1, axis=0), axis=1)
        np.testing.assert_allclose(neighbours, 1.5 * SPACING, rtol=1e-9)


def test_square_points_lie_on_the_bounding_square():
    for n in range(4, 17):
        points = layout(4, n)
        half_side = np.abs(points).max()
        on_edge = np.isclose(np.abs(points), half_side, atol=1e-9).any(axis=1)
        assert on_edge.all(), n
        np.testing.assert_allclose(np.ptp(points, axis=0), 2 * half_side, atol=1e-9)
    corners = [[-70, -70], [-70, 70], [70, -70], [70, 70]]  # side 2 spacings
    np.testing.assert_allclose(sorted_rows(layout(4, 4)), corners, atol=1e-9)
    midpoints = [[-140, -140], [-140, 0], [-140, 140], [0, -140], [0, 140], [140, -140], [140, 0],
                 [140, 140]]  # 8 = corners + side midpoints, 2 spacings apart
    np.testing.assert_allclose(sorted_rows(layout(4, 8)), midpoints, atol=1e-9)


def test_cross_of_five_is_a_plus_with_two_spacing_arms():
    expected = [[-140, 0], [0, -140], [0, 0], [0, 140], [140, 0]]
    np.testing.assert_allclose(sorted_rows(layout(5, 5)), expected, atol=1e-9)
    points = layout(5, 13)  # 3 turbines per arm: every turbine on one of the two axes
    assert np.all(np.isclose(points, 0.0, atol=1e-9).any(axis=1))


def test_two_rows_are_parallel_and_three_spacings_apart():
    for n in range(2, 17):
        points = layout(6, n)
        np.testing.assert_allclose(sorted(np.unique(points[:, 1].round(6))), [-105.0, 105.0])
        assert abs(np.sum(points[:, 1] > 0) - np.sum(points[:, 1] < 0)) <= 1


def test_field_of_four_is_a_diamond():
    d = 2 * SPACING / np.sqrt(2)  # half-diagonal of a 2-spacing square cell
    expected = [[-d, 0], [0, -d], [0, d], [d, 0]]
    np.testing.assert_allclose(sorted_rows(layout(7, 4)), expected, atol=1e-9)


# --- random pattern ------------------------------------------------------------------------------


def test_random_is_reproducible_per_seed_and_differs_across_seeds():
    np.testing.assert_array_equal(layout(RANDOM, 16, seed=3), layout(RANDOM, 16, seed=3))
    assert not np.allclose(layout(RANDOM, 16, seed=3), layout(RANDOM, 16, seed=4))


def test_random_keeps_spacing_and_bounds_over_many_seeds():
    for seed in range(200):
        points = layout(RANDOM, 16, seed=seed)
        assert points.shape == (16, 2)
        assert min_pair_distance(points) >= SPACING
        assert np.all(np.abs(points) <= HALF_EXTENT)


def test_random_succeeds_at_the_packing_bound():
    """n * spacing**2 == (2 * half_extent)**2 / 4 is the tightest case layout_problem accepts."""
    half_extent = 100.0
    for n in (2, 9, 16):
        spacing = np.sqrt(0.25 * (2 * half_extent) ** 2 / n) * (1 - 1e-12)
        assert layout_problem(RANDOM, n, spacing, half_extent) is None
        for seed in range(40):
            points = layout(RANDOM, n, seed=seed, spacing=spacing, half_extent=half_extent)
            assert min_pair_distance(points) >= spacing
            assert np.all(np.abs(points) <= half_extent)


def test_random_spreads_over_the_farm():
    points = np.concatenate([layout(RANDOM, 16, seed=s) for s in range(50)])
    assert np.all(np.abs(points.mean(axis=0)) < 60.0)  # uniform on [-600, 600]: mean ~ 0
    assert np.all(np.ptp(points, axis=0) > 1000.0)


def test_random_gives_up_with_value_error_after_bounded_rounds(monkeypatch):
    import hivex_dsl.sim.procgen.layouts as layouts

    monkeypatch.setattr(layouts, "_RANDOM_CANDIDATES_PER_ROUND", 1)
    monkeypatch.setattr(layouts, "_RANDOM_MAX_ROUNDS", 3)  # at most 3 turbines can be placed
    with pytest.raises(ValueError, match="could not place 16 turbines"):
        layout(RANDOM, 16)


def test_random_requires_a_generator():
    with pytest.raises(ValueError, match="rng"):
        turbine_layout(RANDOM, 4, SPACING, HALF_EXTENT)
    with pytest.raises(ValueError, match="rng"):
        turbine_layout(RANDOM, 4, SPACING, HALF_EXTENT, np.random.RandomState(0))


# --- infeasible and invalid arguments ------------------------------------------------------------


def test_infeasible_chain_is_reported_and_raises():
    reason = layout_problem(2, 16, 100.0, 200.0)
    assert isinstance(reason, str) and "\n" not in reason
    assert "chain" in reason and "1500 m" in reason  # 15 gaps of 100 m
    with pytest.raises(ValueError) as raised:
        turbine_layout(2, 16, 100.0, 200.0)
    assert str(raised.value) == reason


def test_infeasible_random_is_reported_and_raises():
    reason = layout_problem(RANDOM, 16, 100.0, 200.0)  # 16 * 100^2 > 400^2 / 4
    assert isinstance(reason, str) and "random" in reason
    with pytest.raises(ValueError):
        turbine_layout(RANDOM, 16, 100.0, 200.0, np.random.default_rng(0))


def test_feasibility_boundary_of_the_chain():
    assert layout_problem(2, 16, 80.0, 600.0) is None  # spans exactly 1200 m
    assert layout_problem(2, 16, 80.01, 600.0) is not None
    assert min_pair_distance(turbine_layout(2, 16, 80.0, 600.0)) >= 80.0 - 1e-9
    assert np.all(np.abs(turbine_layout(2, 16, 80.0, 600.0)) <= 600.0)


@pytest.mark.parametrize(
    "pattern, n, spacing, half_extent",
    [(-1, 4, 70.0, 600.0), (9, 4, 70.0, 600.0), (1.0, 4, 70.0, 600.0), (True, 4, 70.0, 600.0),
     (0, 0, 70.0, 600.0), (0, 17, 70.0, 600.0), (0, 4.0, 70.0, 600.0),
     (0, 4, 0.0, 600.0), (0, 4, -70.0, 600.0), (0, 4, float("nan"), 600.0),
     (0, 4, 70.0, 0.0), (0, 4, 70.0, float("inf"))],
)
def test_bad_arguments_raise(pattern, n, spacing, half_extent):
    with pytest.raises(ValueError):
        turbine_layout(pattern, n, spacing, half_extent, np.random.default_rng(0))
    with pytest.raises(ValueError):
        layout_problem(pattern, n, spacing, half_extent)
