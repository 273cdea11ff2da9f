"""Drone-Based Reforestation's existing forest: patches of a noise field of its own around the station.

The shared forest rule (:mod:`hivex_dsl.sim.procgen.forest`, Aerial Wildfire Suppression's) grows trees in a band of
terrain heights; on this world's terrain that makes the forest's patchiness grow with the terrain level, since the
hills do (the reward table's note "Drop quality near the station"). Here the trees follow a patch field independent of
the terrain's heights, so every level draws the same kind of forest: fractal Perlin noise over the world, min-max
normalised over the land outside the station's clearing, plus a rise with the distance from the station, so the forest
thins towards the station without a ring. A tree grows where that suitability exceeds ``patch_threshold``, its density
rising linearly over ``patch_ramp`` to ``patch_density``; on land only (terrain above sea level); none within
``station_clear_radius_m`` of the station. The placement itself (jitter, draws, grid) is the shared
:func:`~hivex_dsl.sim.procgen.forest.place_forest`, handed the suitability as its "height" and a band
(:meth:`ReforestationForestSpec.placement_spec`) that gives the density above, so the shared generator is unchanged.
Lengths are metres.
"""

from __future__ import annotations

import numpy as np
from pydantic import Field, model_validator

from ...lang.spec.common import StrictModel
from ...sim.procgen.forest import Forest, ForestSpec, cell_centre_xy, check_forest_grid, place_forest
from ...sim.procgen.noise import draw_lattice, fractal2d
from ...sim.procgen.terrain import Terrain

NOISE_PERIOD = 256  # lattice units; the world spans 400 m / patch_scale_m of them, far fewer
NOISE_OFFSET = 0.5 * NOISE_PERIOD  # the world's centre sits mid-lattice, away from the lattice's seams
PERSISTENCE, LACUNARITY = 0.5, 2.0
OFF_LAND = -1.0  # suitability of ground at or below sea level: below any threshold


class ReforestationForestSpec(StrictModel):
    """Where the existing trees of a Drone-Based Reforestation world grow: the grid and the patch field."""

    cells: int = Field(100, ge=1, le=4000, description="[ours] Grid cells per side; at most one tree per cell.")
    spacing_m: float = Field(4.0, gt=0.0, le=100.0, description="[ours] Side of one grid cell in metres.")
    half_extent_m: float = Field(200.0, gt=0.0, le=10_000.0, description=(
        "[paper] The grid covers +/- this many metres in x and y (the world's half extent); must equal "
        "cells * spacing_m / 2."))
    jitter_m: float = Field(1.0, ge=0.0, le=50.0, description=(
        "[ours] Each tree sits at its cell centre plus a uniform offset in +/- this in x and y (at most "
        "spacing_m / 2)."))
    patch_scale_m: float = Field(130.0, ge=5.0, le=10_000.0, description=(
        "[ours, fitted] Metres per lattice unit of the patch noise: the size of the forest's patches and gaps."))
    patch_octaves: int = Field(2, ge=1, le=6, description=(
        "[ours] Octaves of the patch noise (persistence 0.5, lacunarity 2)."))
    patch_threshold: float = Field(0.87, ge=0.0, le=3.0, description=(
        "[ours, fitted] Trees grow where the suitability (the patch noise normalised to [0, 1] over the land outside "
        "the clearing, plus radial_rise per half extent from the station) exceeds this."))
    patch_ramp: float = Field(0.3, gt=0.0, le=3.0, description=(
        "[ours, fitted] Suitability over which the tree density rises linearly from 0 at patch_threshold to 1."))
    patch_density: float = Field(0.65, gt=0.0, le=1.0, description=(
        "[ours, fitted] Highest tree density (share of cells holding a tree) inside a patch."))
    radial_rise: float = Field(0.16, ge=0.0, le=3.0, description=(
        "[ours, fitted] Suitability added per half extent of distance from the station: the forest thickens outward."))
    station_clear_radius_m: float = Field(45.0, ge=0.0, le=10_000.0, description=(
        "[ours, fitted] No tree within this distance of the station (trees exist only strictly farther away)."))

    @model_validator(mode="after")
    def _consistent(self) -> "ReforestationForestSpec":
        check_forest_grid(self)
        return self

    def placement_spec(self) -> ForestSpec:
        """The shared rule's spec that turns a suitability, passed as its height, into this spec's density:
        nothing below patch_threshold, density (s - threshold) / ramp, up to patch_density (the suitability is
        capped at :meth:`suitability_cap`, the band's top)."""
        ideal = self.patch_threshold + self.patch_ramp
        return ForestSpec(cells=self.cells, spacing_m=self.spacing_m, half_extent_m=self.half_extent_m,
                          jitter_m=self.jitter_m, min_height_m=self.patch_threshold, ideal_height_m=ideal,
                          max_height_m=ideal, density_falloff=1.0 / self.patch_ramp,
                          village_clear_radius_m=self.station_clear_radius_m)

    def suitability_cap(self) -> float:
        """The suitability at which the density reaches patch_density."""
        return self.patch_threshold + self.patch_density * self.patch_ramp


def patch_noise(rng: np.random.Generator, spec: ReforestationForestSpec):
    """A fresh noise field (one lattice drawn from ``rng``): a function of (N, 2) metres to (N,) values in [-1, 1]."""
    perm, grads = draw_lattice(rng, 1, NOISE_PERIOD)

    def at(xy: np.ndarray) -> np.ndarray:
        lattice = xy / spec.patch_scale_m + NOISE_OFFSET
        return fractal2d(perm, grads, lattice[None, :, 0], lattice[None, :, 1], spec.patch_octaves, PERSISTENCE,
                         LACUNARITY)[0]
    return at


def suitability_field(noise, spec: ReforestationForestSpec, terrain: Terrain):
    """The suitability (N, 2) metres -> (N,): ``noise`` min-max normalised over the land cell centres outside the
    clearing, plus radial_rise per half extent from the station, OFF_LAND at or below sea level, capped at
    :meth:`ReforestationForestSpec.suitability_cap`."""
    station = terrain.village
    centres = cell_centre_xy(spec.placement_spec()).reshape(-1, 2)
    usable = (terrain.height_at(centres) > 0.0) & (np.hypot(*(centres - station).T) > spec.station_clear_radius_m)
    values = noise(centres[usable]) if usable.any() else np.zeros(1)
    low, span = values.min(), max(values.max() - values.min(), 1e-12)

    def at(xy: np.ndarray) -> np.ndarray:
        rise = spec.radial_rise * np.hypot(*(xy - station).T) / spec.half_extent_m
        value = np.where(terrain.height_at(xy) > 0.0, (noise(xy) - low) / span + rise, OFF_LAND)
        return np.minimum(value, spec.suitability_cap())
    return at


def place_reforestation_forest(rng: np.random.Generator, spec: ReforestationForestSpec, terrain: Terrain) -> Forest:
    """The existing forest of one world on ``terrain``, its station at the terrain's village.

    Draws, in order: the patch noise's lattice, then :func:`~hivex_dsl.sim.procgen.forest.place_forest`'s jitter
    and per-cell draws.
    """
    suitability = suitability_field(patch_noise(rng, spec), spec, terrain)
    return place_forest(rng, spec.placement_spec(), suitability, terrain.village)
