"""The two reward terms of Wind Farm Control, exactly as the paper's equations."""

from __future__ import annotations

import numpy as np

from ...base.numeric import clamp, constant
from ...sim.reward.terms import TermRegistry
from .simulator import angle_between

TERMS = TermRegistry("wind_farm_control")
_ZERO, _ONE, _TWO, _NINETY = constant(0.0), constant(1.0), constant(2.0), constant(90.0)  # float64 operands


@TERMS.term(
    "generate_energy", title="Generate Energy", paper_row=1, low=0.0, high=1.0, sign="bonus", timing="dense",
    scope="agent",
    description="The turbine's performance: it rises while the rotor faces into the wind and decays by drag.",
    equation="R = max(0, min(1, P)),  P <- P - drag*P + a*W(theta),  W = 0 if theta < 0.5 else Map(theta, 0.5, 1, 0, 1)",
)
def generate_energy(prev, state, actions, params):
    return clamp(state.performance, _ZERO, _ONE)


@TERMS.term(
    "avoid_damage", title="Avoid Damage", paper_row=2, low=0.0, high=1.0, sign="bonus", timing="dense",
    scope="agent",
    description="Highest when the rotor blades are parallel to the wind (facing 90 degrees away from it).",
    equation="R = theta/90 if theta <= 90 else 2 - theta/90,  theta = angle(wind, facing) in degrees",
)
def avoid_damage(prev, state, actions, params):
    theta = np.degrees(angle_between(state.heading, state.local_wind))
    share = theta / _NINETY
    return np.where(theta <= _NINETY, share, _TWO - share)
