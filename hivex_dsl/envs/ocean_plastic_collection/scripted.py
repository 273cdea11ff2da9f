"""A scripted skipper: steer for the densest trash the camera sees, keep clear of the border and the others.

Rules, each overriding the ones before it:

1. Steer for the camera cell with the most trash per step of travel, leaving alone trash within
   ``SAFE_MARGIN_M`` of the border or ``AVOID_STEPS`` of travel from another vessel; idle the throttle to turn on
   the spot when that cell is close and far off the bow. With no trash in sight, go straight,
   turning home when the course runs within ``BORDER_MARGIN_M`` of the border ``LOOKAHEAD_M`` ahead.
2. Group Up only: head for the closest vessel, at full speed while far, creeping once near (the
   speed is read from the two stacked positions, a decision apart), idling once within the close distance.
3. Turn away from a vessel close ahead, idling when it is very close.
4. Stop and turn home when the bow points at the border close by.

In Avoid Plastic (collecting is penalised) it holds still.
"""

from __future__ import annotations

from typing import Callable

import numpy as np

from ...base import portable
from .camera import CAMERA_CELL_M, CAMERA_CELLS, CAMERA_HALF_M
from .simulator import Motion, move

LOOKAHEAD_M = 30.0
BORDER_MARGIN_M = 25.0  # the course is turned home when it runs this close to the border
SAFE_MARGIN_M = 15.0  # trash this close to the border is left alone
AVOID_STEPS = 30.0  # another vessel ahead within this many steps' travel at top speed is turned away from
PATIENCE_STEPS = 40.0  # a cell this many steps away is worth half as much as one at the bow
SHARP_TURN = np.radians(50.0)
SLOW_DOWN_M = 8.0
HOLD_TOLERANCE = np.radians(2.0)
ASTERN = np.radians(170.0)
DANGER_AHEAD_STEPS = 30.0  # closer than DANGER_MARGIN_M to the border this many steps ahead: stop and turn home
DANGER_MARGIN_M = 5.0
GROUP_SPRINT_STEPS = 40.0  # Group Up: full speed to the closest vessel beyond this many steps' travel, creeping within
GROUP_BAND = 0.8  # Group Up: idle once nearer than this fraction of the close distance
GROUP_AVOID = 2.0  # Group Up: turn away only within this multiple of the collision distance
CREEP_SPEED = 0.05  # metres per step


def cell_centres() -> tuple[np.ndarray, np.ndarray]:
    """(25, 25) forward and right offsets in metres of every camera cell centre (row 0 ahead)."""
    offsets = (np.arange(CAMERA_CELLS) + 0.5) * CAMERA_CELL_M - CAMERA_HALF_M
    forward = np.broadcast_to(-offsets[:, None], (CAMERA_CELLS, CAMERA_CELLS))
    right = np.broadcast_to(offsets[None, :], (CAMERA_CELLS, CAMERA_CELLS))
    return forward, right


def steer_toward(bearing: np.ndarray) -> np.ndarray:
    """Steer action for a bearing (radians, positive to the right): 1 right, 2 left, 0 within tolerance.
    Anything nearly astern is turned to the right, so a target dead astern cannot flip the turn each step."""
    right = (bearing > HOLD_TOLERANCE) | (np.abs(bearing) > ASTERN)
    return np.where(right, 1, np.where(bearing < -HOLD_TOLERANCE, 2, 0))


def bearing_of(direction: np.ndarray, offset: np.ndarray) -> np.ndarray:
    """Signed angle (B, A) from the heading ``direction`` (unit, (B, A, 2)) to ``offset``; positive to the right."""
    cross = direction[..., 0] * offset[..., 1] - direction[..., 1] * offset[..., 0]
    dot = (direction * offset).sum(axis=-1)
    return -portable.arctan2(cross, dot)


