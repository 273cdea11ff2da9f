"""The three reward terms of Bee Foraging."""

from __future__ import annotations

import numpy as np

from hivex_dsl.sim.reward.terms import TermRegistry

from .simulator import ENV_ID

TERMS = TermRegistry(ENV_ID)


@TERMS.term("nectar_gathered", title="Nectar Gathered", low=0.0, high=10.0, sign="bonus", timing="event",
            scope="agent", description="The nectar the bee took from a flower this step.")
def nectar_gathered(prev, state, actions, params):
    return state.gathered


@TERMS.term("nectar_delivered", title="Nectar Delivered", low=0.0, high=10.0, sign="bonus", timing="event",
            scope="agent", description="The nectar the bee unloaded at the hive this step.")
def nectar_delivered(prev, state, actions, params):
    return state.delivered


@TERMS.term("flight", title="Flight", low=-1.0, high=0.0, sign="penalty", timing="dense", scope="agent",
            description="-1 for every step the bee flies (hovering is free).")
def flight(prev, state, actions, params):
    return -(np.asarray(actions) != 0).astype(np.float64)
