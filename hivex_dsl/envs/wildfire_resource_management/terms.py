"""The three reward terms of Wildfire Resource Management, as the paper's appendix equations and prose.

Appendix "Reward Description and Calculation: Wildfire Resource Management": each tower's
performance P comes from the distance d1 to the closest observed fire and whether it approaches
(m = d1 < d0), through a broken power law. The equation is defined for d1 <= d_thresh (beyond it
the remapped distance of an approaching fire turns negative), so a tower performs only for a fire
within d_thresh. A tower's performance p is P times the resources it holds (the original's records: its
performance statistics read the policy). The own tower's term is P times the share the agent keeps for itself,
the neighbourhood term each neighbour's p times the share the agent gives it (the original's records: what its
untrained and trained towers were paid for keeping and giving), and the collective term is the root mean square
of p over all nine towers (the equation). rewards/wildfire_resource_management.yaml's notes give the evidence
for each reading; params name the readings before (P times the kept share squared, the neighbours' summed P
times the whole share given, P alone). The power law takes libm's pow on every processor (hivex_dsl.base.portable):
NumPy's own ** took other kernels on AVX-512 processors, and the rewards' last bits followed the machine.
"""

from __future__ import annotations

import numpy as np

from ...base import portable
from ...base.numeric import clamp
from ...sim.reward.terms import TermRegistry
from .resources import MAX_SUPPORT_TENTHS, NEIGHBOURS, TENTHS

TERMS = TermRegistry("wildfire_resource_management")
POWER_LAW_SCALE = 1000.0  # the paper's d' * 1000 / s
POWER_LAW_EXPONENT = -0.5  # the paper's (...)^(-1/2)
# the most a tower's performance can be: P = 1 times every share on it (the centre: 9.0), so the most either
# weighted term pays, whatever shares weigh it (they add up to at most one)
MAX_HELD = MAX_SUPPORT_TENTHS / TENTHS


def remapped_distance(distance: np.ndarray, approaching: np.ndarray, threshold_m: float) -> np.ndarray:
    """The paper's d1n': 0.5 - 0.5 d1n if m else 0.5 + 0.5 d1n, with d1n = d1 / d_thresh clipped to [0, 1].

    P is defined only for d1 <= d_thresh (:func:`performance_of`), where the clip does nothing; beyond
    d_thresh an approaching fire's d1n' would be negative and the power law undefined.
    """
    normalised = clamp(distance / threshold_m, 0.0, 1.0)
    return np.where(approaching, 0.5 - 0.5 * normalised, 0.5 + 0.5 * normalised)


def broken_power_law(remapped: np.ndarray, s: float, a: float) -> np.ndarray:
    """The paper's d1n'' = P = (1 + (d1n' * 1000 / s)^a)^(-1/2), for d1n' >= 0."""
    return portable.power(1.0 + portable.power(remapped * (POWER_LAW_SCALE / s), a), POWER_LAW_EXPONENT)


def tower_performance(state, params) -> np.ndarray:
    """(B, A) P of every tower; ``idle_performance`` where no burning tree is within ``distance_threshold_m``.

    The simulator computes P once per sighting, under its own params, and keeps it with the sighting
    (``Sighting.performance``): the three terms read it. A hand-made sighting without it is computed here.
    """
    sighting = state.sighting
    if sighting.performance is not None:
        return sighting.performance
    return performance_of(sighting.distance, sighting.approaching, sighting.seen, params)


def held_performance(state, params) -> np.ndarray:
    """(B, A) a tower's performance as Collective and Individual Performance read it: P, times the resources the
    tower holds (its total support in units of one agent's share) under ``performance_weight`` 'resources'."""
    performance = tower_performance(state, params)
    if params.performance_weight == "resources":
        return performance * (state.support / TENTHS)
    return performance


def performance_of(distance: np.ndarray, approaching: np.ndarray, seen: np.ndarray, params) -> np.ndarray:
    """(B, A) P from the distances (B, A) to the closest seen fires (inf where none is ``seen``) and whether
    they approach: broken_power_law(remapped_distance(...)) where the fire is seen within
    ``distance_threshold_m``, else ``idle_performance``.

    Fewer array operations than the two functions, the same floats where the fire is in range
    (elsewhere any value, replaced): a distance is >= 0, so clipping it below is a no-op; a farther
    tower's distance (inf for none) stays finite through the clip; and n * -0.5 is exactly -(0.5 * n).
    """
    in_range = seen & (distance <= params.distance_threshold_m)
    normalised = np.minimum(distance / params.distance_threshold_m, 1.0)
    remapped = normalised * np.where(approaching, -0.5, 0.5)
    remapped += 0.5
    scaled = remapped * (POWER_LAW_SCALE / params.power_law_s)
    performance = portable.power(1.0 + portable.power(scaled, params.power_law_a), POWER_LAW_EXPONENT)
    return np.where(in_range, performance, params.idle_performance)


