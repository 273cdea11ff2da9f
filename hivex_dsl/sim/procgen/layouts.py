"""Turbine layout patterns for Wind Farm Control.

HIVEX Wind Farm Control has 9 layout patterns. The original geometry is not published, so these
are our own, chosen to be clearly distinct. ``s`` is the minimum turbine spacing (metres); every
pattern places any turbine count ``n`` in 1..16 with every pair at least ``s`` apart:

* 0 default  -- staggered rows of 4 along x, 2 s between turbines and rows, odd rows shifted by s.
* 1 grid     -- near-square grid with ceil(sqrt(n)) columns, filled row by row, pitch 1.5 s.
* 2 chain    -- one straight row along x, pitch s.
* 3 circle   -- evenly spaced on a circle (first turbine at the top), neighbours 1.5 s apart.
* 4 square   -- evenly spaced along the perimeter of a square (first turbine at a corner),
                side chosen so the closest pair is 2 s apart.
* 5 cross    -- a plus: one turbine at the centre, the rest dealt to the N, E, S, W arms in
                turn, pitch 2 s along each arm.
* 6 two_rows -- two parallel rows along x, 3 s apart, turbines alternating between the rows,
                pitch 1.5 s along each row.
* 7 field    -- a diamond: the grid of ceil(sqrt(n)) columns with double pitch (2 s),
                rotated clockwise by 45 degrees.
* 8 random   -- uniform in [-half_extent, half_extent]^2 with every pair >= s apart
                (vectorised rejection sampling from the caller's ``np.random.Generator``).

Deterministic patterns (0-7) have their bounding box centred on the origin. Positions are
``(n, 2)`` float64 arrays of (x, y) in metres, inside ``[-half_extent, half_extent]^2``.
"""

from __future__ import annotations

import math
import numbers

import numpy as np

from ...base.errors import is_integer

__all__ = ["PATTERN_NAMES", "MAX_TURBINES", "turbine_layout", "layout_problem"]

PATTERN_NAMES: tuple[str, ...] = (
    "default", "grid", "chain", "circle", "square", "cross", "two_rows", "field", "random",
)
MAX_TURBINES = 16
RANDOM_PATTERN = 8

# Random pattern: at most this fraction of the farm's area may be "claimed" by n * spacing**2.
# Then the discs of radius `spacing` around n - 1 placed turbines cover at most pi/4 of the farm,
# so every candidate is acceptable with probability >= 1 - pi/4 > 0.21 whatever came before.
_RANDOM_PACKING_FRACTION = 0.25
_RANDOM_CANDIDATES_PER_ROUND = 128  # failure chance per round <= 0.79**128 < 1e-13
_RANDOM_MAX_ROUNDS = 64  # 16 turbines need at most 16 successful rounds

# Relative slack when comparing a layout's span with the farm width (float rounding only).
_FIT_TOLERANCE = 1e-12


# --- pattern shapes in units of the spacing (min pair distance >= 1) -----------------------------


def _staggered_rows(n: int) -> np.ndarray:
    """Default: rows of 4, pitch 2 in x and y, odd rows shifted by 1 (offshore-style stagger)."""
    k = np.arange(n)
    column, row = k % 4, k // 4
    return np.column_stack([2.0 * column + (row % 2), 2.0 * row])


def _square_grid(n: int, pitch: float) -> np.ndarray:
    """Row-major grid with ceil(sqrt(n)) columns and the given pitch."""
    columns = math.isqrt(n - 1) + 1  # == ceil(sqrt(n)) for n >= 1
    k = np.arange(n)
    return pitch * np.column_stack([k % columns, k // columns]).astype(np.float64)


def _grid(n: int) -> np.ndarray:
    """Grid: ceil(sqrt(n)) columns, pitch 1.5."""
    return _square_grid(n, 1.5)


def _chain(n: int) -> np.ndarray:
    """One straight row along x, pitch 1."""
    return np.column_stack([np.arange(n, dtype=np.float64), np.zeros(n)])


def _scaled_to_min_distance(points: np.ndarray, distance: float) -> np.ndarray:
    """``points`` scaled about the origin so their closest pair is ``distance`` apart."""
    if len(points) < 2:
        return points
    return points * (distance / _min_pair_distance(points))


def _circle(n: int) -> np.ndarray:
    """Evenly spaced on a circle starting at the top; neighbours 1.5 apart."""
    angles = np.pi / 2 + 2.0 * np.pi * np.arange(n) / n
    return _scaled_to_min_distance(np.column_stack([np.cos(angles), np.sin(angles)]), 1.5)


def _square_perimeter(n: int) -> np.ndarray:
    """Evenly spaced (by arc length) along a square's perimeter from a corner; closest pair 2."""
    corners = np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]])
    directions = np.array([[1.0, 0.0], [0.0, 1.0], [-1.0, 0.0], [0.0, -1.0]])
    arc = 4.0 * np.arange(n) / n  # in side lengths, in [0, 4)
    side = np.minimum(np.floor(arc).astype(np.int64), 3)
    points = corners[side] + (arc - side)[:, None] * directions[side]
    return _scaled_to_min_distance(points, 2.0)


