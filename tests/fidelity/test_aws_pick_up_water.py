"""Aerial Wildfire Suppression's Pick Up Water: what a straight flight earns, derived by hand (issue 52, item 8).

The task pays +100 on the pick-up and -100/3000 every step of the episode, and a plane that picked up waits,
frozen and still paying, until the last plane of its world has (the release's AgentManager.AgentDone: the reward
table's notes); so every plane of a world returns 100 - L / 30 for the world's length L, the time its slowest
plane takes, as the original's own pages do point for point (test return 94.3 for Episode Length 167). The
all-zeros plane flies straight on at 5 m a step from a uniform point of the island (at least two steps from the
ring, |x|, |y| <= 590 m) at a uniform heading. For a uniform point of a square of half-side h and a uniform
direction the mean distance to the edge is (2h / pi) (2 ln(1 + sqrt 2) - (2 sqrt 2 - 2) / 3) = 0.9464 h
(integrate the squared chords): 115 steps a plane; the world waits for the slowest of three, whose mean is read
from the same distribution (E max = sum x_(k) ((k / n)^3 - ((k - 1) / n)^3) over its sorted values): 178.8 steps,
a return of 94.04, below the published PPO's 94.7-95.1 at levels 2-10 (its 93.0 at level 1 is the one cell
below, within the audit's margin). The original's untrained policy took 172-250 steps (its first summary
points); a plane alone at 5 m could not (115), the slowest of three can.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

import hivex_dsl
from hivex_dsl.evaluation.published import cell
from hivex_dsl.evaluation.rollout import rollout

EPISODES = 40
LEVEL = 3
MEAN_EDGE_DISTANCE = 2 / math.pi * (2 * math.log(1 + math.sqrt(2)) - (2 * math.sqrt(2) - 2) / 3)  # x half-side
RING, SPEED, PLANES = 600.0, 5.0, 3


@pytest.fixture(scope="module")
def straight():
    compiled = hivex_dsl.compile({"hivex": 1, "environment": "aerial_wildfire_suppression", "task": "pick_up_water",
                                  "terrain_level": LEVEL, "agents": PLANES, "episode_length": 3000,
                                  "seeds": {"train": 5000, "test": 6000}})
    return compiled, rollout(compiled, "zeros", EPISODES, split="test")


def edge_steps(half: float, speed: float) -> np.ndarray:
    """Steps of a straight flight to the ring (floor(d / speed) + 1) from a grid of points of the square of
    half-side ``half`` and a grid of headings: the distribution of one plane's time."""
    u = (np.arange(240) + 0.5) / 240 * 2 * half - half
    t = (np.arange(720) + 0.5) / 720 * 2 * np.pi
    x, y, t = np.meshgrid(u, u, t, indexing="ij", sparse=True)
    c, s = np.cos(t), np.sin(t)  # no heading of the grid lies on an axis
    distance = np.minimum((RING - x * np.sign(c)) / np.abs(c), (RING - y * np.sign(s)) / np.abs(s))
    return np.floor(distance.ravel() / speed) + 1


def mean_of_the_slowest(values: np.ndarray, of: int) -> float:
    x = np.sort(values)
    k = np.arange(1, len(x) + 1) / len(x)
    return float((x * (k ** of - (k - 1 / len(x)) ** of)).sum())


def test_the_mean_edge_distance_constant_by_integration():
    # the square [0, 2]^2 (h = 1): mean of min(u / cos t, v / sin t) over u, v uniform on [0, 2], t on [0, pi/2]
    u = (np.arange(400) + 0.5) / 200
    t = (np.arange(400) + 0.5) / 400 * (np.pi / 2)
    uu, vv, tt = np.meshgrid(u, u, t, indexing="ij", sparse=True)
    assert np.minimum(uu / np.cos(tt), vv / np.sin(tt)).mean() == pytest.approx(MEAN_EDGE_DISTANCE, rel=2e-3)


def test_one_planes_time_and_the_slowest_of_three_by_hand():
    steps = edge_steps(RING - 2 * SPEED, SPEED)
    # from within 590 m to the ring at 600 m: past the mean edge distance of the 590 m square (111.7 steps), and
    # near that of the 600 m square (113.6; the last 10 m crossed at a slant, the last step's half: 115.0)
    assert MEAN_EDGE_DISTANCE * (RING - 2 * SPEED) / SPEED < steps.mean() < MEAN_EDGE_DISTANCE * RING / SPEED + 2
    assert mean_of_the_slowest(steps, 1) == pytest.approx(steps.mean())
    assert mean_of_the_slowest(steps, PLANES) == pytest.approx(178.8, abs=0.3)


def test_a_plane_flies_5_m_a_step_and_waits_for_its_world(straight):
    compiled, done = straight
    assert compiled.params.plane_speed_m == SPEED and compiled.params.finished_planes == "wait"
    assert (done.lengths == done.lengths[:, :1]).all()  # one length a world: its slowest plane's


def test_each_plane_earns_100_less_a_thirtieth_of_its_worlds_steps(straight):
    _, done = straight
    assert (done.statistics["Water Pickup"] == 1).all()
    np.testing.assert_allclose(done.returns, 100 - done.lengths / 30, atol=1e-9)


def test_the_straight_flights_take_the_hand_derived_time(straight):
    _, done = straight
    expected = mean_of_the_slowest(edge_steps(RING - 2 * SPEED, SPEED), PLANES)
    worlds = done.lengths[:, 0]
    assert abs(worlds.mean() - expected) <= 3 * worlds.std() / math.sqrt(worlds.size)


def test_all_zeros_earns_less_than_the_published_ppo(straight):
    _, done = straight
    published = cell("aerial_wildfire_suppression", 5, LEVEL).return_mean  # 94.67
    assert done.returns.mean() < published
