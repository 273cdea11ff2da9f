"""A scripted drone pilot a forester would write, from the observations alone.

With a seed: cruise high (a wide camera view) until trees come into sight, sink toward the
nearest one, and drop the seed a few metres outside the forest edge where no planted tree is
close; over the forest, back out. It searches on a spiral around the station (the forest grows in
patches at uneven distances) and remembers where its team last dropped a seed, flying there first
on its next trip. Without a seed (where returns pay), or when the battery would
not last the way home with a margin: fly back to the station and land on it until the return
recharges and reloads it (a docking charges only on a return: the pilot remembers whether it has
been away, which it cannot observe). Where returns pay nothing, a seedless drone searches on.
Where the camera is blank (``camera_images: blank``, the original's runs), it sees no tree and drops
its seed once the spiral has taken it ``BLIND_DROP_M`` from the station.
"""

from __future__ import annotations

import math
from typing import Callable

import numpy as np

from ...base import portable
from ...sim.procgen.wind import wrap_angle
from .camera import NEW_TREE_BELOW, TREE_BELOW, pixel_offsets
from .simulator import returns_reload

CRUISE_HEIGHT_M = 30.0  # above ground while searching: a ~60 m wide view at the default 90 degrees
APPROACH_HEIGHT_M = 7.0  # above ground near the forest: ~1 m per camera pixel
HOME_HEIGHT_M = 10.0  # above ground flying home
LANDING_HEIGHT_M = 2.0  # above the station pad
PAD_HOVER_M = 3.0  # this close to the station (horizontally) a drone flying home stops and sinks onto the pad
DROP_MIN_M, DROP_MAX_M = 2.5, 6.0  # nearest tree pixel distance at which to drop (crowns reach ~1.5 m further)
NEW_TREE_CLEARANCE_M = 4.0
ENERGY_MARGIN = 1.5
FULL_BATTERY = 0.98  # a battery this full was just filled: on the pad after its return it drains a few thousandths
BORDER = 0.8  # fraction of the half extent where a searching drone turns back
SWEEP_OFFSET = np.radians(30.0)  # [ours] off the centre when turning back at the border
SPIRAL_GAP_M = 50.0  # between the turns of the search spiral: a little less than the camera's width at cruise height
SPIRAL_START_M = 30.0  # straight out from the station to here, then round it
SPOT_REACHED_M = 5.0  # at the remembered drop spot with no tree in sight: forget it
BLIND_DROP_M = 60.0  # [ours] a pilot whose camera is blank drops its seed this far from the station


def _pixel_grid() -> tuple[np.ndarray, np.ndarray]:
    """(256,) east and north offsets of the camera pixels in units of the footprint half width."""
    u = pixel_offsets()
    east, north = np.meshgrid(u, -u)
    return east.ravel(), north.ravel()