def _cross(n: int) -> np.ndarray:
    """A plus: centre turbine, then N, E, S, W arms in turn, pitch 2 along each arm."""
    arms = np.array([[0.0, 1.0], [1.0, 0.0], [0.0, -1.0], [-1.0, 0.0]])
    k = np.arange(n - 1)
    arm_points = arms[k % 4] * (2.0 * (k // 4 + 1))[:, None]
    return np.vstack([np.zeros((1, 2)), arm_points])


def _two_rows(n: int) -> np.ndarray:
    """Two rows along x, 3 apart, turbines alternating between them, pitch 1.5 along a row."""
    k = np.arange(n)
    return np.column_stack([1.5 * (k // 2), 3.0 * (k % 2)])


def _diamond_field(n: int) -> np.ndarray:
    """The pitch-2 square grid rotated clockwise by 45 degrees."""
    grid = _square_grid(n, 2.0)
    return np.column_stack([grid[:, 0] + grid[:, 1], grid[:, 1] - grid[:, 0]]) / np.sqrt(2.0)


_SHAPES = (
    _staggered_rows,
    _grid,
    _chain,
    _circle,
    _square_perimeter,
    _cross,
    _two_rows,
    _diamond_field,
)


# --- helpers -------------------------------------------------------------------------------------


def _min_pair_distance(points: np.ndarray) -> float:
    """Smallest distance between two distinct rows of ``points`` (m, 2); inf if m < 2."""
    if len(points) < 2:
        return math.inf
    gaps = np.linalg.norm(points[:, None, :] - points[None, :, :], axis=-1)
    return float(gaps[np.triu_indices(len(points), k=1)].min())


def _centred(points: np.ndarray) -> np.ndarray:
    """``points`` translated so their bounding box is centred on the origin."""
    return points - (points.min(axis=0) + points.max(axis=0)) / 2.0


def _check_arguments(pattern: object, n: object, spacing: object, half_extent: object) -> None:
    """ValueError unless pattern is 0..8, n is 1..16 and spacing, half_extent are finite > 0."""
    for name, value in (("pattern", pattern), ("n", n)):
        if not is_integer(value):
            raise ValueError(f"{name} must be an integer, got {value!r}")
    if not 0 <= pattern < len(PATTERN_NAMES):
        raise ValueError(f"pattern must be in 0..{len(PATTERN_NAMES) - 1}, got {pattern}")
    if not 1 <= n <= MAX_TURBINES:
        raise ValueError(f"n (turbine count) must be in 1..{MAX_TURBINES}, got {n}")
    for name, value in (("spacing", spacing), ("half_extent", half_extent)):
        if not (isinstance(value, numbers.Real) and 0.0 < value < math.inf):
            raise ValueError(f"{name} must be a finite number > 0 (metres), got {value!r}")


def _deterministic_layout(pattern: int, n: int, spacing: float) -> np.ndarray:
    """(n, 2) positions in metres of a deterministic pattern, bounding box centred; no bounds check."""
    return _centred(_SHAPES[pattern](n) * spacing)


def _label(pattern: int) -> str:
    return f"pattern {pattern} ({PATTERN_NAMES[pattern]})"


_ADVICE = "lower params.turbine_spacing_m or raise params.farm_half_extent_m"


# --- public API ----------------------------------------------------------------------------------


def layout_problem(pattern: int, n: int, spacing: float, half_extent: float) -> str | None:
    """Why :func:`turbine_layout` would fail for these arguments, or None if it surely succeeds.

    Args:
        pattern: 0..8 (see ``PATTERN_NAMES``).
        n: turbine count, 1..16.
        spacing: minimum distance between any two turbines, metres (> 0).
        half_extent: the farm is the square ``[-half_extent, half_extent]^2``, metres (> 0).

    Returns:
        None if the layout fits (for Random: for every generator), else a one-line reason.

    Raises:
        ValueError: if an argument is out of its domain (wrong pattern, n, or non-positive size).
    """
    _check_arguments(pattern, n, spacing, half_extent)
    width = 2.0 * half_extent
    if pattern == RANDOM_PATTERN:
        claimed, allowed = n * spacing**2, _RANDOM_PACKING_FRACTION * width**2
        if claimed <= allowed:
            return None
        return (
            f"{_label(pattern)} with {n} turbines at spacing {spacing:g} m needs "
            f"n x spacing^2 = {claimed:g} m^2 <= 1/4 of the farm area (2 x {half_extent:g} m)^2 "
            f"= {allowed:g} m^2; {_ADVICE}, or use fewer turbines"
        )
    span = float(np.ptp(_deterministic_layout(pattern, n, spacing), axis=0).max())
    if span <= width * (1.0 + _FIT_TOLERANCE):
        return None
    return (
        f"{_label(pattern)} with {n} turbines spans {span:g} m at spacing {spacing:g} m, "
        f"wider than the farm (2 x {half_extent:g} m); {_ADVICE}"
    )


def _random_layout(
    n: int, spacing: float, half_extent: float, rng: np.random.Generator
) -> np.ndarray:
    """Uniform positions in the farm square, every pair >= spacing apart (rejection sampling).

    Each round draws a batch of candidates; a candidate is kept if it is far enough from every
    turbine already placed and from every *earlier* acceptable candidate of the same batch (so
    kept candidates are mutually compatible without a sequential loop).
    """
    placed = np.empty((0, 2))
    m = _RANDOM_CANDIDATES_PER_ROUND
    earlier = np.tri(m, k=-1, dtype=bool)  # earlier[i, j]: candidate j comes before i
    for _ in range(_RANDOM_MAX_ROUNDS):
        candidates = rng.uniform(-half_extent, half_extent, size=(m, 2))
        to_placed = np.linalg.norm(candidates[:, None, :] - placed[None, :, :], axis=-1)
        acceptable = np.all(to_placed >= spacing, axis=1)
        mutual = np.linalg.norm(candidates[:, None, :] - candidates[None, :, :], axis=-1)
        clash = (mutual < spacing) & earlier & acceptable[None, :]
        keep = np.flatnonzero(acceptable & ~clash.any(axis=1))[: n - len(placed)]
        placed = np.vstack([placed, candidates[keep]])
        if len(placed) == n:
            return placed
    raise ValueError(
        f"{_label(RANDOM_PATTERN)}: could not place {n} turbines {spacing:g} m apart in "
        f"2 x {half_extent:g} m after {_RANDOM_MAX_ROUNDS} rounds; {_ADVICE}"
    )


def turbine_layout(
    pattern: int,
    n: int,
    spacing: float,
    half_extent: float,
    rng: np.random.Generator | None = None,
) -> np.ndarray:
    """Turbine positions for one farm.

    Args:
        pattern: 0..8, index into ``PATTERN_NAMES`` (see the module docstring for geometry).
        n: turbine count, 1..16.
        spacing: minimum distance between any two turbines, metres (> 0).
        half_extent: farm half-width, metres; positions lie in ``[-half_extent, half_extent]^2``.
        rng: required for pattern 8 (random) only; deterministic patterns ignore it.

    Returns:
        ``(n, 2)`` float64 (x, y) positions in metres.

    Raises:
        ValueError: bad arguments, or the layout does not fit (message from :func:`layout_problem`).
    """
    problem = layout_problem(pattern, n, spacing, half_extent)
    if problem is not None:
        raise ValueError(problem)
    if pattern == RANDOM_PATTERN:
        if not isinstance(rng, np.random.Generator):
            raise ValueError(
                f"{_label(pattern)} needs rng, a numpy.random.Generator; got {type(rng).__name__}"
            )
        return _random_layout(int(n), float(spacing), float(half_extent), rng)
    positions = _deterministic_layout(int(pattern), int(n), float(spacing))
    return np.clip(positions, -half_extent, half_extent)
