"""Ocean Plastic Collection content: the pollution heat map, pebble sampling, vessel spawn points.

HIVEX samples floating plastic pebbles from a seeded pollution heat map (the paper shows 20 seeds
of heat map and vessel spawn positions); the map's construction, the pebble count and the spawn
rules are not published, so they are ours:

* :func:`pollution_map` -- fractal Perlin noise (:mod:`.noise`) stretched to [0, 1], sharpened by
  a power, plus Gaussian "hotspots", normalised into a probability over ``R x R`` cells.
* :func:`sample_pebbles` -- a cell by its heat (inverse CDF), then uniform within the cell.
* :func:`spawn_vessels` -- points a minimum spacing apart and away from the border (vectorised
  rejection sampling), with uniformly random headings.

Grid convention: the world is the square ``[-H, H]^2`` metres (``H`` the half extent), split into
``R x R`` square cells of side ``c = 2H / R`` metres. ``heat[b, i, j]`` is the cell with
``x in [-H + j c, -H + (j + 1) c)`` and ``y in [-H + i c, -H + (i + 1) c)``: the row index ``i``
increases with y, the column index ``j`` with x. Every random number comes from the caller's
``np.random.Generator``; every function works on a batch of ``B`` independent worlds at once.
"""

from __future__ import annotations

import math
import numbers
from typing import Literal

import numpy as np
from pydantic import Field, model_validator

from ...base import portable
from ...lang.spec.common import SCHEMA_VERSION, StrictModel
from .noise import draw_lattice, fractal2d, require_int
from .presets import load_preset

__all__ = ["PollutionSpec", "SpawnSpec", "PollutionPreset", "load_pollution_preset", "cell_size_m",
           "pollution_map", "sample_pebbles", "spawn_problem", "spawn_vessels"]

PRESET_FILE = "pollution.yaml"
HALF_EXTENT = Field(200.0, ge=10.0, le=10_000.0, description=(
    "[orig] Half the side of the square world in metres: the world is [-H, H]^2."))

# Spawn feasibility: n * spacing^2 may claim at most this fraction of the spawn square (see
# spawn_problem; a proof constant like procgen/layouts.py's, not a tunable).
_PACKING_FRACTION = 0.25


def _margin_below(spec: StrictModel, name: str) -> StrictModel:
    """``spec`` itself, or ValueError unless its margin ``name`` is below its ``half_extent_m``."""
    margin, half = getattr(spec, name), spec.half_extent_m
    if margin >= half:
        raise ValueError(f"{name} ({margin:g} m) must be smaller than half_extent_m ({half:g} m)")
    return spec


class PollutionSpec(StrictModel):
    """How a pollution heat map is built and how many pebbles float on it."""

    half_extent_m: float = HALF_EXTENT
    resolution: int = Field(64, ge=4, le=512, description=(
        "[ours] Cells per side R of the heat map grid; a cell is 2 H / R metres wide (6.25 m)."))
    noise_scale_m: float = Field(120.0, ge=1.0, le=100_000.0, description=(
        "[ours] Size of one noise lattice cell in metres (the size of the broad patches)."))
    noise_octaves: int = Field(3, ge=1, le=8, description="[ours] Octaves of the fractal background noise.")
    noise_persistence: float = Field(0.5, gt=0.0, le=1.0, description="[ours] Amplitude ratio between octaves.")
    contrast: float = Field(1.5, ge=0.0, le=16.0, description=(
        "[ours] Exponent p of the background (noise stretched to [0, 1])^p; larger concentrates patches. Fitted with "
        "pebble_count to the original's untrained records: the highest nearby count (25 m) its vessels passed, 104 a "
        "vessel-episode by Find Highest Polluted Area's first return, is 5.5 times their collection, 18.97; random "
        "play here passes 5.4 times it at 1.5 (4.5 on an even map, 5.9 at 2, 6.9 with the four hotspots first chosen: "
        "the reward table's supply note)."))
    hotspot_count: int = Field(0, ge=0, le=32, description=(
        "[ours] Gaussian hotspots added to the background; none by default (the fit of contrast: hotspots make the "
        "map's peaks, and a collector steering for them, richer than the original's records show)."))
    hotspot_weight: float = Field(2.0, ge=0.0, le=1_000.0, description=(
        "[ours] Peak heat of one hotspot relative to the background's maximum of 1."))
    hotspot_radius_m: float = Field(20.0, ge=1.0, le=10_000.0, description="[ours] Hotspot Gaussian sigma in metres.")
    hotspot_margin_m: float = Field(40.0, ge=0.0, le=10_000.0, description=(
        "[ours] Hotspot centres are uniform in [-(H - margin), H - margin]^2 metres."))
    pebble_count: int = Field(6000, ge=1, le=100_000, description=(
        "[orig] Plastic pebbles per episode, a fixed amount (the paper: not replaced). Fitted, in steps of 500, to "
        "the original's untrained policy, whose Local Reward (the vessel-episode's count) is 18.97: uniform random "
        "play collects 19.0 pebbles a vessel-episode here (the reward table's supply note)."))

    @model_validator(mode="after")
    def _margin_inside_world(self) -> "PollutionSpec":
        return _margin_below(self, "hotspot_margin_m")