def trash_target(density, worth, position, direction, safe_m, neighbour, clear_m):
    """The best camera cell: (B, A, 25, 25) densities summed over 3 x 3 neighbours (favouring
    clusters), weighted by ``worth`` (25, 25), among the cells whose centre lies within ``safe_m``
    of the world's centre on both axes and at least ``clear_m`` from the closest other vessel at
    ``neighbour`` (B, A, 2) metres. Returns (found, bearing, distance), each (B, A)."""
    forward, right = cell_centres()
    padded = np.pad(density, ((0, 0), (0, 0), (1, 1), (1, 1)))
    cluster = sum(padded[:, :, i:i + CAMERA_CELLS, j:j + CAMERA_CELLS] for i in range(3) for j in range(3))
    heading_x, heading_y = direction[..., 0, None, None], direction[..., 1, None, None]
    world_x = position[..., 0, None, None] + forward * heading_x + right * heading_y
    world_y = position[..., 1, None, None] + forward * heading_y - right * heading_x
    clear = np.hypot(world_x - neighbour[..., 0, None, None], world_y - neighbour[..., 1, None, None]) >= clear_m
    safe = (np.abs(world_x) < safe_m) & (np.abs(world_y) < safe_m) & clear
    score = ((density + 0.25 * cluster) * worth * safe).reshape(density.shape[:2] + (-1,))
    best = np.argmax(score, axis=-1)
    found = np.take_along_axis(score, best[..., None], axis=-1)[..., 0] > 0.0
    f, r = forward.reshape(-1)[best], right.reshape(-1)[best]
    return found, portable.arctan2(r, f), np.hypot(f, r)


def cruise_rules(position, direction, half, found, steer, throttle):
    """With no trash in sight go straight at full speed, turning home when the course nears the border."""
    home = steer_toward(bearing_of(direction, -position))
    leaving = (np.abs(position + LOOKAHEAD_M * direction) > half - BORDER_MARGIN_M).any(axis=-1)
    return np.where(found, steer, np.where(leaving, home, 0)), np.where(found, throttle, 1)


def danger_rules(position, direction, half, ahead_m, steer, throttle):
    """Stop and turn home when the bow points at the border close by (within ``ahead_m``)."""
    danger = (np.abs(position + ahead_m * direction) > half - DANGER_MARGIN_M).any(axis=-1)
    home = steer_toward(bearing_of(direction, -position))
    return np.where(danger, home, steer), np.where(danger, 0, throttle)


def group_rules(gap, bearing, speed, close_m, sprint_m, burst_m, steer, throttle):
    """Head for the closest vessel: at full speed while far, creeping (at most CREEP_SPEED) once
    within ``sprint_m``, drifting once a decision's throttle (``burst_m`` of travel) would carry it inside
    the close distance, and idle once nearer than GROUP_BAND of the close distance."""
    far = np.isfinite(gap) & (gap >= GROUP_BAND * close_m)
    sprint = gap > sprint_m
    steer = np.where(far, steer_toward(bearing), steer)
    creep = ((speed < CREEP_SPEED) & (gap > close_m + burst_m)).astype(np.int64)
    throttle = np.where(far, np.where(sprint, 1, creep), np.where(np.isfinite(gap), 0, throttle))
    return steer, throttle


def avoid_rules(gap, bearing, avoid_m, idle_m, steer, throttle):
    """Turn away from a vessel closer than ``avoid_m`` ahead, idling when it is closer than ``idle_m``."""
    ahead = (gap < avoid_m) & (np.abs(bearing) < np.pi / 2)
    steer = np.where(ahead, np.where(bearing > 0, 2, 1), steer)
    return steer, np.where(ahead, (gap >= idle_m).astype(np.int64), throttle)


