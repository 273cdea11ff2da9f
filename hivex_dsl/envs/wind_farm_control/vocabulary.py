"""What an expression may read in Wind Farm Control: turbine pose, the wind, alignment and performance.

Each reader takes the value from the state the simulator built; the wind angle and the force are
the simulator's own functions of that state (the state keeps the heading and the local wind, not
the angle between them). The wind has no speed (see NOT_MODELLED).
"""

from __future__ import annotations

import math

import numpy as np

from ...sim.procgen.wind import wrap_angle
from ...sim.reward.vocabulary import Vocabulary, quantity
from .simulator import alignment, angle_between, wind_force


def declare(compiled) -> dict:
    p = compiled.params
    half = p.farm_half_extent_m
    a, drag = p.motor_acceleration, p.drag
    # P <- (1 - drag) P + a W from P = 0 with W in [0, 1] stays below a / drag and below a * steps
    top = min(a / drag, a * compiled.episode_length) if drag > 0 else a * compiled.episode_length
    items = [
        quantity("x_m", "agent", "number", "m", -half, half, "The turbine's position east of the farm centre."),
        quantity("y_m", "agent", "number", "m", -half, half, "The turbine's position north of the farm centre."),
        quantity("heading_rad", "agent", "number", "rad", -math.pi, math.pi,
                 "Where the rotor faces, counter-clockwise from east."),
        quantity("wind_direction_rad", "agent", "number", "rad", -math.pi, math.pi,
                 "Where the wind at the turbine blows to, counter-clockwise from east."),
        quantity("main_wind_direction_rad", "world", "number", "rad", -math.pi, math.pi,
                 "Where the farm's main wind blows to."),
        quantity("wind_angle_deg", "agent", "number", "deg", 0.0, 180.0,
                 "Unsigned angle between the rotor's facing and the local wind (Avoid Damage's theta)."),
        quantity("alignment", "agent", "number", "1", 0.0, 1.0,
                 "How squarely the rotor faces into the wind: 1 upwind, 0 downwind (the paper's theta)."),
        quantity("wind_force", "agent", "number", "1", 0.0, 1.0,
                 "The paper's W(theta): 0 below the alignment threshold, rising linearly to 1."),
        quantity("performance", "agent", "number", "1", 0.0, top,
                 "The turbine's performance P, unclamped (Generate Energy pays it clamped to [0, 1])."),
    ]
    return {q.name: q for q in items}


READERS = {
    "x_m": lambda s, e, c: s.positions[..., 0],
    "y_m": lambda s, e, c: s.positions[..., 1],
    "heading_rad": lambda s, e, c: s.heading,
    "wind_direction_rad": lambda s, e, c: s.local_wind,
    # the wind model draws a reset's main direction in [0, 2 pi) and wraps it from the first step on
    "main_wind_direction_rad": lambda s, e, c: wrap_angle(s.wind.main),
    "wind_angle_deg": lambda s, e, c: np.degrees(angle_between(s.heading, s.local_wind)),
    "alignment": lambda s, e, c: alignment(s.heading, s.local_wind),
    "wind_force": lambda s, e, c: wind_force(alignment(s.heading, s.local_wind), c.params.alignment_threshold),
    "performance": lambda s, e, c: s.performance,
}

# the wind of the HIVEX Wind component (and of the paper) is a direction field without a speed: a turbine's
# performance follows its alignment alone
NOT_MODELLED = {
    "wind_speed": "the wind (the original's Wind component) has a direction and no speed, and a turbine's "
                  "performance follows its alignment alone; read wind_direction_rad, wind_angle_deg, alignment or "
                  "wind_force.",
}

VOCABULARY = Vocabulary("wind_farm_control", declare, READERS, not_modelled=NOT_MODELLED)