class SpawnSpec(StrictModel):
    """Where vessels start: apart from each other, away from the border, any heading."""

    half_extent_m: float = HALF_EXTENT
    min_spacing_m: float = Field(30.0, ge=0.0, le=10_000.0, description="[ours] Minimum metres between two vessels.")
    border_margin_m: float = Field(20.0, ge=0.0, le=10_000.0, description=(
        "[ours] Minimum metres from a spawn point to the world border."))
    candidates_per_round: int = Field(64, ge=8, le=4096, description=(
        "[ours] Candidate points per world per rejection-sampling round."))
    max_rounds: int = Field(64, ge=1, le=10_000, description=(
        "[ours] Rejection-sampling rounds before spawn_vessels gives up with a ValueError."))

    @model_validator(mode="after")
    def _margin_inside_world(self) -> "SpawnSpec":
        return _margin_below(self, "border_margin_m")


class PollutionPreset(StrictModel):
    """generators/pollution.yaml: the defaults of both specs, as data."""

    hivex: Literal[SCHEMA_VERSION]
    generator: Literal["pollution"]
    pollution: PollutionSpec
    spawn: SpawnSpec

    @model_validator(mode="after")
    def _same_world(self) -> "PollutionPreset":
        if self.pollution.half_extent_m != self.spawn.half_extent_m:
            raise ValueError("pollution.half_extent_m and spawn.half_extent_m must be equal (one world)")
        return self


def load_pollution_preset() -> PollutionPreset:
    """generators/pollution.yaml validated as a :class:`PollutionPreset`."""
    return load_preset(PRESET_FILE, PollutionPreset)


def _require(name: str, value: object, kind: type) -> None:
    """ValueError unless ``value`` is an instance of ``kind``."""
    if not isinstance(value, kind):
        raise ValueError(f"{name} must be a {kind.__name__}, got {type(value).__name__}")


def _checked_heat(heat: object) -> np.ndarray:
    """``heat`` as a float64 (B, R, R) array of non-negative weights, each map with a positive sum."""
    heat = np.asarray(heat, dtype=np.float64)
    if heat.ndim != 3 or heat.shape[1] != heat.shape[2] or heat.shape[0] < 1 or heat.shape[1] < 1:
        raise ValueError(f"heat must have shape (B, R, R) with B, R >= 1, got {heat.shape}")
    if not np.isfinite(heat).all() or (heat < 0.0).any():
        raise ValueError("heat must be finite and non-negative")
    if not (heat.sum(axis=(1, 2)) > 0.0).all():
        raise ValueError("every heat map must have a positive sum (some cell with heat > 0)")
    return heat


# --- heat map ------------------------------------------------------------------------------------


def cell_size_m(half_extent_m: float, resolution: int) -> float:
    """Side of one heat-map cell in metres: ``2 H / R``."""
    return 2.0 * half_extent_m / resolution


def _cell_centres(spec: PollutionSpec) -> np.ndarray:
    """(R,) cell-centre coordinates in metres along either axis, increasing."""
    cell = cell_size_m(spec.half_extent_m, spec.resolution)
    return -spec.half_extent_m + (np.arange(spec.resolution) + 0.5) * cell


def _background(rng: np.random.Generator, spec: PollutionSpec, batch: int) -> np.ndarray:
    """(B, R, R) fractal noise stretched to [0, 1] per map, raised to the power ``contrast``."""
    perm, grads = draw_lattice(rng, batch)
    ys, xs = np.meshgrid(_cell_centres(spec), _cell_centres(spec), indexing="ij")
    x = np.broadcast_to(xs / spec.noise_scale_m, (batch,) + xs.shape)
    y = np.broadcast_to(ys / spec.noise_scale_m, (batch,) + ys.shape)
    noise = fractal2d(perm, grads, x, y, octaves=spec.noise_octaves, persistence=spec.noise_persistence)
    low, high = noise.min(axis=(1, 2), keepdims=True), noise.max(axis=(1, 2), keepdims=True)
    return portable.power((noise - low) / np.maximum(high - low, 1e-12), spec.contrast)


