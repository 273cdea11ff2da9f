"""The batched Bee Foraging simulator: ``B`` meadows of ``A`` bees and ``F`` flowers, stepped as whole arrays."""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np
from gymnasium import spaces

from hivex_dsl.runtime import StepOutcome
from hivex_dsl.runtime.global_state import StateComponent

ENV_ID = "bee_foraging"
# actions: 0 hover, 1 north, 2 south, 3 east, 4 west -> unit moves (x, y)
MOVES = np.array([[0, 0], [0, 1], [0, -1], [1, 0], [-1, 0]], np.float64)
PICTURE = 84  # pixels a side of a rendered meadow


@dataclass(frozen=True)
class BeeState:
    positions: np.ndarray  # (B, A, 2) metres from the hive
    load: np.ndarray  # (B, A) nectar carried
    flowers: np.ndarray  # (B, F, 2) metres from the hive
    nectar: np.ndarray  # (B, F) nectar left on each flower
    gathered: np.ndarray  # (B, A) nectar gathered on the last step
    delivered: np.ndarray  # (B, A) nectar unloaded at the hive on the last step


class BeeForagingSimulator:
    """See :class:`hivex_dsl.runtime.contract.Simulator` for what each member promises."""

    observation_labels = ("position x", "position y", "load", "nearest flower x", "nearest flower y",
                          "nearest flower nectar", "hive x", "hive y")
    action_meanings = "0 hover, 1 north, 2 south, 3 east, 4 west"
    render_fps = 10

    def __init__(self, compiled):
        self.params = compiled.params
        self.agents = compiled.agents
        self.half = self.params.meadow_half_extent_m
        self.observation_space = spaces.Box(-1.0, 1.0, (len(self.observation_labels),), np.float32)
        self.action_space = spaces.Discrete(len(MOVES))

    def reset(self, rng: np.random.Generator, batch: int) -> BeeState:
        p, shape = self.params, (batch, self.agents)
        flowers = rng.uniform(-0.9 * self.half, 0.9 * self.half, (batch, p.flowers, 2))
        return BeeState(positions=rng.uniform(-p.reach_m, p.reach_m, shape + (2,)), load=np.zeros(shape),
                        flowers=flowers, nectar=np.full((batch, p.flowers), p.nectar_per_flower),
                        gathered=np.zeros(shape), delivered=np.zeros(shape))

    def reset_where(self, state: BeeState, mask: np.ndarray, rng: np.random.Generator) -> BeeState:
        fresh = self.reset(rng, mask.shape[0])
        return BeeState(*(np.where(mask.reshape((-1,) + (1,) * (old.ndim - 1)), new, old)
                          for old, new in zip(_fields(state), _fields(fresh))))

    def step(self, state: BeeState, actions: np.ndarray, rng: np.random.Generator) -> tuple[BeeState, StepOutcome]:
        p = self.params
        positions = np.clip(state.positions + MOVES[actions] * p.speed_m, -self.half, self.half)
        nearest, distance = nearest_flower(positions, state.flowers, state.nectar)
        want = np.where(distance <= p.reach_m, np.minimum(p.gather_rate, p.capacity - state.load), 0.0)
        at_flower = nearest[..., None] == np.arange(state.nectar.shape[1])  # (B, A, F)
        demand = (at_flower * want[..., None]).sum(axis=1)  # (B, F): bees at one flower share what it has
        share = np.where(demand > 0, np.minimum(1.0, state.nectar / np.where(demand > 0, demand, 1.0)), 0.0)
        gathered = want * np.take_along_axis(share, nearest, axis=1)
        nectar = np.maximum(state.nectar - (at_flower * gathered[..., None]).sum(axis=1), 0.0)
        load = state.load + gathered
        home = np.hypot(positions[..., 0], positions[..., 1]) <= p.reach_m
        delivered = np.where(home, load, 0.0)
        new = replace(state, positions=positions, load=load - delivered, nectar=nectar, gathered=gathered,
                      delivered=delivered)
        empty = (nectar.sum(axis=1) <= 0) & (new.load.sum(axis=1) <= 0)
        events = {"gathered": gathered > 0, "delivered": delivered > 0,
                  "meadow_empty": np.broadcast_to(empty[:, None], load.shape).copy()}
        return new, StepOutcome(np.zeros(load.shape, bool), events)

    def observe(self, state: BeeState) -> np.ndarray:
        nearest, _ = nearest_flower(state.positions, state.flowers, state.nectar)
        flower = np.take_along_axis(state.flowers, nearest[..., None], axis=1)  # (B, A, 2)
        nectar = np.take_along_axis(state.nectar, nearest, axis=1)
        offset = np.where(nectar[..., None] > 0, (flower - state.positions) / (2 * self.half), 0.0)
        return np.concatenate([state.positions / self.half, (state.load / self.params.capacity)[..., None], offset,
                               (nectar / self.params.nectar_per_flower)[..., None], -state.positions / self.half],
                              axis=-1).astype(np.float32)

    def render(self, state: BeeState, index: int) -> np.ndarray:
        picture = np.zeros((PICTURE, PICTURE, 3), np.uint8)
        picture[:] = (90, 160, 70)
        flowers = self._pixels(state.flowers[index])
        full = state.nectar[index] / self.params.nectar_per_flower
        picture[flowers[:, 1], flowers[:, 0]] = (np.array([255, 220, 40]) * (0.4 + 0.6 * full[:, None])).astype(np.uint8)
        hive = self._pixels(np.zeros((1, 2)))[0]
        picture[hive[1] - 1:hive[1] + 2, hive[0] - 1:hive[0] + 2] = (120, 70, 30)
        bees = self._pixels(state.positions[index])
        picture[bees[:, 1], bees[:, 0]] = (20, 20, 20)
        return picture

    def _pixels(self, xy: np.ndarray) -> np.ndarray:
        """(N, 2) metres -> (N, 2) pixel (column, row), north up."""
        scaled = (xy / self.half + 1.0) / 2.0 * (PICTURE - 1)
        return np.stack([scaled[:, 0], PICTURE - 1 - scaled[:, 1]], axis=1).round().astype(np.int64)

    def state_components(self) -> tuple[StateComponent, ...]:
        return (StateComponent("nectar left", 1, 0.0, 1.0, "Nectar on the flowers / what they held at the start."),
                StateComponent("load", 1, 0.0, 1.0, "The nectar the bee carries / its capacity.", per_agent=True))

    def world_state(self, state: BeeState) -> tuple[np.ndarray, np.ndarray]:
        """(vectors (B, A, 8) float32 the bees' observations, world (B, 1 + A): nectar left, each bee's load)."""
        full = state.nectar.shape[1] * self.params.nectar_per_flower
        world = np.concatenate([state.nectar.sum(axis=1, keepdims=True) / full, state.load / self.params.capacity],
                               axis=1)
        return self.observe(state), world


def nearest_flower(positions: np.ndarray, flowers: np.ndarray, nectar: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """For each bee the nearest flower that has nectar: (index (B, A), distance (B, A), inf when none has)."""
    gaps = np.linalg.norm(positions[:, :, None, :] - flowers[:, None, :, :], axis=-1)  # (B, A, F)
    gaps = np.where(nectar[:, None, :] > 0, gaps, np.inf)
    nearest = gaps.argmin(axis=-1)
    return nearest, np.take_along_axis(gaps, nearest[..., None], axis=-1)[..., 0]


def _fields(state: BeeState) -> tuple[np.ndarray, ...]:
    return (state.positions, state.load, state.flowers, state.nectar, state.gathered, state.delivered)


def state_facts(simulator: BeeForagingSimulator, state: BeeState, params) -> dict[str, list[float]]:
    """World 0's facts counted flower by flower and bee by bee, for the tests to compare with ``world_state``."""
    left = sum(float(n) for n in state.nectar[0]) / (len(state.nectar[0]) * params.nectar_per_flower)
    return {"nectar left": [left], "load": [float(load) / params.capacity for load in state.load[0]]}
