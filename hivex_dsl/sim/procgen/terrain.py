"""Island height maps for Aerial Wildfire Suppression and Wildfire Resource Management.

The recipe is the original release's (ENVIRONMENTS.md, Aerial Wildfire Suppression, Terrain):
fractal Perlin noise mapped to [0, 1], a square island falloff subtracted, clamped to [0, 1],
the height curve t^2, times a height multiplier taken from the terrain level (1..10 -> 8..30).
The village sits on land within +/-450 m of the centre, on ground flattened to its height.

Grid convention: ``heights[i, j]`` is the height at ``x = -extent/2 + j * cell`` and
``y = -extent/2 + i * cell`` (column index j grows with x, row index i grows with y); the first
and last rows and columns lie on the map border. Lengths and heights are metres.
"""

from __future__ import annotations

import numbers
from dataclasses import dataclass
from typing import Literal

import numpy as np
from pydantic import Field, model_validator

from ...base import portable
from ...base.errors import is_integer
from ...lang.spec.common import SCHEMA_VERSION, StrictModel
from .noise import draw_lattice, fractal2d
from .presets import load_preset

PRESET_FILE = "terrain.yaml"


class TerrainSpec(StrictModel):
    """Constants of one height map; :func:`terrain_spec_for_level` sets ``height_multiplier``."""

    size: int = Field(241, ge=3, le=2049, description=(
        "[orig] Grid cells per side of the height map: 241 in Aerial Wildfire Suppression's release, its noise map "
        "of mapChunkSize 239 + 2."))
    extent_m: float = Field(1666.0, ge=10.0, le=100_000.0, description=(
        "[orig] Side of the square map in metres: 1,666 in Aerial Wildfire Suppression's release, whose mesh spans "
        "238 units of its noise map, scaled by its TerrainData asset's uniformScale 7."))
    noise_scale: float = Field(40.0, ge=1.0, le=10_000.0, description=(
        "[orig] Perlin scale: the noise is sampled at (cell index / noise_scale), so it is grid cells per lattice unit."))
    noise_period: int = Field(256, ge=2, le=4096, description="[ours] Period of the random noise lattice, in lattice units.")
    octaves: int = Field(4, ge=1, le=8, description="[orig] Octaves of the fractal noise.")
    persistence: float = Field(0.3, gt=0.0, le=1.0, description="[orig] Amplitude ratio between successive octaves.")
    lacunarity: float = Field(2.2, ge=1.0, le=4.0, description="[orig] Frequency ratio between successive octaves.")
    falloff_a: float = Field(5.0, gt=0.0, le=20.0, description="[orig] Exponent a of the island falloff v^a / (v^a + (b - b v)^a).")
    falloff_b: float = Field(2.5, gt=0.0, le=20.0, description="[orig] Factor b of the island falloff; larger b means a wider island.")
    height_exponent: float = Field(2.0, ge=0.5, le=8.0, description=(
        "[orig] The height curve t^p applied after the falloff: Aerial Wildfire Suppression's release draws its "
        "meshHeightCurve, keys (0, 0) with slope 0 and (1, 1) with slope 2, whose Hermite cubic is t^2 exactly."))
    height_multiplier: int = Field(8, ge=1, le=100, description=(
        "[orig] Height multiplier, 8..30 for terrain levels 1..10 (height_multiplier_for_level); the default is level 1's."))
    metres_per_multiplier: float = Field(7.0, gt=0.0, le=100.0, description=(
        "[orig] Metres of peak height per multiplier unit: 7 in Aerial Wildfire Suppression's release, whose "
        "TerrainData asset scales its mesh by uniformScale 7 on every axis, so 8 x 7 = 56 m peaks at level 1 and "
        "30 x 7 = 210 m at level 10, the peaks ENVIRONMENTS.md reports (its reward table's note 'The release's "
        "terrain assets')."))
    village_half_range_m: float = Field(450.0, ge=0.0, le=50_000.0, description=(
        "[orig] The village lies within +/- this of the centre in x and in y."))
    village_flat_radius_m: float = Field(60.0, ge=0.0, le=10_000.0, description=(
        "[ours] Ground within this distance of the village is exactly at the village cell's height."))
    village_blend_m: float = Field(40.0, ge=0.0, le=10_000.0, description=(
        "[ours] Width of the smooth ramp from the flattened ground back to the untouched terrain."))
    village_tries: int = Field(64, ge=1, le=4096, description=(
        "[ours] Uniform village candidates drawn; if none is on land the highest cell in range is used."))
    sea_level_m: float = Field(0.0, ge=0.0, le=1_000.0, description=(
        "[ours] Cells at or below this height are sea; the recipe's clamp puts open sea at exactly 0 m."))

    @model_validator(mode="after")
    def _village_inside(self) -> "TerrainSpec":
        reach = self.village_half_range_m + self.village_flat_radius_m + self.village_blend_m
        if reach >= self.extent_m / 2:
            raise ValueError(
                f"village_half_range_m + village_flat_radius_m + village_blend_m ({reach:g} m) must be less "
                f"than half the extent ({self.extent_m / 2:g} m) so the flattening never reaches the border")
        return self


