"""Weather for Aerial Wildfire Suppression and Wildfire Resource Management, batched over worlds.

Temperature, humidity and overcast are smooth fractal noise fields with values in [0, 1] that
drift with the main wind direction (ENVIRONMENTS.md, Aerial Wildfire Suppression: Weather).
Each field of each world has its own random noise lattice; a field value at a point is
``clip(mean + contrast * noise((point - offset) / noise_scale_m), 0, 1)`` and every step adds
``drift_m_per_step * (cos, sin)(wind main direction)`` to the world's offset, so the pattern
moves with the wind. Lengths are metres, angles radians (the direction the wind blows *to*).
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import lru_cache
from typing import Any, Literal

import numpy as np
from pydantic import Field

from ...base.numeric import all_true, clamp
from ...lang.spec.common import SCHEMA_VERSION, StrictModel
from ..batching import assemble
from .noise import blend_corners, draw_lattice, octave_frequencies, sum_octaves
from .presets import load_preset

PRESET_FILE = "weather.yaml"
FIELDS = ("temperature", "humidity", "overcast")


def _mean(name: str) -> Any:
    return Field(0.5, ge=0.0, le=1.0, description=(
        f"[ours] Mean {name} (dimensionless, 0..1); the AWS release's field reads 0.465 where its noise is 0 "
        "(Unity's Mathf.PerlinNoise, (noise + 0.69) / 1.483: the reward tables' note 'The release's weather')."))


def _contrast(name: str) -> Any:
    return Field(0.8, ge=0.0, le=2.0, description=(
        f"[ours] {name.capitalize()} at noise value +/-1 is mean +/- contrast, clipped to [0, 1]; the AWS "
        "release's one octave spreads as a contrast of about 0.56 does on this noise (a standard deviation of "
        "about 0.17)."))


class WeatherSpec(StrictModel):
    """Constants of the weather fields."""

    noise_scale_m: float = Field(500.0, ge=1.0, le=100_000.0, description=(
        "[ours] Size of one weather noise lattice cell in metres: fronts a few hundred metres across. The AWS "
        "release's scene: about 930 m for temperature and humidity, 280 m for overcast (one scale here for all)."))
    noise_period: int = Field(256, ge=2, le=4096, description="[ours] Period of the noise lattice, in lattice cells.")
    octaves: int = Field(2, ge=1, le=8, description="[ours] Octaves of the weather noise (the AWS release: 1).")
    persistence: float = Field(0.5, gt=0.0, le=1.0, description="[ours] Amplitude ratio between successive octaves.")
    lacunarity: float = Field(2.0, ge=1.0, le=4.0, description="[ours] Frequency ratio between successive octaves.")
    drift_m_per_step: float = Field(1.0, ge=0.0, le=1_000.0, description=(
        "[ours] Metres the weather fields move along the main wind direction per step (as the wind noise). The "
        "AWS release moves them 0.001 noise units a rendered frame, about 0.056 m an academy step (0.017 m for "
        "overcast), and never draws them anew: one field for the whole run."))
    temperature_mean: float = _mean("temperature")
    temperature_contrast: float = _contrast("temperature")
    humidity_mean: float = _mean("humidity")
    humidity_contrast: float = _contrast("humidity")
    overcast_mean: float = _mean("overcast")
    overcast_contrast: float = _contrast("overcast")


class WeatherPreset(StrictModel):
    """generators/weather.yaml: the WeatherSpec defaults (Wildfire Resource Management's), and the AWS release's
    weather as this generator reads it (``release``, Aerial Wildfire Suppression's default: the reward tables' note
    'The release's weather')."""

    hivex: Literal[SCHEMA_VERSION]
    generator: Literal["weather"]
    defaults: WeatherSpec
    release: WeatherSpec


def load_weather_preset() -> WeatherPreset:
    """generators/weather.yaml validated as a :class:`WeatherPreset` (located errors)."""
    return load_preset(PRESET_FILE, WeatherPreset)


@dataclass(frozen=True)
class WeatherState:
    """Weather of ``B`` worlds with ``F = len(FIELDS)`` fields and lattice period ``P``.

    perm: (F, B, 2P) int64 and grads: (F, B, P, 2) float64, the noise lattice of field f in
    world b at ``[f, b]`` (fields in :data:`FIELDS` order); offsets: (B, 2) float64 metres, how
    far each world's fields have moved since reset.
    """

    perm: np.ndarray
    grads: np.ndarray
    offsets: np.ndarray

    def __post_init__(self) -> None:
        fields, batch = len(FIELDS), self.offsets.shape[0] if self.offsets.ndim == 2 else -1
        if self.offsets.ndim != 2 or self.offsets.shape[1] != 2:
            raise ValueError(f"offsets must have shape (B, 2), got {self.offsets.shape}")
        if self.grads.ndim != 4 or self.grads.shape[:2] != (fields, batch) or self.grads.shape[3] != 2:
            raise ValueError(f"grads must have shape ({fields}, {batch}, P, 2), got {self.grads.shape}")
        if self.perm.shape != (fields, batch, 2 * self.grads.shape[2]):
            raise ValueError(f"perm must have shape ({fields}, {batch}, 2P), got {self.perm.shape}")


def _check_batch(name: str, array: object, batch: int, tail: tuple[int, ...]) -> np.ndarray:
    """``array`` as finite float64 of shape (batch, *tail) (a -1 in tail means any size)."""
    array = np.asarray(array, dtype=np.float64)
    shape_ok = array.ndim == 1 + len(tail) and array.shape[0] == batch
    shape_ok = shape_ok and all(t in (-1, s) for t, s in zip(tail, array.shape[1:]))
    if not shape_ok:
        wanted = ", ".join(["B"] + ["N" if t == -1 else str(t) for t in tail])
        raise ValueError(f"{name} must have shape ({wanted}) with B = {batch}, got {array.shape}")
    if not np.isfinite(array).all():
        raise ValueError(f"{name} must be finite")
    return array


def weather_reset(rng: np.random.Generator, batch: int, spec: WeatherSpec) -> WeatherState:
    """Fresh weather for ``batch`` worlds: one lattice per field and world, zero offsets.

    Draws one :func:`~hivex_dsl.sim.procgen.noise.draw_lattice` of ``F * batch`` rows (field-major).
    """
    perm, grads = draw_lattice(rng, len(FIELDS) * batch, spec.noise_period)
    period = spec.noise_period
    return WeatherState(perm=perm.reshape(len(FIELDS), batch, 2 * period),
                        grads=grads.reshape(len(FIELDS), batch, period, 2), offsets=np.zeros((batch, 2)))


def weather_reset_where(state: WeatherState, mask: np.ndarray, rng: np.random.Generator,
                        spec: WeatherSpec) -> WeatherState:
    """Replace the weather of the worlds where ``mask`` (B,) bool is true by fresh draws."""
    mask = np.asarray(mask)
    if mask.dtype != np.bool_ or mask.shape != state.offsets.shape[:1]:
        raise ValueError(f"mask must be a bool array of shape {state.offsets.shape[:1]}, got {mask.dtype} {mask.shape}")
    fresh = weather_reset(rng, int(np.count_nonzero(mask)), spec)
    perm, grads, offsets = state.perm.copy(), state.grads.copy(), state.offsets.copy()
    perm[:, mask], grads[:, mask], offsets[mask] = fresh.perm, fresh.grads, fresh.offsets
    return WeatherState(perm=perm, grads=grads, offsets=offsets)


def weather_step(state: WeatherState, wind_main: np.ndarray, spec: WeatherSpec) -> WeatherState:
    """Move every world's fields ``drift_m_per_step`` metres along its main wind ``wind_main`` (B,) radians."""
    angle = np.asarray(wind_main, dtype=np.float64)
    if angle.shape != state.offsets.shape[:1]:
        raise ValueError(f"wind_main must have shape (B,) with B = {state.offsets.shape[0]}, got {angle.shape}")
    if not all_true(np.isfinite(angle)):
        raise ValueError("wind_main must be finite")
    heading = np.empty(state.offsets.shape)
    np.cos(angle, out=heading[:, 0])
    np.sin(angle, out=heading[:, 1])
    heading *= spec.drift_m_per_step
    heading += state.offsets
    # the lattice is the valid state's and the offsets keep their shape: no checks to repeat
    return assemble(WeatherState, perm=state.perm, grads=state.grads, offsets=heading)


def weather_at(state: WeatherState, points: np.ndarray, spec: WeatherSpec) -> dict[str, np.ndarray]:
    """Weather at ``points`` (B, N, 2) metres: {temperature, humidity, overcast} -> (B, N) in [0, 1]."""
    points = _check_batch("points", points, state.offsets.shape[0], (-1, 2))
    return dict(zip(FIELDS, weather_fields(state, points, spec)))


def weather_fields(state: WeatherState, points: np.ndarray, spec: WeatherSpec) -> np.ndarray:
    """(F, B, N) float64 fields in :data:`FIELDS` order at finite ``points`` (B, N, 2) metres (unchecked).

    Each field is the fractal Perlin noise of :func:`~hivex_dsl.sim.procgen.noise.fractal_unchecked` on its own
    lattice, with the same floating-point operations; the fields share their sample points, so where the
    points fall in the lattice (cells, offsets, fades) is worked out once for all three. Arrays keep the x/y
    and octave axes first, so every operation runs along the long (B, N) axes.
    """
    moved = (points - state.offsets[:, None, :]) / spec.noise_scale_m
    frequencies = octave_frequencies(spec.octaves, spec.lacunarity)  # (K, 1)
    lattice = np.multiply(moved.transpose(2, 0, 1)[:, None], frequencies[..., None], order="C")  # (2, K, B, N)
    lower = np.floor(lattice)
    gx, gy = _corner_gradients(state.perm, state.grads, lower)  # (4, F, K, B, N) each
    noise = sum_octaves(blend_corners(gx, gy, lattice - lower), spec.persistence, axis=1)  # (F, B, N)
    means, contrasts = _field_constants(*(getattr(spec, f"{name}_{part}") for part in ("mean", "contrast")
                                          for name in FIELDS))
    return clamp(means + contrasts * noise, 0.0, 1.0)


@lru_cache(maxsize=64)
def _field_constants(*values: float) -> tuple[np.ndarray, np.ndarray]:
    """(F, 1, 1) float64 means and contrasts of the fields (``values``: the F means, then the F contrasts),
    shaped to scale (F, B, N) noise; read-only."""
    means, contrasts = np.array(values).reshape(2, -1, 1, 1)
    means.flags.writeable = contrasts.flags.writeable = False
    return means, contrasts


@lru_cache(maxsize=64)
def _lattice_rows(fields: int, batch: int, period: int) -> tuple[np.ndarray, np.ndarray]:
    """(F, 1, B, 1) int64 offsets of each field and world's rows in the flat perm (2P per row) and grads
    (P per row) tables, shaped for (F, K, B, N) lookups; read-only."""
    rows = np.arange(fields * batch).reshape(fields, 1, batch, 1) * period
    perm_rows, grad_rows = 2 * rows, rows
    perm_rows.flags.writeable = grad_rows.flags.writeable = False
    return perm_rows, grad_rows


def _corner_gradients(perm: np.ndarray, grads: np.ndarray, lower: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Gradient components (4, F, K, B, N) at the corners (0, 0), (1, 0), (0, 1), (1, 1) of the lattice cells
    with lower-left corners ``lower`` (2, K, B, N), from every field's lattice perm (F, B, 2P), grads
    (F, B, P, 2): :func:`~hivex_dsl.sim.procgen.noise.corner_gradients` with the cell indices computed once."""
    fields, batch, period = grads.shape[:3]
    perm_rows, grad_rows = _lattice_rows(fields, batch, period)
    cell = _cell_indices(lower, period)  # (2 lower/next, 2 x/y, K, B, N)
    flat_perm = perm.reshape(-1)
    hashed_x = flat_perm.take(perm_rows + cell[:, None, 0])  # (2 x, F, K, B, N)
    hashed_x += perm_rows
    # (2 y, 2 x, F, K, B, N) -> (4, ...): corner 2 * y + x, the order (0, 0), (1, 0), (0, 1), (1, 1)
    corner = (hashed_x[None] + cell[:, None, None, 1]).reshape((4,) + hashed_x.shape[1:])
    gradient = flat_perm.take(corner)
    gradient += grad_rows
    both = grads.reshape(-1, 2).take(gradient, axis=0)
    return both[..., 0], both[..., 1]


def _cell_indices(lower: np.ndarray, period: int) -> np.ndarray:
    """(2, ...) int64 lattice indices mod ``period`` of the lower corners ``lower`` (...) (integral floats),
    then of the next cells: ``np.mod(lower, period).astype(np.int64)`` and that plus one, mod ``period``.

    Integral floats within +/-2^62 convert to int64 exactly, and integer remainders (a mask for a power of
    two) are the float ones, only much cheaper on many points; beyond that the float remainder is taken.
    """
    cell = np.empty((2,) + lower.shape, np.int64)
    if np.maximum.reduce(lower, axis=None) < 2.0**62 and np.minimum.reduce(lower, axis=None) > -(2.0**62):
        cell[0] = lower  # exact: an integral float of this size
        _remainder(cell[0], period)
    else:
        cell[0] = np.mod(lower, period)
    np.add(cell[0], 1, out=cell[1])
    _remainder(cell[1], period)
    return cell


def _remainder(values: np.ndarray, period: int) -> None:
    """``values %= period`` in place for int64 ``values`` (>= 0 for either sign, as NumPy's %): a mask when
    ``period`` is a power of two (two's complement makes it the same), far cheaper than a division."""
    if period & (period - 1) == 0:
        np.bitwise_and(values, period - 1, out=values)
    else:
        np.remainder(values, period, out=values)