def _hotspots(rng: np.random.Generator, spec: PollutionSpec, batch: int) -> np.ndarray:
    """(B, R, R) sum of ``hotspot_count`` Gaussians of peak ``hotspot_weight`` at random centres."""
    reach = spec.half_extent_m - spec.hotspot_margin_m
    centres = rng.uniform(-reach, reach, size=(batch, spec.hotspot_count, 2))
    offsets = _cell_centres(spec)[None, None, :, None] - centres[:, :, None, :]  # (B, K, R, 2)
    profiles = portable.exp(-0.5 * (offsets / spec.hotspot_radius_m) ** 2)  # separable Gaussian factors
    # sum_k gy[b, k, i] * gx[b, k, j] as a batched matrix product: no (B, K, R, R) intermediate.
    return spec.hotspot_weight * np.matmul(profiles[..., 1].transpose(0, 2, 1), profiles[..., 0])


def pollution_map(rng: np.random.Generator, spec: PollutionSpec, batch: int = 1) -> np.ndarray:
    """Seeded pollution heat maps for ``batch`` (>= 1) independent worlds, all draws from ``rng``.

    Returns ``(B, R, R)`` float64, ``R = spec.resolution``: every entry >= 0, every map sums to 1.
    ``heat[b, i, j]`` is the probability of the cell of side ``2 H / R`` metres at row ``i``
    (y increasing) and column ``j`` (x increasing); see the module docstring.
    """
    _require("rng", rng, np.random.Generator)
    _require("spec", spec, PollutionSpec)
    batch = require_int("batch", batch, 1)
    heat = _background(rng, spec, batch) + _hotspots(rng, spec, batch)
    total = heat.sum(axis=(1, 2), keepdims=True)
    if not (total > 0.0).all():  # only with flat noise, contrast > 0 and no hotspots
        raise ValueError("a pollution map came out all zero; set contrast to 0 or add hotspots")
    return heat / total


# --- pebbles -------------------------------------------------------------------------------------


def _sample_cells(rng: np.random.Generator, heat: np.ndarray, count: int) -> np.ndarray:
    """(B, count) flat cell indices ``i * R + j`` drawn from each world's heat by inverse CDF; one
    ``searchsorted`` serves the batch, world ``b``'s CDF being offset into ``[b, b + 1]``."""
    batch = heat.shape[0]
    flat = heat.reshape(batch, -1)
    cells = flat.shape[1]
    cumulative = np.cumsum(flat, axis=1)
    cdf = cumulative / cumulative[:, -1:]  # non-decreasing, last entry exactly 1
    rows = np.arange(batch)[:, None]
    draws = rng.random((batch, count)) + rows
    local = np.searchsorted((cdf + rows).ravel(), draws.ravel(), side="right").reshape(batch, count)
    local -= rows * cells
    # Rounding can push a draw past its row's last positive cell; pull it back.
    last_positive = cells - 1 - np.argmax(flat[:, ::-1] > 0.0, axis=1)
    return np.clip(local, 0, last_positive[:, None])


def sample_pebbles(
    rng: np.random.Generator, heat: np.ndarray, count: int, half_extent_m: float
) -> np.ndarray:
    """``count`` (>= 1) pebbles per world: a cell by its heat, then uniform within the cell.

    ``heat`` is ``(B, R, R)`` non-negative cell weights (e.g. :func:`pollution_map`; each map is
    normalised by its own sum) over the world ``[-H, H]^2``, ``H = half_extent_m`` metres. Returns
    ``(B, count, 2)`` float64 (x, y) metres inside the world; a pebble of world ``b`` lies in cell
    ``(i, j)`` (row i along y) with probability ``heat[b, i, j] / heat[b].sum()``.
    """
    _require("rng", rng, np.random.Generator)
    heat = _checked_heat(heat)
    count = require_int("count", count, 1)
    if not (isinstance(half_extent_m, numbers.Real) and 0.0 < half_extent_m < math.inf):
        raise ValueError(f"half_extent_m must be a finite number > 0 (metres), got {half_extent_m!r}")
    resolution = heat.shape[1]
    row, column = np.divmod(_sample_cells(rng, heat, count), resolution)
    within = rng.random((heat.shape[0], count, 2))
    corner = np.stack([column, row], axis=-1)
    cell = cell_size_m(float(half_extent_m), resolution)
    return np.clip(-half_extent_m + (corner + within) * cell, -half_extent_m, half_extent_m)


# --- vessel spawn points -------------------------------------------------------------------------