class LevelMapping(StrictModel):
    """Terrain level -> height multiplier, linear and rounded (ENVIRONMENTS.md)."""

    levels: int = Field(10, ge=2, le=100, description="[orig] Terrain levels run 1..levels.")
    first_multiplier: int = Field(8, ge=1, le=100, description="[orig] Height multiplier at level 1.")
    last_multiplier: int = Field(30, ge=1, le=100, description="[orig] Height multiplier at the last level.")


LEVELS = LevelMapping()


def height_multiplier_for_level(level: int, mapping: LevelMapping = LEVELS) -> int:
    """round(first + (level - 1) * (last - first) / (levels - 1)); 8, 10, 13, ..., 30 by default."""
    if not is_integer(level):
        raise ValueError(f"terrain level must be an integer, got {level!r}")
    if not 1 <= level <= mapping.levels:
        raise ValueError(f"terrain level must be in 1..{mapping.levels}, got {level}")
    span = mapping.last_multiplier - mapping.first_multiplier
    return int(round(mapping.first_multiplier + (int(level) - 1) * span / (mapping.levels - 1)))


def terrain_spec_for_level(level: int, **overrides: object) -> TerrainSpec:
    """:class:`TerrainSpec` with the level's height multiplier and any other field overridden."""
    if "height_multiplier" in overrides:
        raise ValueError("height_multiplier is set by the terrain level; do not override it as well")
    return TerrainSpec(height_multiplier=height_multiplier_for_level(level), **overrides)


class TerrainPreset(StrictModel):
    """generators/terrain.yaml: the TerrainSpec defaults and the multiplier of every level."""

    hivex: Literal[SCHEMA_VERSION]
    generator: Literal["terrain"]
    defaults: TerrainSpec
    level_height_multipliers: list[int] = Field(min_length=2, max_length=100, description=(
        "Height multiplier of terrain levels 1, 2, ... in order."))


def load_terrain_preset() -> TerrainPreset:
    """generators/terrain.yaml validated as a :class:`TerrainPreset` (located errors)."""
    return load_preset(PRESET_FILE, TerrainPreset)


def _frozen(array: np.ndarray) -> np.ndarray:
    """A read-only float64 copy of ``array``."""
    copy = np.array(array, dtype=np.float64)
    copy.setflags(write=False)
    return copy