def scripted_policy(compiled) -> Callable[[dict], dict]:
    """observations {vector (B, A, 20), visual (B, A, 16, 16, 1)} -> actions {continuous, discrete}."""
    p = compiled.params
    half = compiled.generators["terrain"].extent_m / 2.0
    bound = p.height_bound_m
    view = math.tan(math.radians(p.camera_fov_deg) / 2.0)
    period = compiled.decision_period  # an action is held this many physics steps: the gains are per decision
    turn = np.radians(p.turn_rate_deg) * period
    east, north = _pixel_grid()
    gather = compiled.weights.get("group_up", 0.0) > 0.0  # meet the others only where meeting pays
    soar = compiled.task_name == "find_high_terrain"  # the height reward reads the drone's own height
    w = compiled.weights
    fetches = w.get("pick_up_seed", 0.0) > 0.0  # a seedless drone flies home for a seed; elsewhere it searches on
    docks = fetches or w.get("pick_up_seed_explored", 0.0) > 0.0  # landed, it waits for its return to pay
    # without a seed it heads for trees only where finding them pays (elsewhere it cruises on, exploring)
    seeks_trees = w.get("find_close_tree", 0.0) > 0.0 or w.get("high_fertility_location_delta", 0.0) > 0.0
    reach = np.hypot(east, north)
    bearing = portable.arctan2(north, east)

    def steer_toward(heading: np.ndarray, target: np.ndarray, slow_within: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(throttle, steer) turning toward bearing ``target``; slow while turning or within ``slow_within`` m."""
        error = wrap_angle(target - heading)
        steer = np.clip(error / turn, -1.0, 1.0)
        throttle = np.where(np.abs(error) < np.radians(60.0), 1.0, 0.2) * np.clip(slow_within, 0.0, 1.0)
        return throttle, steer

    # where a return hands over no seed and no charge (tasks whose drones start seedless), the pilot tells a return
    # by the decisions it has sat on the pad: a docking lasts the charging cycle
    reloads = returns_reload(compiled.task_name)
    docking_decisions = int(np.ceil(np.ceil(1.0 / p.charge_per_step - 1e-9) / period))
    # (B, A): been return_min_distance_m away since the last return, decisions landed since, furthest reached
    trips = {"out": np.zeros((0, 0), bool), "landed": np.zeros((0, 0), np.int64), "far": np.zeros((0, 0))}
    # (B, A, 2): where the drone's team last dropped a seed this episode (NaN: nowhere yet), the forest edge to go to
    spots = {"xy": np.zeros((0, 0, 2))}

    def remembered(x: np.ndarray, y: np.ndarray, new_episode: np.ndarray, lost: np.ndarray) -> np.ndarray:
        """(B, A, 2) the spot each drone flies to, NaN where none: cleared at a new episode and where the drone reached
        it ``lost`` (looking for trees, none in sight)."""
        if spots["xy"].shape[:2] != x.shape:
            spots["xy"] = np.full(x.shape + (2,), np.nan)
        gone = new_episode | (lost & (np.hypot(spots["xy"][..., 0] - x, spots["xy"][..., 1] - y) < SPOT_REACHED_M))
        spots["xy"] = np.where(gone[..., None], np.nan, spots["xy"])
        return spots["xy"]

    def remember_drops(x: np.ndarray, y: np.ndarray, drop: np.ndarray) -> None:
        """Every drone of a world remembers the last spot (x, y) where one of them drops (``drop`` (B, A) bool)."""
        worlds, agents = np.nonzero(drop)
        spots["xy"][worlds] = np.stack([x[worlds, agents], y[worlds, agents]], axis=-1)[:, None, :]

    def tripped(home_distance: np.ndarray, holding: np.ndarray, fresh: np.ndarray, landed: np.ndarray) -> np.ndarray:
        """(B, A) whether a drone's docking now would be a return (the simulator's ``away``, which the pilot cannot
        observe): a seed in hand, a docking's whole cycle sat out on the pad or a new episode (``fresh``, the older
        stack zeros) clears it."""
        if trips["out"].shape != holding.shape:
            trips["out"], trips["far"] = np.zeros(holding.shape, bool), np.zeros(holding.shape)
            trips["landed"] = np.zeros(holding.shape, np.int64)
        out = trips["out"]
        trips["landed"] = np.where(landed & out & ~fresh, trips["landed"] + 1, 0)
        trips["far"] = np.maximum(np.where(fresh, 0.0, trips["far"]), home_distance)
        returned = trips["landed"] >= docking_decisions
        trips["out"] = (out & ~holding & ~fresh & ~returned) | (home_distance >= p.return_min_distance_m)
        return trips["out"]

    def act(observations: dict) -> dict:
        frames = observations["vector"]
        fresh = ~frames[..., 10:20].any(axis=-1)  # a first observation's older stack is zeros (no real frame is)
        v = frames[..., :10].astype(np.float64) / p.vector_observation_gain
        image = observations["visual"][..., 0].reshape(v.shape[:2] + (-1,))
        above, x, y, z = v[..., 0] * bound, v[..., 1] * half, v[..., 2] * half, v[..., 3] * bound
        heading = portable.arctan2(v[..., 5], v[..., 4])
        station_z, holding, energy = v[..., 7] * bound, v[..., 8] > 0.5, v[..., 9]
        ground = z - above
        home_distance = np.hypot(x, y)
        # the way home and 20 decisions' reserve (a drone deciding every k-th step turns and lands k times coarser)
        steps_home = home_distance / p.drone_speed_m + (z - station_z) / p.climb_speed_m + 20.0 * period
        # (where a return neither reloads nor pays, going home is no use: the drone flies on until its battery is out;
        # where it does not reload, the drone flies seedless)
        steps_per_battery = p.energy_steps_with_seed if reloads else p.energy_steps_without_seed
        enough = (energy > ENERGY_MARGIN * steps_home / steps_per_battery + 0.02) | (not reloads and not docks)
        # landed on the pad without a seed, or back for energy: stay the charging cycle, until the return hands it a
        # full battery and a seed (a drone passing over does not land; one lingering there after its return drains)
        landed = (home_distance < PAD_HOVER_M) & (z - station_z < LANDING_HEIGHT_M + 1.0)
        out = tripped(home_distance, holding, fresh, landed)
        waiting = docks & ~holding & (home_distance < p.charge_radius_m) & out
        charging = (landed & docks & reloads & (~holding | (energy < FULL_BATTERY))) | waiting
        # grouping: everyone meets at the station, the one place all know; where returns do not reload, a seedless
        # drone that fetches flies out far enough for its next docking to be a return, and one whose returns pay the
        # distance explored (Explore Furthest) hops so once it has been to the border: each return pays it again
        hopping = (not reloads) & docks & (trips["far"] >= BORDER * half)
        seeking = (holding | ~fetches | (~reloads & ~out)) & enough & ~gather & ~charging & ~(hopping & out)

        hw = np.maximum(p.camera_min_half_width_m, above * view)
        tree = (image < TREE_BELOW) & p.cameras_render  # a blank camera's zeros are no trees
        tree_distance = np.where(tree, reach, np.inf).min(axis=-1) * hw
        tree_bearing = bearing[np.where(tree, reach, np.inf).argmin(axis=-1)]
        planted = (image >= TREE_BELOW) & (image < NEW_TREE_BELOW)
        planted_near = (np.where(planted, reach, np.inf).min(axis=-1) * hw) < NEW_TREE_CLEARANCE_M
        sees_tree = np.isfinite(tree_distance) & (holding | seeks_trees)

        # searching: straight on, turning back near the border toward a line 30 degrees off the centre, so that each
        # crossing sweeps new ground (straight back through the centre a drone can shuttle on one line all episode)
        outward = (np.abs(x) > BORDER * half) | (np.abs(y) > BORDER * half)
        target = np.where(outward, portable.arctan2(-y, -x) + SWEEP_OFFSET, heading)
        # looking for trees: to the team's last drop spot if there is one, else out and round the station on a spiral
        # (an Archimedean one: outward by SPIRAL_GAP_M a turn, so each turn's view borders the last's)
        looking = holding | seeks_trees
        spot = remembered(x, y, fresh, looking & ~sees_tree)
        known = looking & np.isfinite(spot[..., 0])
        circumference = 2.0 * np.pi * np.maximum(home_distance, 1.0)
        around = portable.arctan2(y, x) + np.pi / 2.0 - portable.arctan2(SPIRAL_GAP_M, circumference)
        spiral = np.where(home_distance < SPIRAL_START_M, portable.arctan2(y, x), around)
        target = np.where(looking & ~outward, spiral, target)
        target = np.where(known, portable.arctan2(spot[..., 1] - y, spot[..., 0] - x), target)
        height = np.full(x.shape, CRUISE_HEIGHT_M)
        # trees in sight: approach the nearest; too close (or a planted tree here): slide along the edge
        target = np.where(sees_tree, tree_bearing, target)
        height = np.where(sees_tree, APPROACH_HEIGHT_M, height)
        over_forest = sees_tree & (tree_distance < DROP_MIN_M)
        target = np.where(over_forest, tree_bearing + np.pi, target)
        crowded = sees_tree & planted_near & ~over_forest
        target = np.where(crowded, tree_bearing + np.pi / 2.0, target)
        ready = sees_tree & (tree_distance <= DROP_MAX_M) & ~over_forest & ~planted_near
        if not p.cameras_render:  # blind (the original's blank camera): drop a seed once out on the spiral
            ready = holding & (home_distance >= BLIND_DROP_M)
        # nearing the drop window, slow so that a throttle held for a decision stops in it rather than flying through
        approach = np.where(sees_tree & ~over_forest, (tree_distance - DROP_MIN_M) / (p.drone_speed_m * period), 1.0)
        throttle, steer = steer_toward(heading, target, np.where(ready, 0.0, approach))

        # home: straight to the station, slowing within 4 m and what a held throttle flies in the rest of a decision,
        # then down onto the pad
        home_throttle, home_steer = steer_toward(
            heading, portable.arctan2(-y, -x), home_distance / (4.0 + (period - 1) * p.drone_speed_m))
        home_throttle = np.where(home_distance < PAD_HOVER_M, 0.0, home_throttle)  # over the pad: hover, dock
        throttle, steer = np.where(seeking, throttle, home_throttle), np.where(seeking, steer, home_steer)
        home_z = np.where(home_distance < 6.0, station_z + LANDING_HEIGHT_M, ground + HOME_HEIGHT_M)
        target_z = np.where(seeking, ground + height, home_z)
        climb = np.clip((np.minimum(target_z, bound - 1.0) - z) / (p.climb_speed_m * period), -1.0, 1.0)
        if soar:
            climb = np.ones_like(climb)

        drop = seeking & ready
        remember_drops(x, y, drop & holding)
        drop = drop.astype(np.int64)[..., None]
        continuous = np.stack([throttle, steer, climb], axis=-1).astype(np.float32)
        return {"continuous": continuous, "discrete": drop}

    return act
