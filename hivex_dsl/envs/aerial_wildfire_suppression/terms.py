"""The reward terms of Aerial Wildfire Suppression: the paper's nine plus the original's wait for water.

Each term carries the paper's magnitude (-100, +1, +10, ...); the reward table's columns are the
paper's task multipliers. Events are read from the state the step wrote, so terms are pure reads.
"""

from __future__ import annotations

import numpy as np

from ...base.numeric import and_not, constant
from ...sim.reward.terms import TermRegistry

TERMS = TermRegistry("aerial_wildfire_suppression")


_MINUS_100, _10, _MINUS_50, _MINUS_0_01, _100, _5 = map(constant, (-100.0, 10.0, -50.0, -0.01, 100.0, 5.0))
# A compile-time check (see __init__.py) keeps a swath from wetting more trees than this.
MAX_TREES_PER_DROP = 2_000


def _per_agent(state, world_values: np.ndarray, scale: np.ndarray) -> np.ndarray:
    """(B,) -> (B, A): ``scale`` times a world-level quantity, given to every plane of the world."""
    every_plane = np.empty(state.flying.shape)
    np.multiply(world_values[:, None], scale, out=every_plane)  # one call: no broadcast_to(...).astype
    return every_plane


@TERMS.term(
    "crossed_border", title="Crossed Border", paper_row=1, low=-100.0, high=0.0, sign="penalty", timing="event",
    scope="agent", description="-100 when the plane leaves the 1500 x 1500 border square; its episode ends.",
    equation="r_cb = -100 if |p_x| > eh or |p_y| > eh (eh = 750) else 0",
)
def crossed_border(prev, state, actions, params):
    return _MINUS_100 * state.crossed


@TERMS.term(
    "pick_up_water", title="Pick-up Water", paper_row=2, low=0.0, high=1.0, sign="bonus", timing="event",
    scope="agent", description="+1 when a plane without water enters the water ring around the island and fills up.",
    equation="r_pw = 1 if ih < max(|p_x|, |p_y|) <= eh and the plane held no water (ih = 600, eh = 750) else 0",
)
def pick_up_water(prev, state, actions, params):
    return state.picked_up.astype(np.float64)  # = 1.0 * picked_up


@TERMS.term(
    "fire_out", title="Fire Out", paper_row=3, low=0.0, high=10.0, sign="bonus", timing="event", scope="global",
    description="+10 to every plane on the step the fire on the whole island dies out, helped or not.",
    equation="r_nb = 10 when no tree burns any more (once, on the step the fire goes out) else 0",
)
def fire_out(prev, state, actions, params):
    paid = _per_agent(state, state.fire_went_out, _10)
    return paid * state.flying if params.finished_planes == "wait" else paid  # a waiting plane is frozen: no pay


@TERMS.term(
    "too_close_to_village", title="Too Close to Village", paper_row=4, low=-50.0, high=0.0, sign="penalty",
    timing="event", scope="global",
    description="-50 to every plane, once per episode, when a burning tree comes within 150 m of the village centre.",
    equation="r_cv = -50 if some tree within 150 m of the village burns (first time this episode) else 0",
)
def too_close_to_village(prev, state, actions, params):
    return _per_agent(state, state.village_threatened, _MINUS_50)


@TERMS.term(
    "time_step_burning", title="Time Step Burning", paper_row=5, low=-0.01, high=0.0, sign="penalty",
    timing="dense", scope="global", description="-0.01 every step while some tree on the island burns.",
    equation="r_tsb = -0.01 if some tree burns else 0",
)
def time_step_burning(prev, state, actions, params):
    return _per_agent(state, state.burning, _MINUS_0_01)


@TERMS.term(
    "find_fire", title="Find Fire", paper_row=6, low=0.0, high=100.0, sign="bonus", timing="event", scope="agent",
    description="+100 the first time in an episode a burning tree is within the plane's 150 m view square.",
    equation="r_f = 100 if a burning tree lies within +/-150 m of p (first time this episode) else 0",
)
def find_fire(prev, state, actions, params):
    return _100 * state.found_fire


@TERMS.term(
    "find_village", title="Find Village", paper_row=7, low=0.0, high=100.0, sign="bonus", timing="event",
    scope="agent", description="+100 the first time in an episode the plane is within 150 m of the village centre.",
    equation="r_v = 100 if |p - village| <= 150 (first time this episode) else 0",
)
def find_village(prev, state, actions, params):
    return _100 * state.found_village


@TERMS.term(
    "extinguishing_tree", title="Extinguishing Tree", paper_row=8, low=0.0, high=5.0 * MAX_TREES_PER_DROP,
    sign="bonus", timing="event", scope="agent",
    description="+5 for every burning tree this plane's water drop turned wet.",
    equation="r_e = 5 * sum_t [t_prev = burning and t = wet]",
)
def extinguishing_tree(prev, state, actions, params):
    return _5 * state.extinguished


@TERMS.term(
    "preparing_tree", title="Preparing Tree", paper_row=9, low=0.0, high=1.0 * MAX_TREES_PER_DROP, sign="bonus",
    timing="event", scope="agent", description="+1 for every existing (not burning) tree this plane's water drop turned wet.",
    equation="r_p = sum_t [t_prev = existing and t = wet]",
)
def preparing_tree(prev, state, actions, params):
    return state.prepared.astype(np.float64)  # = 1.0 * prepared


@TERMS.term(
    "time_step_without_water", title="Time Step Without Water", paper_row=None, low=-1.0, high=0.0, sign="penalty",
    timing="dense", scope="agent",
    description="The original's cost of waiting in the pick-up-water task: -water_wait_penalty per step without water.",
    equation="r_w = -water_wait_penalty (100 / 3000) while the plane holds no water else 0",
)
def time_step_without_water(prev, state, actions, params):
    charged = and_not(state.flying, state.water)
    # under finished_planes: wait the release charges every step of the shared episode, a waiting plane's too (the
    # term's contract, which fingerprints hash, is left as it was: records trained on it stay matched)
    if params.finished_planes == "wait":
        charged = charged | ~state.flying
    return -params.water_wait_penalty * charged
