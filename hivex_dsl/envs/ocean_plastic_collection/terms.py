"""The seven reward terms of Ocean Plastic Collection, as the paper's reward description and equations
(Appendix, Reward Description and Calculation: Ocean Plastic Collection). Where the prose and the
equation disagree (Close to Other Vessel, Collide with Trash), the published test results decide;
``notes`` in rewards/ocean_plastic_collection.yaml gives each reading and its evidence."""

from __future__ import annotations

import numpy as np

from ...sim.procgen.pollution import PollutionSpec
from ...sim.reward.terms import TermRegistry

TERMS = TermRegistry("ocean_plastic_collection")

LOWEST_COUNT_FACTOR = 0.01  # [paper] a
CRASH_PENALTY = -100.0  # [paper] crossing the border, colliding with another vessel
CLOSE_REWARD = 1.0  # [paper] prose and the original README (the equation prints 10)
TRASH_COLLISION_PENALTY = -1.0  # [paper] prose and the original README (the equation prints -100)


def _largest_pebble_count() -> int:
    """The upper bound of PollutionSpec.pebble_count: no step can collect or see more pebbles."""
    bounds = [m.le for m in PollutionSpec.model_fields["pebble_count"].metadata if getattr(m, "le", None) is not None]
    return int(bounds[0])


MAX_PEBBLES = _largest_pebble_count()


@TERMS.term(
    "collect_trash", title="Collect Trash", paper_row=1, low=0.0, high=float(MAX_PEBBLES), sign="bonus",
    timing="event", scope="agent",
    description="+1 for each floating plastic pebble the vessel's collector picked up this step.",
    equation="r_t = sum_i I(p_i is collected)",
)
def collect_trash(prev, state, actions, params):
    return state.collected.astype(np.float64)


@TERMS.term(
    "lowest_collected_trash_count", title="Global Lowest Trash Collected", paper_row=2, low=0.0,
    high=LOWEST_COUNT_FACTOR * MAX_PEBBLES * MAX_PEBBLES, sign="bonus", timing="event", scope="global",
    description="For every pebble collected anywhere in the world this step, every vessel gets 0.01 times the "
                "lowest count of pebbles any vessel of the world has collected so far this episode (paid on "
                "collection, not on every step: the published Global Reward, see the reward table's notes).",
    equation="R(T) = a * min(t_1, ..., t_n) * c,  a = 0.01,  c = pebbles collected in the world this step",
)
def lowest_collected_trash_count(prev, state, actions, params):
    lowest = state.collected_total.min(axis=1, keepdims=True)
    collected_in_world = state.collected.sum(axis=1, keepdims=True)
    return np.zeros(state.collected_total.shape) + LOWEST_COUNT_FACTOR * lowest * collected_in_world


@TERMS.term(
    "crossed_border", title="Crossed Border", paper_row=3, low=CRASH_PENALTY, high=0.0, sign="penalty",
    timing="event", scope="agent",
    description="-100 on the step the vessel leaves the square world (half extent 200 m).",
    equation="r_cb = -100 if p_x > eh or p_x < -eh or p_y > eh or p_y < -eh else 0,  eh = 200",
)
def crossed_border(prev, state, actions, params):
    return np.where(state.crossed_border, CRASH_PENALTY, 0.0)


@TERMS.term(
    "collided_with_other_vessel", title="Collided with Other Vessel", paper_row=4, low=CRASH_PENALTY, high=0.0,
    sign="penalty", timing="event", scope="agent",
    description="-100 on the step the vessel collides with another vessel (both get it).",
    equation="r_c = -100 if exists n in N_p with p colliding with n else 0",
)
def collided_with_other_vessel(prev, state, actions, params):
    return np.where(state.collided_vessel, CRASH_PENALTY, 0.0)


@TERMS.term(
    "close_to_other_vessel", title="Close to Other Vessel", paper_row=5, low=0.0, high=CLOSE_REWARD, sign="bonus",
    timing="dense", scope="agent",
    description="+1 every step the closest other vessel still in the world is at most close_distance_m (10 m) away.",
    equation="r = 1 if d <= d_thresh else 0,  d = distance to the closest other vessel, d_thresh = 10",
)
def close_to_other_vessel(prev, state, actions, params):
    return np.where(state.closest <= params.close_distance_m, CLOSE_REWARD, 0.0)


@TERMS.term(
    "nearby_trash_count_delta", title="Nearby Trash Count Delta", paper_row=6, low=0.0, high=float(MAX_PEBBLES),
    sign="bonus", timing="dense", scope="agent",
    description="The rise, if any, of the count of floating pebbles nearer than nearby_radius_m (25 m) above the "
                "highest count of the vessel's episode so far (the prose's running maximum); that highest count "
                "is 0 before the first step, so an episode pays its highest nearby count in all.",
    equation="ntc = sum_i [dist(p_i) < 25],  r = max(0, ntc_current - ntc_old),  "
             "ntc_old <- ntc_current when ntc_current > ntc_old",
)
def nearby_trash_count_delta(prev, state, actions, params):
    return np.maximum(state.nearby - prev.nearby_best, 0).astype(np.float64)


@TERMS.term(
    "collide_with_trash", title="Collide with Trash", paper_row=7, low=TRASH_COLLISION_PENALTY, high=0.0,
    sign="penalty", timing="event", scope="agent",
    description="-1 on a step the vessel runs into (and so picks up) at least one floating pebble.",
    equation="r_p = -1 if exists p_t in P_t with p colliding with p_t else 0",
)
def collide_with_trash(prev, state, actions, params):
    return np.where(state.collected > 0, TRASH_COLLISION_PENALTY, 0.0)