def spawn_problem(spec: SpawnSpec, agents: int) -> str | None:
    """Why :func:`spawn_vessels` could fail for ``agents`` vessels, or None if it surely succeeds.

    Vessels spawn in ``[-L, L]^2``, ``L = H - border_margin_m``. If ``agents * min_spacing_m^2 <=
    1/4 (2 L)^2`` the discs of radius ``min_spacing_m`` around placed vessels cover at most pi/4
    of it, so each round places a vessel with probability >= ``1 - (pi/4)^candidates_per_round``.
    Raises ValueError if ``spec`` is not a :class:`SpawnSpec` or ``agents`` not an integer >= 1.
    """
    _require("spec", spec, SpawnSpec)
    agents = require_int("agents", agents, 1)
    reach = spec.half_extent_m - spec.border_margin_m
    claimed, allowed = agents * spec.min_spacing_m**2, _PACKING_FRACTION * (2.0 * reach) ** 2
    if agents > 1 and claimed > allowed:
        return (
            f"{agents} vessels {spec.min_spacing_m:g} m apart need agents x min_spacing_m^2 = "
            f"{claimed:g} m^2 <= 1/4 of the spawn square (2 x {reach:g} m)^2 = {allowed:g} m^2; "
            "lower min_spacing_m or border_margin_m, raise half_extent_m, or use fewer vessels")
    if agents > spec.max_rounds:
        return f"{agents} vessels need max_rounds >= {agents} (one vessel per round at worst), got {spec.max_rounds}"
    return None


def _pair_gaps2(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Squared distances (n, M, K) between points ``a`` (n, M, 2) and ``b`` (n, K, 2)."""
    return ((a[:, :, None, 0] - b[:, None, :, 0]) ** 2) + ((a[:, :, None, 1] - b[:, None, :, 1]) ** 2)


def _spawn_round(
    rng: np.random.Generator, spec: SpawnSpec, placed: np.ndarray, filled: np.ndarray, active: np.ndarray
) -> None:
    """One rejection-sampling round for the worlds ``active`` (n,), filling ``placed`` (B, A, 2) and
    ``filled`` (B,) in place. A candidate is kept if far enough from its world's placed vessels and
    from every *earlier* acceptable candidate of the round, so kept candidates are compatible."""
    agents, count = placed.shape[1], spec.candidates_per_round
    reach, spacing2 = spec.half_extent_m - spec.border_margin_m, spec.min_spacing_m**2
    candidates = rng.uniform(-reach, reach, size=(active.size, count, 2))
    used = np.arange(agents)[None, None, :] < filled[active][:, None, None]  # (n, 1, A)
    acceptable = ((_pair_gaps2(candidates, placed[active]) >= spacing2) | ~used).all(axis=2)
    earlier = np.tri(count, k=-1, dtype=bool)[None]  # earlier[., i, j]: j drawn before i
    clash = (_pair_gaps2(candidates, candidates) < spacing2) & earlier & acceptable[:, None, :]
    keep = acceptable & ~clash.any(axis=2)
    rank = np.cumsum(keep, axis=1) - 1
    take = keep & (rank < (agents - filled[active])[:, None])
    world, candidate = np.nonzero(take)
    placed[active[world], filled[active[world]] + rank[world, candidate]] = candidates[world, candidate]
    filled[active] += take.sum(axis=1)


def spawn_vessels(
    rng: np.random.Generator, spec: SpawnSpec, batch: int, agents: int
) -> tuple[np.ndarray, np.ndarray]:
    """Spawn points and headings of ``agents`` (A >= 1) vessels in each of ``batch`` (B >= 1) worlds.

    Returns ``positions`` (B, A, 2) float64 (x, y) metres in ``[-(H - margin), H - margin]^2``,
    every pair within a world at least ``min_spacing_m`` apart, and ``headings`` (B, A) float64
    radians, uniform in ``[-pi, pi)``, counter-clockwise from +x. Raises ValueError for bad
    arguments, an infeasible setting (:func:`spawn_problem`) or, with vanishing probability,
    ``max_rounds`` rounds not placing every vessel.
    """
    _require("rng", rng, np.random.Generator)
    problem = spawn_problem(spec, agents)
    if problem is not None:
        raise ValueError(problem)
    batch, agents = require_int("batch", batch, 1), int(agents)
    placed, filled = np.zeros((batch, agents, 2)), np.zeros(batch, dtype=np.int64)
    for _ in range(spec.max_rounds):  # bounded rounds; each round is whole-batch
        active = np.flatnonzero(filled < agents)
        if active.size == 0:
            break
        _spawn_round(rng, spec, placed, filled, active)
    if (filled < agents).any():
        raise ValueError(
            f"could not place {agents} vessels {spec.min_spacing_m:g} m apart in "
            f"{int((filled < agents).sum())} of {batch} worlds after {spec.max_rounds} rounds; "
            "raise max_rounds or candidates_per_round, or lower min_spacing_m")
    return placed, rng.uniform(-np.pi, np.pi, size=(batch, agents))
