"""Physical constants of Ocean Plastic Collection; every one bounded, documented and overridable.

[paper] values come from the paper's specification table and reward equations, [orig] from the
original release, [ours] are this project's defaults where neither says (ENVIRONMENTS.md). The
world, its pollution heat map, the pebble count and the spawn rules are generator fields
(``generators: pollution / spawn``), not params.
"""

from __future__ import annotations

import math
from typing import Any, ClassVar, Literal, Optional

from pydantic import Field, model_validator

from ...lang.spec.common import AS_DEFAULT, StrictModel

CrashOutcome = Literal["end_world", "end", "respawn"]
CameraSource = Literal["pebbles", "heat_map", "blank"]


class OceanPlasticCollectionParams(StrictModel):
    # each with what was done before it came, written out (not AS_DEFAULT): collection uncapped (issue 52, session 48)
    ADDED_FIELDS: ClassVar[dict[str, Any]] = {"collect_per_decision": 0, "camera_source": "pebbles",
                                              "max_speed_m": None, "heading_noise_deg": AS_DEFAULT,
                                              "neighbour_sight_m": AS_DEFAULT}

    acceleration: float = Field(0.2, gt=0.0, le=1.0, description=(
        "[orig] Metres per step added to the vessel's speed on each step it accelerates (throttle 1); fitted with "
        "turn_rate_deg to the original's untrained policy, whose vessel-episodes last 32.5-35.2 decisions (the reward "
        "table's pace note)."))
    drag: float = Field(0.1, ge=0.0, le=1.0, description=(
        "[ours] Fraction of its speed a vessel loses each step; top speed is acceleration / drag (2 m per step), or "
        "max_speed_m where that is lower. 0 (with max_speed_m): a vessel holds its speed when it does not "
        "throttle, so once moving it cannot slow down."))
    max_speed_m: Optional[float] = Field(None, gt=0.0, le=20.0, description=(
        "[ours] A vessel's speed, metres per step, never exceeds this (null: no cap, the default; top speed is then "
        "acceleration / drag). With drag 0 it is the speed every moving vessel keeps: the reading of the original's "
        "records under test in issue 52 (the reward table's note 'Early lives')."))
    turn_rate_deg: float = Field(6.0, gt=0.0, le=45.0, description=(
        "[orig] Degrees a vessel turns per step while steering right or left (it turns at any speed); fitted with "
        "acceleration (the reward table's pace note)."))
    heading_noise_deg: float = Field(0.0, ge=0.0, le=30.0, description=(
        "[ours] Standard deviation, in degrees, of a random turn the sea gives every moving or resting vessel each "
        "physics step, beside its steering (0: none, the default). A probe of issue 52's open question: the "
        "original's trained worlds crash at a steady rate, about once every 160 decisions, with policies sharper "
        "than ours that crash less (the reward table's ending note), as a disturbance no policy can foresee would "
        "make them; trained at 3 degrees the vessels adapted and still outlived the original's (the same note)."))
    neighbour_sight_m: Optional[float] = Field(None, ge=0.0, le=1000.0, description=(
        "[ours] The vector observation's closest neighbouring vessel is sent only while it is at most this many "
        "metres away, (0, 0) otherwise, as a vessel with no neighbour is (null: at any distance, the default; 0: "
        "never, vessels blind to each other). A probe of issue 52's open question, what makes the original's "
        "trained worlds crash about once every 160 decisions: a blind scripted skipper lives that long, but PPO "
        "trained blind crashes no more often than PPO that sees, about two thirds as often as the original's, "
        "keeping to its own part of the map (the reward table's note 'Vessels blind to each other')."))
    collector_reach_m: float = Field(3.0, gt=0.0, le=20.0, description=(
        "[ours] The collector reaches this far ahead of the vessel's centre; a pebble it sweeps over is collected."))
    collector_half_width_m: float = Field(1.5, gt=0.0, le=10.0, description=(
        "[ours] Half the width of the collector across the vessel's heading."))
    collision_distance_m: float = Field(10.0, gt=0.0, le=50.0, description=(
        "[orig] Two vessels whose centres come closer than this collide (-100 each). No source gives the vessels' "
        "size; fitted to the original's records (issue 52; the reward table's ending note): trained at 5 m, this "
        "project's first choice, the vessels learned to outlive the original's about 150 decisions by half again "
        "and returned 2-3 times its return, at 10 m they live nearly as long; and at 10 m Close to Other Vessel "
        "(within close_distance_m, 10 m) pays nothing, a vessel that near having collided, as the original's Group "
        "Up, which returned about what its main task did, shows."))
    close_distance_m: float = Field(10.0, gt=0.0, le=200.0, description=(
        "[paper] d_thresh of Close to Other Vessel: the reward is given while the closest vessel is at most this far."))
    nearby_radius_m: float = Field(25.0, gt=0.0, le=100.0, description=(
        "[paper] d_threshold of Nearby Trash Count Delta: pebbles nearer than this count as nearby."))
    camera_full_count: int = Field(2, ge=1, le=100, description=(
        "[ours] Pebbles in one 2 m camera cell that read as trash density 1; fewer read proportionally less."))
    camera_source: CameraSource = Field("pebbles", description=(
        "[ours] What the 25 x 25 visual observation shows. 'pebbles' (the default; the README's 'Trash (625)' and "
        "the process figure's 25 x 25 grid of 2 m cells, a GridSensor's settings): the floating pebbles counted in "
        "each 2 m cell, camera_full_count of them reading 1; 'heat_map' (the process figure's colours): the "
        "pollution heat map the pebbles were drawn from, each cell its density over the world's densest; 'blank': "
        "zeros, what a rendered camera sends under the configs' no_graphics. Trained, the seeing readings pass the "
        "original's pace and return by a quarter of the budget and the blind one stays at half its return (the "
        "reward table's note 'What the vessels saw')."))
    crash_outcome: CrashOutcome = Field("end_world", description=(
        "[orig] What follows a crash (crossing the border or colliding with another vessel) besides the paper's "
        "-100, on which the paper is silent. 'end_world' (the original's Episode Length and return curves: the "
        "reward table's ending note) ends the episode of every vessel of the world, the crashed one paying -100; "
        "'end' ends that vessel's episode alone, as the original Aerial Wildfire Suppression does at its border; "
        "'respawn' moves it to a free spawn point at rest on the next step, its episode going on."))
    collect_per_decision: int = Field(0, ge=0, le=100, description=(
        "[ours] At most this many pebbles a vessel collects within one decision, the nearest first (0: no cap, the "
        "default). The original's training pace stays near one pebble a decision in every collecting task (the "
        "reward table's pace note), as a release that takes one pebble an action would; 1 models that reading. "
        "Trained in issue 52's session 49 on its own fit (8,000 pebbles on an even map), it held the pace at or "
        "below the original's but lengthened the vessels' lives, so it is not the default; and the original's Avoid "
        "Plastic records rule it out, as under it a vessel-episode returns exactly its Local there, where the "
        "original's return 0.45-0.99 of theirs (the pace note)."))
    respawn_candidates: int = Field(16, ge=1, le=256, description=(
        "[ours] Random spawn points tried per respawn; the one farthest from the other vessels is taken."))

    @property
    def top_speed_m(self) -> float:
        """Metres per step a vessel that always throttles approaches: acceleration / drag, at most max_speed_m."""
        free = self.acceleration / self.drag if self.drag > 0 else math.inf
        return min(free, math.inf if self.max_speed_m is None else self.max_speed_m)

    @model_validator(mode="after")
    def _speed_bounded(self) -> "OceanPlasticCollectionParams":
        if self.drag == 0 and self.max_speed_m is None:
            raise ValueError("drag 0 needs max_speed_m: without drag and a cap a throttling vessel's speed grows "
                             "without bound; give max_speed_m (metres per step) or a drag above 0")
        return self
