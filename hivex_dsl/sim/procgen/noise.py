"""Batched 2D Perlin gradient noise, shared by every environment's procedural content.

Wind, weather and terrain use it. All functions work on a batch of ``B`` independent noise fields
at once, each with its own random lattice:

* :func:`draw_lattice` draws the lattice (a permutation table and unit gradient vectors) from an
  ``np.random.Generator`` -- the only source of randomness in this module.
* :func:`perlin2d` evaluates classic Perlin noise (quintic fade) at arbitrary points.
* :func:`fractal2d` sums several octaves of it ("fractal Brownian motion").
* Callers that keep a lattice in their state evaluate it in parts: :func:`octave_points`,
  :func:`corner_gradients` (which a caller whose points stay in their cells may keep),
  :func:`blend_corners` and :func:`sum_octaves`; :func:`fractal_unchecked` chains them.

Coordinates are in *lattice units*: one unit is the distance between neighbouring lattice points,
and a field with period ``P`` repeats every ``P`` units in x and in y. Noise values are
dimensionless and lie in ``[-1, 1]``; callers scale them to physical units (m/s, metres, ...).
"""

from __future__ import annotations

import functools
import numbers

import numpy as np

from ...base.errors import is_integer
from ...base.numeric import clamp, constant

__all__ = ["draw_lattice", "fade", "perlin2d", "fractal2d", "fractal_unchecked", "octave_frequencies", "octave_points",
           "corner_gradients", "blend_corners", "sum_octaves"]

# Unit-gradient 2D Perlin noise peaks at sqrt(2)/2 in magnitude; this factor maps it onto [-1, 1].
_RANGE_SCALE = np.sqrt(2.0)


def require_int(name: str, value: object, minimum: int) -> int:
    """``value`` as a Python int, or ValueError if it is not an integer >= ``minimum``."""
    if not is_integer(value):
        raise ValueError(f"{name} must be an integer, got {value!r}")
    if value < minimum:
        raise ValueError(f"{name} must be >= {minimum}, got {value}")
    return int(value)


def draw_lattice(
    rng: np.random.Generator, batch: int, period: int = 256
) -> tuple[np.ndarray, np.ndarray]:
    """Random lattice for ``batch`` independent noise fields.

    Args:
        rng: the generator every random number is drawn from.
        batch: number of independent fields ``B`` (>= 1).
        period: lattice period ``P`` in lattice units (>= 2); the noise repeats every ``P`` units.

    Returns:
        perm: ``(B, 2P)`` int64 -- per row, a random permutation of ``range(P)`` repeated twice.
        grads: ``(B, P, 2)`` float64 -- unit gradient vectors at uniformly random angles.
    """
    if not isinstance(rng, np.random.Generator):
        raise ValueError(f"rng must be a numpy.random.Generator, got {type(rng).__name__}")
    batch = require_int("batch", batch, 1)
    period = require_int("period", period, 2)
    ordered = np.broadcast_to(np.arange(period, dtype=np.int64), (batch, period))
    perm = rng.permuted(ordered, axis=1)
    angles = rng.uniform(0.0, 2.0 * np.pi, size=(batch, period))
    grads = np.stack([np.cos(angles), np.sin(angles)], axis=-1)
    return np.concatenate([perm, perm], axis=1), grads