def burst_travel(motion: Motion, period: int) -> float:
    """Metres a vessel at rest travels on one decision of full throttle (``period`` physics steps of the
    simulator's :func:`move`) and the coast after it (speed x keep / (1 - keep), the geometric tail; without drag
    the coast never ends, infinite)."""
    position, heading, speed = np.zeros((1, 1, 2)), np.zeros((1, 1)), np.zeros((1, 1))
    throttle, active = np.array([[[1, 0]]]), np.ones((1, 1), bool)
    for _ in range(period):
        position, heading, speed, _ = move(position, heading, speed, throttle, active, motion)
    coast = speed[0, 0] * motion.keep / (1.0 - motion.keep) if motion.keep < 1.0 else np.inf  # no drag: it never stops
    return float(position[0, 0, 0] + coast)


def scripted_policy(compiled) -> Callable[[dict], np.ndarray]:
    """observations {vector (B, A, 12), visual (B, A, 25, 25, 2)} -> actions (B, A, 2)."""
    params, weights = compiled.params, compiled.weights
    half = compiled.generators["pollution"].half_extent_m
    top_speed = params.top_speed_m
    forward, right = cell_centres()
    turning = np.abs(portable.arctan2(right, forward)) / np.radians(params.turn_rate_deg)
    steps_away = np.hypot(forward, right) / top_speed + turning
    worth = 1.0 / (1.0 + steps_away / PATIENCE_STEPS)
    period = compiled.decision_period  # the stacked positions are a decision, this many physics steps, apart
    hold_still = weights.get("collect_trash", 0.0) < 0.0
    # Closeness that only a collision reaches (a collision distance at or past the close distance) is not sought.
    group_up = weights.get("close_to_other_vessel", 0.0) > 0.0 and params.collision_distance_m < params.close_distance_m
    # Distances in steps of travel at top speed, so the skipper keeps its margins at any vessel pace (issue 52: the
    # default vessels run 2 m a step, where margins fitted at 0.5 m a step crashed most worlds' vessels).
    clear_m, ahead_m, sprint_m = AVOID_STEPS * top_speed, DANGER_AHEAD_STEPS * top_speed, GROUP_SPRINT_STEPS * top_speed
    # Grouping vessels creep, so they turn away only when nearly touching, and then idle.
    avoid_m = GROUP_AVOID * params.collision_distance_m if group_up else clear_m
    burst_m = burst_travel(Motion.of(params), period)
    idle_m = avoid_m if group_up else clear_m / 2

    def act(observations: dict) -> np.ndarray:
        vector, density = observations["vector"], observations["visual"][..., 0]
        if hold_still:
            return np.zeros(vector.shape[:2] + (2,), np.int64)
        position, direction = vector[..., 0:2] * half, vector[..., 2:4]
        has_neighbour = np.any(vector[..., 4:6] != 0.0, axis=-1)
        neighbour = np.where(has_neighbour[..., None], vector[..., 4:6] * half, np.inf)
        found, bearing, distance = trash_target(density, worth, position, direction, half - SAFE_MARGIN_M, neighbour,
                                                clear_m)
        steer = steer_toward(bearing)
        throttle = np.where((np.abs(bearing) > SHARP_TURN) & (distance < SLOW_DOWN_M), 0, 1)
        steer, throttle = cruise_rules(position, direction, half, found, steer, throttle)
        offset = np.where(has_neighbour[..., None], neighbour - position, 0.0)
        gap = np.where(has_neighbour, np.hypot(offset[..., 0], offset[..., 1]), np.inf)
        neighbour_bearing = bearing_of(direction, offset)
        if group_up:
            speed = np.hypot(*np.moveaxis(vector[..., 0:2] - vector[..., 6:8], -1, 0)) * (half / period)
            steer, throttle = group_rules(gap, neighbour_bearing, speed, params.close_distance_m, sprint_m,
                                           burst_m, steer, throttle)
        steer, throttle = avoid_rules(gap, neighbour_bearing, avoid_m, idle_m, steer, throttle)
        steer, throttle = danger_rules(position, direction, half, ahead_m, steer, throttle)
        return np.stack([throttle, steer], axis=-1).astype(np.int64)

    return act
