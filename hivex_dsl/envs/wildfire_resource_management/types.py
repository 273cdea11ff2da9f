"""The batched state of Wildfire Resource Management."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ...sim.fire import FireState
from ...sim.procgen.weather import WeatherState
from ...sim.procgen.wind import WindState
from ..island import IslandMaps


@dataclass(frozen=True)
class Sighting:
    """The closest burning tree each tower (B, A) observes within its detection radius.

    cell: (B, A) int64 forest cell row * C + col of the horizontally closest burning tree in the tower's search
    square (half side = the detection radius), -1 when none burns there; ``cells`` is C (see ``row``, ``col``).
    offset: (B, A, 3) metres from the tower to that tree (x, y, and z = ground height difference), 0 unless seen.
    distance: (B, A) float64 3-D distance C(x) to it, inf unless it lies within the detection radius.
    approaching: (B, A) bool m of the paper: the distance shrank at the last fire step (a fire that just came
    into range counts as approaching; it came from beyond the radius).
    cohorts: (B, A, S) complex128 key (see .sight: squared cell distance + 1j * cell row * C + col; inf + 1j * a
    negative number for none) of the closest tree in the search square among the trees of age j (slot j <
    S = burn_steps), kept so the next fire step only has to search its ignitions; None in hand-made sightings.
    performance: (B, A) float64 tower performance P of the paper under the simulator's params
    (terms.performance_of), computed once per sighting for the three reward terms; None in hand-made
    sightings (the terms then compute it).
    """

    cell: np.ndarray
    cells: int
    offset: np.ndarray
    distance: np.ndarray
    approaching: np.ndarray
    cohorts: np.ndarray | None = None
    performance: np.ndarray | None = None

    @property
    def row(self) -> np.ndarray:
        """(B, A) int64 forest row of ``cell``, -1 when none (-1 // C is -1)."""
        return self.cell // self.cells

    @property
    def col(self) -> np.ndarray:
        """(B, A) int64 forest column of ``cell``, -1 when none."""
        return np.where(self.cell >= 0, self.cell % self.cells, -1)

    @property
    def seen(self) -> np.ndarray:
        """(B, A) bool: a burning tree is in range."""
        return np.isfinite(self.distance)


@dataclass(frozen=True)
class WildfireResourceState:
    """B worlds of A = 9 watchtowers; resources in integer tenths; per-step events describe the last step."""

    maps: IslandMaps
    fire: FireState
    wind: WindState
    weather: WeatherState
    conditions: np.ndarray  # (B, G, G, 3) float32 temperature, humidity, overcast on the weather grid
    fire_factors: np.ndarray  # (B, G * G) int8 weather factors of fire spread (hot, dry, low) on that grid
    tick: int  # steps since the batch was created; the fire and weather samples run on it
    tower_ground: np.ndarray  # (B, A) float32 ground height under each tower
    tower_weather: np.ndarray  # (B, A, 3) float32 temperature, humidity, overcast at each tower
    sighting: Sighting
    allocation: np.ndarray  # (B, A, 4) int16 tenths agent a gave to itself and its neighbours 1-3
    budget: np.ndarray  # (B, A) int16 tenths agent a has not allocated
    support: np.ndarray  # (B, A) int32 tenths tower a receives from every agent, itself included
    impossible: np.ndarray  # (B, A) int16 add/subtract components of the last step that could not happen
    impossible_total: np.ndarray  # (B, A) int32 the same, summed over the episode
    frame: np.ndarray  # (B, A, 16) float32 the stacked observation, newest frame first
    fire_went_out: np.ndarray  # (B,) bool: the fire went out on the last step
