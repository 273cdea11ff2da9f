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
from typing import Any, Literal

import numpy as np
from pydantic import Field

from ..spec.common import SCHEMA_VERSION, StrictModel
from .noise import clamp, draw_lattice, fractal_unchecked
from .presets import load_preset

PRESET_FILE = "weather.yaml"
FIELDS = ("temperature", "humidity", "overcast")


def _mean(name: str) -> Any:
    return Field(0.5, ge=0.0, le=1.0, description=f"[ours] Mean {name} (dimensionless, 0..1).")


def _contrast(name: str) -> Any:
    return Field(0.8, ge=0.0, le=2.0, description=(
        f"[ours] {name.capitalize()} at noise value +/-1 is mean +/- contrast, clipped to [0, 1]."))


class WeatherSpec(StrictModel):
    """Constants of the weather fields."""

    noise_scale_m: float = Field(500.0, ge=1.0, le=100_000.0, description=(
        "[ours] Size of one weather noise lattice cell in metres: fronts a few hundred metres across."))
    noise_period: int = Field(256, ge=2, le=4096, description="[ours] Period of the noise lattice, in lattice cells.")
    octaves: int = Field(2, ge=1, le=8, description="[ours] Octaves of the weather noise.")
    persistence: float = Field(0.5, gt=0.0, le=1.0, description="[ours] Amplitude ratio between successive octaves.")
    lacunarity: float = Field(2.0, ge=1.0, le=4.0, description="[ours] Frequency ratio between successive octaves.")
    drift_m_per_step: float = Field(1.0, ge=0.0, le=1_000.0, description=(
        "[ours] Metres the weather fields move along the main wind direction per step (as the wind noise)."))
    temperature_mean: float = _mean("temperature")
    temperature_contrast: float = _contrast("temperature")
    humidity_mean: float = _mean("humidity")
    humidity_contrast: float = _contrast("humidity")
    overcast_mean: float = _mean("overcast")
    overcast_contrast: float = _contrast("overcast")


class WeatherPreset(StrictModel):
    """generators/weather.yaml: the WeatherSpec defaults."""

    hivex: Literal[SCHEMA_VERSION]
    generator: Literal["weather"]
    defaults: WeatherSpec


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

    Draws one :func:`~hivex_dsl.procgen.noise.draw_lattice` of ``F * batch`` rows (field-major).
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
    heading = np.empty(state.offsets.shape)
    np.cos(angle, out=heading[:, 0])
    np.sin(angle, out=heading[:, 1])
    return WeatherState(perm=state.perm, grads=state.grads, offsets=state.offsets + spec.drift_m_per_step * heading)


def weather_at(state: WeatherState, points: np.ndarray, spec: WeatherSpec) -> dict[str, np.ndarray]:
    """Weather at ``points`` (B, N, 2) metres: {temperature, humidity, overcast} -> (B, N) in [0, 1]."""
    fields, batch = len(FIELDS), state.offsets.shape[0]
    points = _check_batch("points", points, batch, (-1, 2))
    moved = (points - state.offsets[:, None, :]) / spec.noise_scale_m
    shape = (fields * batch, points.shape[1])
    x = np.broadcast_to(moved[None, ..., 0], (fields,) + moved.shape[:2]).reshape(shape)
    y = np.broadcast_to(moved[None, ..., 1], (fields,) + moved.shape[:2]).reshape(shape)
    noise = fractal_unchecked(state.perm.reshape(fields * batch, -1), state.grads.reshape(fields * batch, -1, 2),
                      x, y, spec.octaves, spec.persistence, spec.lacunarity).reshape((fields,) + moved.shape[:2])
    return {name: clamp(getattr(spec, f"{name}_mean") + getattr(spec, f"{name}_contrast") * noise[k], 0.0, 1.0)
            for k, name in enumerate(FIELDS)}