@dataclass(frozen=True)
class Terrain:
    """A height map: ``heights`` (n, n) float64 metres (grid convention in the module docstring),
    ``cell_m`` grid spacing in metres, ``extent_m`` = cell_m * (n - 1) side length in metres,
    ``village`` (2,) float64 village position (x, y) in metres. Arrays are read-only copies."""

    heights: np.ndarray
    cell_m: float
    extent_m: float
    village: np.ndarray

    def __post_init__(self) -> None:
        heights, village = np.asarray(self.heights), np.asarray(self.village)
        if heights.ndim != 2 or heights.shape[0] != heights.shape[1] or heights.shape[0] < 2:
            raise ValueError(f"heights must be a square (n, n) array with n >= 2, got shape {heights.shape}")
        if not np.isfinite(heights).all():
            raise ValueError("heights must be finite")
        if not (isinstance(self.cell_m, numbers.Real) and np.isfinite(self.cell_m) and self.cell_m > 0):
            raise ValueError(f"cell_m must be a positive finite number, got {self.cell_m!r}")
        expected = self.cell_m * (heights.shape[0] - 1)
        if not isinstance(self.extent_m, numbers.Real) or not np.isclose(self.extent_m, expected, rtol=1e-9, atol=0.0):
            raise ValueError(f"extent_m must equal cell_m * (n - 1) = {expected:g}, got {self.extent_m!r}")
        if village.shape != (2,) or not np.isfinite(village).all():
            raise ValueError(f"village must be a finite (2,) array, got shape {village.shape}")
        object.__setattr__(self, "heights", _frozen(heights))
        object.__setattr__(self, "village", _frozen(village))

    @property
    def coords(self) -> np.ndarray:
        """(n,) float64 metres: x of column j and y of row i, ``-extent/2 + index * cell``."""
        return -self.extent_m / 2 + np.arange(self.heights.shape[0]) * self.cell_m

    def _cell_of(self, xy: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Lower corner indices (..., 2) as (j, i), offsets (..., 2) in [0, 1], inside mask (..., 2)."""
        xy = np.asarray(xy, dtype=np.float64)
        if xy.ndim < 1 or xy.shape[-1] != 2:
            raise ValueError(f"points must have shape (..., 2), got {xy.shape}")
        if not np.isfinite(xy).all():
            raise ValueError("points must be finite")
        last = self.heights.shape[0] - 1
        index = (xy + self.extent_m / 2) / self.cell_m
        inside = (index >= 0.0) & (index <= last)
        index = np.clip(index, 0.0, last)
        lower = np.minimum(np.floor(index), last - 1).astype(np.int64)
        return lower, index - lower, inside

    def _corners(self, lower: np.ndarray) -> tuple[np.ndarray, ...]:
        """Heights at the four corners (j, i), (j+1, i), (j, i+1), (j+1, i+1) of each cell."""
        j, i, h = lower[..., 0], lower[..., 1], self.heights
        return h[i, j], h[i, j + 1], h[i + 1, j], h[i + 1, j + 1]

    def height_at(self, xy: np.ndarray) -> np.ndarray:
        """Bilinear height (...) in metres at points ``xy`` (..., 2) metres, clamped at the border."""
        lower, frac, _ = self._cell_of(xy)
        z00, z10, z01, z11 = self._corners(lower)
        tx, ty = frac[..., 0], frac[..., 1]
        low, high = z00 + tx * (z10 - z00), z01 + tx * (z11 - z01)
        return low + ty * (high - low)

    def slope_at(self, xy: np.ndarray) -> np.ndarray:
        """Gradient (dz/dx, dz/dy) (..., 2), metres per metre, of the bilinear surface at ``xy`` (..., 2).

        Outside the map the clamped surface is flat along the clamped axis, so that component is 0.
        """
        lower, frac, inside = self._cell_of(xy)
        z00, z10, z01, z11 = self._corners(lower)
        tx, ty = frac[..., 0], frac[..., 1]
        dzdx = ((1.0 - ty) * (z10 - z00) + ty * (z11 - z01)) / self.cell_m
        dzdy = ((1.0 - tx) * (z01 - z00) + tx * (z11 - z10)) / self.cell_m
        return np.stack([dzdx, dzdy], axis=-1) * inside


def _island(rng: np.random.Generator, spec: TerrainSpec) -> np.ndarray:
    """The raw (size, size) height map in metres, before the village is flattened.

    The noise is min-max normalised over the map (a map-local mapping onto [0, 1]), as the
    release's NoiseData asset asks (normalizeMode Local: InverseLerp over the map's lowest and
    highest noise); with the fixed mapping (n + 1) / 2 the peaks would stay near 36 m at level 1
    instead of the 56 m the original shows, because fractal noise seldom nears +/-1.
    """
    n = spec.size
    index = np.arange(n) / spec.noise_scale
    x = np.broadcast_to(index[None, None, :], (1, n, n))
    y = np.broadcast_to(index[None, :, None], (1, n, n))
    perm, grads = draw_lattice(rng, 1, spec.noise_period)
    noise = fractal2d(perm, grads, x, y, spec.octaves, spec.persistence, spec.lacunarity)[0]
    span = noise.max() - noise.min()
    value = (noise - noise.min()) / span if span > 0 else np.zeros_like(noise)
    return island_heights(value, np.abs(np.linspace(-1.0, 1.0, n)), spec)


def island_heights(value: np.ndarray, edge: np.ndarray, spec: TerrainSpec) -> np.ndarray:
    """(n, n) metres from the normalised noise ``value`` (n, n) in [0, 1]: the square island falloff subtracted,
    clamped to [0, 1], the height curve and the multiplier's metres. ``edge`` (n,) is each row's and column's
    distance from the centre in [0, 1] (the falloff reads their larger)."""
    v = np.maximum(edge[None, :], edge[:, None])
    a, b = spec.falloff_a, spec.falloff_b
    rising = portable.power(v, a)
    falloff = rising / (rising + portable.power(b - b * v, a))
    t = np.clip(value - falloff, 0.0, 1.0)
    return portable.power(t, spec.height_exponent) * (spec.height_multiplier * spec.metres_per_multiplier)


def _place_village(rng: np.random.Generator, raw: Terrain, spec: TerrainSpec) -> np.ndarray:
    """(2,) metres: the first of ``village_tries`` uniform candidates whose nearest cell is land,
    else the highest cell within the range. Always draws the same amount of randomness."""
    reach = spec.village_half_range_m
    candidates = rng.uniform(-reach, reach, size=(spec.village_tries, 2))
    nearest = np.rint((candidates + raw.extent_m / 2) / raw.cell_m).astype(np.int64)
    land = raw.heights[nearest[:, 1], nearest[:, 0]] > spec.sea_level_m
    if land.any():
        return candidates[np.argmax(land)]
    in_range = np.flatnonzero(np.abs(raw.coords) <= reach)
    if in_range.size == 0:
        in_range = np.array([np.argmin(np.abs(raw.coords))])
    block = raw.heights[np.ix_(in_range, in_range)]
    i, j = np.unravel_index(np.argmax(block), block.shape)
    return raw.coords[[in_range[j], in_range[i]]]


def _flatten(raw: Terrain, village: np.ndarray, spec: TerrainSpec) -> np.ndarray:
    """(size, size) heights with ground at the village cell's height within the flat radius,
    blending back to ``raw`` over ``village_blend_m`` with a smoothstep of the distance."""
    j, i = np.rint((village + raw.extent_m / 2) / raw.cell_m).astype(np.int64)
    level = raw.heights[i, j]
    c = raw.coords
    distance = np.hypot(c[None, :] - village[0], c[:, None] - village[1])
    beyond = distance - spec.village_flat_radius_m
    if spec.village_blend_m > 0:
        t = np.clip(beyond / spec.village_blend_m, 0.0, 1.0)
        weight = 1.0 - t * t * (3.0 - 2.0 * t)
    else:
        weight = (beyond <= 0.0).astype(np.float64)
    return raw.heights + weight * (level - raw.heights)


def generate_terrain(rng: np.random.Generator, spec: TerrainSpec) -> Terrain:
    """A fresh height map and village; pure (the same ``rng`` state gives identical arrays).

    Draws, in order, the noise lattice and ``spec.village_tries`` village candidates from ``rng``.
    """
    if not isinstance(rng, np.random.Generator):
        raise ValueError(f"rng must be a numpy.random.Generator, got {type(rng).__name__}")
    if not isinstance(spec, TerrainSpec):
        raise ValueError(f"spec must be a TerrainSpec, got {type(spec).__name__}")
    cell = spec.extent_m / (spec.size - 1)
    raw = Terrain(_island(rng, spec), cell, spec.extent_m, np.zeros(2))
    village = _place_village(rng, raw, spec)
    return Terrain(_flatten(raw, village, spec), cell, spec.extent_m, village)