def _checked_inputs(
    perm: np.ndarray, grads: np.ndarray, x: np.ndarray, y: np.ndarray
) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Validate a lattice and sample coordinates; return them as int64 / float64 arrays."""
    perm = np.asarray(perm)
    grads = np.asarray(grads, dtype=np.float64)
    x = np.asarray(x, dtype=np.float64)
    y = np.asarray(y, dtype=np.float64)
    if grads.ndim != 3 or grads.shape[2] != 2 or grads.shape[1] < 2:
        raise ValueError(f"grads must have shape (B, P, 2) with P >= 2, got {grads.shape}")
    batch, period = grads.shape[:2]
    if perm.shape != (batch, 2 * period):
        raise ValueError(
            f"perm must have shape (B, 2P) = {(batch, 2 * period)} to match grads {grads.shape}, "
            f"got {perm.shape}"
        )
    if not np.issubdtype(perm.dtype, np.integer):
        raise ValueError(f"perm must hold integers, got dtype {perm.dtype}")
    if perm.min() < 0 or perm.max() >= period:
        raise ValueError(f"perm entries must lie in [0, {period}), the lattice period")
    if x.shape != y.shape:
        raise ValueError(f"x and y must have identical shapes, got {x.shape} and {y.shape}")
    if x.ndim < 1 or x.shape[0] != batch:
        raise ValueError(f"x and y must have shape (B, ...) with B = {batch}, got {x.shape}")
    if not (np.isfinite(x).all() and np.isfinite(y).all()):
        raise ValueError("x and y must be finite")
    return perm.astype(np.int64, copy=False), grads, x, y


def fade(t: np.ndarray) -> np.ndarray:
    """Quintic smoothstep 6t^5 - 15t^4 + 10t^3 (zero first and second derivative at 0 and 1), t float64."""
    return t * t * t * (t * (t * _SIX - _FIFTEEN) + _TEN)


# Operands of the float64 hot paths below, as 0-d arrays (see hivex_dsl.base.numeric).
_SIX, _FIFTEEN, _TEN = constant(6.0), constant(15.0), constant(10.0)
_ONE, _MINUS_ONE, _RANGE_SCALE_0D = constant(1.0), constant(-1.0), constant(_RANGE_SCALE)


# The four corners of a lattice cell, in the order (0, 0), (1, 0), (0, 1), (1, 1).
_CORNER_X = np.array([0.0, 1.0, 0.0, 1.0])
_CORNER_Y = np.array([0.0, 0.0, 1.0, 1.0])


def corner_gradients(perm: np.ndarray, grads: np.ndarray, lower: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Hashed gradients at the four corners of lattice cells.

    Args:
        perm, grads: a validated lattice, ``(B, 2P)`` and ``(B, P, 2)``.
        lower: ``(2, B, ...)`` float lower-left corners (``floor`` of x, then of y) of the cells.

    Returns:
        ``(gx, gy)``, each ``(4, B, ...)``: the gradient components at the corners (0, 0), (1, 0),
        (0, 1), (1, 1). They depend on the cell only, so a caller whose points stay in their cells
        may keep them between evaluations (see :func:`blend_corners`).
    """
    batch, period = grads.shape[:2]
    shape = (batch,) + (1,) * (lower.ndim - 2)
    # Flat tables with per-row offsets: one 1-D take per lookup is much cheaper than 2-D fancy indexing.
    perm_offset = (np.arange(batch) * perm.shape[1]).reshape(shape)
    grad_offset = (np.arange(batch) * period).reshape(shape)
    flat_perm = perm.reshape(-1)
    index0 = np.mod(lower, period).astype(np.int64)
    index = np.stack([index0, (index0 + 1) % period])  # (2 lower/next, 2 x/y, B, ...)
    hashed_x = flat_perm.take(perm_offset + index[:, 0])
    gradient = flat_perm.take(perm_offset + hashed_x[[0, 1, 0, 1]] + index[[0, 0, 1, 1], 1]) + grad_offset
    both = grads.reshape(-1, 2).take(gradient, axis=0)
    return both[..., 0], both[..., 1]


def blend_corners(gx: np.ndarray, gy: np.ndarray, offset: np.ndarray) -> np.ndarray:
    """Perlin noise from the corner gradients' components ``gx``, ``gy`` (4, ...) and float64 offsets
    ``offset`` (2, ...) (x, then y) in [0, 1) within the cells.

    Returns values in [-1, 1] shaped like ``gx[0]``: each corner's gradient dotted with the offset from
    that corner, blended with the quintic fade along x (per pair of corners), then along y. Every
    operation is elementwise, so any layout works where ``offset[0]`` broadcasts against ``gx[0]``
    (the weather's fields share their offsets, for instance); keep the long axes last.
    """
    corner_x, corner_y = _corner_columns(gx.ndim)
    dots = gx * (offset[0] - corner_x)
    dots += gy * (offset[1] - corner_y)
    weights = fade(offset)
    bottom = dots[0] + weights[0] * (dots[1] - dots[0])  # corners (0, 0) and (1, 0)
    top = dots[2] + weights[0] * (dots[3] - dots[2])  # corners (0, 1) and (1, 1)
    blended = bottom + weights[1] * (top - bottom)
    return clamp(_RANGE_SCALE_0D * blended, _MINUS_ONE, _ONE)


@functools.lru_cache(maxsize=8)
def _corner_columns(ndim: int) -> tuple[np.ndarray, np.ndarray]:
    """The corners' x and y offsets shaped (4, 1, ...) to broadcast against gradients of ``ndim`` axes."""
    corner_shape = (4,) + (1,) * (ndim - 1)
    return _CORNER_X.reshape(corner_shape), _CORNER_Y.reshape(corner_shape)


def _perlin_unchecked(perm: np.ndarray, grads: np.ndarray, x: np.ndarray, y: np.ndarray) -> np.ndarray:
    """Perlin noise on validated inputs (see :func:`perlin2d`), values in [-1, 1]."""
    points = np.stack([x, y])
    lower = np.floor(points)
    return blend_corners(*corner_gradients(perm, grads, lower), points - lower)


def perlin2d(perm: np.ndarray, grads: np.ndarray, x: np.ndarray, y: np.ndarray) -> np.ndarray:
    """Classic 2D Perlin gradient noise with quintic fade, evaluated for a batch of fields.

    Args:
        perm: ``(B, 2P)`` integer permutation table from :func:`draw_lattice`.
        grads: ``(B, P, 2)`` unit gradients from :func:`draw_lattice`.
        x, y: float arrays of identical shape ``(B, ...)``, coordinates in lattice units.
            Row ``b`` of ``x``/``y`` is evaluated with ``perm[b]``/``grads[b]``.

    Returns:
        ``(B, ...)`` float64 noise in ``[-1, 1]`` (raw value times sqrt(2), clipped). The noise is
        0 at integer lattice points, smooth (C2) everywhere, and periodic with period ``P`` in
        x and in y.
    """
    return _perlin_unchecked(*_checked_inputs(perm, grads, x, y))