@TERMS.term(
    "watch_tower_performance", title="Watch Tower Performance", paper_row=1, low=0.0, high=MAX_HELD, sign="bonus",
    timing="dense", scope="agent",
    description=("The own tower's performance P, weighted by the share of its resources the agent keeps for itself, "
                 "so neither what it gives nor what its neighbours give the tower moves the term (own_term_weight "
                 "'kept', the default; 'allocated_kept' also weighs P by the share the agent has allocated, "
                 "'held_kept' by the resources the tower holds, 'kept_squared' is P times the kept share squared, the "
                 "equation as printed)."),
    equation=("R = P * r_supporting,  r_supporting = own allocation to itself in [0, 1] (the paper prints "
              "r_distributed * r_supporting with r_supporting twice; the prose: weighted by the resources distributed "
              "by self to self);  "
              "P = (1 + (d' * 1000 / s)^a)^(-1/2),  d' = 0.5 - 0.5 d1n if m else 0.5 + 0.5 d1n,  "
              "d1n = d1 / d_thresh,  m = d1 < d0  (d_thresh = 200, s = 270, a = 5);  "
              "P = idle_performance (0) without a fire within d_thresh"),
)
def watch_tower_performance(prev, state, actions, params):
    own = state.allocation[..., 0] / TENTHS
    if params.own_term_weight == "held_kept":
        return held_performance(state, params) * own
    if params.own_term_weight == "allocated_kept":
        return tower_performance(state, params) * ((TENTHS - state.budget) / TENTHS) * own
    if params.own_term_weight == "kept":
        return tower_performance(state, params) * own
    return tower_performance(state, params) * own * own


@TERMS.term(
    "neighbour_performance", title="Neighbourhood Performance", paper_row=2, low=0.0, high=MAX_HELD,
    sign="bonus", timing="dense", scope="team",
    description=("The performances of the tower's three neighbouring towers (each P times the resources it holds), "
                 "each weighted by the resource the agent gives that neighbour (neighbour_term_weight 'given_each', "
                 "the default; 'given_total' is the neighbours' summed P times the whole share given)."),
    equation="R_neighbourhood = sum_{i=1..n} p_i * r_given,i over the n = 3 neighbours,  p_i = P_i * the "
             "neighbour's total support in shares,  r_given,i = the agent's allocation to neighbour i in [0, 1]",
)
def neighbour_performance(prev, state, actions, params):
    if params.neighbour_term_weight == "given_each":
        given_each = state.allocation[..., 1:] / TENTHS  # (B, A, 3) the share given each neighbour
        return np.add.reduce(held_performance(state, params).take(NEIGHBOURS, axis=1) * given_each, axis=-1)
    given = np.add.reduce(state.allocation[..., 1:], axis=-1) / TENTHS  # (B, A) resource given to the neighbours
    return np.add.reduce(tower_performance(state, params).take(NEIGHBOURS, axis=1), axis=-1) * given


@TERMS.term(
    "collective_performance", title="Collective Performance", paper_row=3, low=-1.0, high=1.0, sign="mixed",
    timing="dense", scope="global",
    description=("One minus how far the root mean square of all nine towers' performances is from 1; a tower's "
                 "performance is its P times the resources it holds (performance_weight 'resources', the default; "
                 "P alone under 'none'), so a tower holding several shares can overshoot 1."),
    equation="R_collective = 1 - |1 - sqrt(MSE)|,  MSE = (1/n) sum_{i=1..n} (p_i * s_i)^2 over all n = 9 towers,  "
             "s_i = tower i's total support in shares (1 under performance_weight 'none'); at least -1 (all nine "
             "shares on the centre: sqrt(81 / 9) = 3)",
)
def collective_performance(prev, state, actions, params):
    p = held_performance(state, params)
    mean_square = np.add.reduce(p * p, axis=-1) / p.shape[-1]  # np.mean's sum and division, without its overhead
    # the absolute value bites once a tower holds more than one share: its P x support, and so the RMS, can exceed 1
    value = 1.0 - np.abs(1.0 - np.sqrt(mean_square))
    every_agent = np.empty(p.shape)
    every_agent[:] = value[:, None]
    return every_agent
