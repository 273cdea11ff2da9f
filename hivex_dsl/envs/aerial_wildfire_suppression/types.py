"""The batched state of Aerial Wildfire Suppression."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ...sim.fire import FireState
from ...sim.procgen.weather import WeatherState
from ...sim.procgen.wind import WindState
from ..island import IslandMaps


@dataclass(frozen=True)
class Sighting:
    """Nearest burning tree around each plane (B, A) and near each village (B,)."""

    plane_found: np.ndarray  # (B, A) bool: a burning tree within the view square
    plane_xy: np.ndarray  # (B, A, 2) metres of that tree (0 where none)
    village_threat: np.ndarray  # (B,) bool: a burning tree in the village's zone (params.village_zone)


@dataclass(frozen=True)
class AerialWildfireState:
    """B worlds of A planes. Angles in radians; positions in metres; per-step events describe the last step."""

    maps: IslandMaps
    fire: FireState
    wind: WindState
    weather: WeatherState
    tick: int  # steps since the batch was created: the clock of the fire's cadence and of the rendered frames
    position: np.ndarray  # (B, A, 2)
    heading: np.ndarray  # (B, A)
    water: np.ndarray  # (B, A) bool holding water
    flying: np.ndarray  # (B, A) bool; false once a plane crossed the border
    # (B, A, 2) metres: where each plane last read the ground below it (params.terrain_cast: its position after
    # every step under 'step', at the last rendered frame under 'frame')
    cast_at: np.ndarray
    sighting: Sighting
    # latches of one-off rewards within an episode
    seen_fire: np.ndarray  # (B, A) bool
    seen_village: np.ndarray  # (B, A) bool
    village_hit: np.ndarray  # (B,) bool
    # the release's city flag: fire came within village_radius_m of the village in this world (kept while the
    # world continues into another episode: params.episodes_continue)
    village_reached: np.ndarray  # (B,) bool
    # events of the last step
    crossed: np.ndarray  # (B, A) bool
    picked_up: np.ndarray  # (B, A) bool
    dropped: np.ndarray  # (B, A) bool
    found_fire: np.ndarray  # (B, A) bool
    found_village: np.ndarray  # (B, A) bool
    extinguished: np.ndarray  # (B, A) int32 trees burning -> wet by this plane's drop
    prepared: np.ndarray  # (B, A) int32 trees existing -> wet by this plane's drop
    fire_went_out: np.ndarray  # (B,) bool
    village_threatened: np.ndarray  # (B,) bool: the first step fire came too close
    burning: np.ndarray  # (B,) bool: some tree burns after the step
    finishes: np.ndarray  # (B,) int64 the release's AgentDone calls this episode (finished_planes: wait; else 0)
    # the release's BurnNext clock (params.fire_cadence 'frames', burn_clock.py): its burnCoroutineRunning flag,
    # and whether a BurnNext started at the last frame waits (it outlives a redraw of its world)
    burn_running: np.ndarray  # (B,) bool
    burn_waiting: np.ndarray  # (B,) bool
    # what the cameras see: the palette image of each world (see view.py), written in place like fire.trees
    look: np.ndarray  # uint8, row-major (B, S, S) or tiled (B, S / 8, S / 8, 8, 8): see view.is_tiled
    visual: np.ndarray  # (B, A, P, P, 3) float32 the planes' cameras after the step