def _check_octave_args(octaves: int, persistence: float, lacunarity: float) -> int:
    """Validate the fractal parameters; return ``octaves`` as an int."""
    octaves = require_int("octaves", octaves, 1)
    if not (isinstance(persistence, numbers.Real) and 0.0 < persistence <= 1.0):
        raise ValueError(f"persistence must be in (0, 1], got {persistence!r}")
    if not (isinstance(lacunarity, numbers.Real) and 1.0 <= lacunarity < np.inf):
        raise ValueError(f"lacunarity must be a finite number >= 1, got {lacunarity!r}")
    return octaves


def fractal2d(
    perm: np.ndarray,
    grads: np.ndarray,
    x: np.ndarray,
    y: np.ndarray,
    octaves: int = 4,
    persistence: float = 0.5,
    lacunarity: float = 2.0,
) -> np.ndarray:
    """Fractal (multi-octave) Perlin noise for a batch of fields.

    Octave ``k`` (``k = 0 .. octaves-1``) is :func:`perlin2d` at frequency ``lacunarity**k``
    with amplitude ``persistence**k``; the sum is divided by the sum of amplitudes, so the result
    stays in ``[-1, 1]``. With an integer ``lacunarity`` the result keeps period ``P``.

    Args:
        perm, grads, x, y: as for :func:`perlin2d`; shapes ``(B, 2P)``, ``(B, P, 2)``, ``(B, ...)``.
        octaves: number of octaves, >= 1.
        persistence: amplitude ratio between successive octaves, in (0, 1].
        lacunarity: frequency ratio between successive octaves, >= 1.

    Returns:
        ``(B, ...)`` float64 noise in ``[-1, 1]``.
    """
    octaves = _check_octave_args(octaves, persistence, lacunarity)
    return fractal_unchecked(*_checked_inputs(perm, grads, x, y), octaves, persistence, lacunarity)


@functools.lru_cache(maxsize=64)
def octave_frequencies(octaves: int, lacunarity: float) -> np.ndarray:
    """``(octaves, 1)`` read-only frequencies ``lacunarity**k`` (callers take ``[:, 0]`` or add the axes they need)."""
    frequencies = np.array([lacunarity**k for k in range(octaves)]).reshape(octaves, 1)
    frequencies.flags.writeable = False
    return frequencies


def octave_points(x: np.ndarray, y: np.ndarray, octaves: int, lacunarity: float) -> np.ndarray:
    """Sample points of every octave: ``(B, ...)`` x and y -> ``(2, B, ..., octaves)`` lattice coordinates."""
    frequencies = octave_frequencies(octaves, lacunarity)[:, 0]
    points = np.empty((2,) + x.shape + (octaves,))
    np.multiply(x[..., None], frequencies, out=points[0])
    np.multiply(y[..., None], frequencies, out=points[1])
    return points


def sum_octaves(layered: np.ndarray, persistence: float, axis: int = -1) -> np.ndarray:
    """Per-octave noise with the octaves along ``axis`` -> their amplitude-weighted mean (that axis gone),
    in [-1, 1]; octave k has amplitude ``persistence**k``, summed in order."""
    octaves = layered.shape[axis]
    amplitudes, amplitude_sum = _octave_amplitudes(octaves, persistence)
    before = (slice(None),) * (axis % layered.ndim)
    total = layered[before + (0,)]  # amplitude 1
    for k in range(1, octaves):  # loop over octaves only, in order
        total = total + amplitudes[k] * layered[before + (k,)]
    return clamp(total / amplitude_sum, _MINUS_ONE, _ONE)


@functools.lru_cache(maxsize=64)
def _octave_amplitudes(octaves: int, persistence: float) -> tuple[tuple[np.ndarray, ...], np.ndarray]:
    """Each octave's amplitude ``persistence**k`` and their running sum, as 0-d float64 operands."""
    amplitudes = [persistence**k for k in range(octaves)]
    amplitude_sum = 1.0
    for amplitude in amplitudes[1:]:  # summed in the order sum_octaves always used
        amplitude_sum += amplitude
    return tuple(constant(a) for a in amplitudes), constant(amplitude_sum)


def fractal_unchecked(perm: np.ndarray, grads: np.ndarray, x: np.ndarray, y: np.ndarray, octaves: int,
                      persistence: float, lacunarity: float) -> np.ndarray:
    """:func:`fractal2d` without argument checks, for lattices from :func:`draw_lattice` held in state.

    Every octave is evaluated in one Perlin call on a trailing octave axis (the per-call NumPy
    overhead dominates for the few points a simulator samples each step); the octaves are then
    summed in order, so the result is identical to evaluating them one by one.
    """
    points = octave_points(x, y, octaves, lacunarity)
    lower = np.floor(points)
    return sum_octaves(blend_corners(*corner_gradients(perm, grads, lower), points - lower), persistence)
