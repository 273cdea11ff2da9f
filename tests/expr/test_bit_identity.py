"""Formulas of the registered reward terms re-expressed as expressions give the same bits as the
NumPy written by hand: the plan runs the same calls in the written order, with no reassociation."""

from __future__ import annotations

import numpy as np
import pytest

from hivex_dsl.base import portable
from hivex_dsl.base.numeric import clamp, constant
from hivex_dsl.lang.expr import Quantity, compile_expression

QUANTITIES = (
    Quantity("theta_deg", "agent", "number", "deg", 0.0, 180.0, "angle between wind and rotor facing"),
    Quantity("performance", "agent", "number", "1", -2.0, 3.0, "turbine performance"),
    Quantity("remapped", "agent", "number", "1", 0.0, 1.0, "a remapped distance"),
    Quantity("nearby", "agent", "number", "1", 0.0, 50.0, "pebbles nearby"),
    Quantity("dx_m", "agent", "number", "m", -500.0, 500.0, "east offset"),
    Quantity("dy_m", "agent", "number", "m", -500.0, 500.0, "north offset"),
    Quantity("burning", "world", "number", "1", 0.0, 400.0, "burning trees"),
    Quantity("holding", "agent", "bool", "", 0.0, 1.0, "holds a seed"),
)
VOCABULARY = {q.name: q for q in QUANTITIES}
_NINETY, _TWO = constant(90.0), constant(2.0)

FORMULAS = {
    # Wind Farm Control's avoid_damage, as its term writes it
    "where(theta_deg <= 90, theta_deg / 90, 2 - theta_deg / 90)":
        lambda s, p: np.where(s["theta_deg"] <= _NINETY, s["theta_deg"] / _NINETY, _TWO - s["theta_deg"] / _NINETY),
    # Wind Farm Control's generate_energy
    "clip(performance, 0, 1)": lambda s, p: clamp(s["performance"], constant(0.0), constant(1.0)),
    # Wildfire Resource Management's power law, as its term writes it (the same bits on every processor)
    "(1 + (remapped * (2 / 3)) ** 1.5) ** -0.5":
        lambda s, p: portable.power(1.0 + portable.power(s["remapped"] * (2.0 / 3.0), 1.5), -0.5),
    "remapped ** 2 + remapped ** 0.5": lambda s, p: s["remapped"] ** 2 + np.sqrt(s["remapped"]),
    # Ocean Plastic Collection's pebble gain
    "max(delta(nearby), 0)": lambda s, p: np.maximum(s["nearby"] - p["nearby"], 0.0),
    # Ocean Plastic Collection's lowest count, one value per world
    "0.5 * team_min(nearby)": lambda s, p: 0.5 * s["nearby"].min(axis=1),
    "team_mean(performance) * 2": lambda s, p: s["performance"].mean(axis=1) * 2.0,
    "team_sum(nearby) - burning": lambda s, p: s["nearby"].sum(axis=1) - s["burning"],
    "nearby / (burning + 1)": lambda s, p: s["nearby"] / (s["burning"][:, None] + 1.0),
    # Drone-Based Reforestation's energy cost while holding a seed
    "where(prev(holding), -1 / 250, 0)": lambda s, p: np.where(p["holding"], -1.0 / 250, 0.0),
    "exp(-(sqrt(dx_m ** 2 + dy_m ** 2) / 100{m}) ** 2)":
        lambda s, p: portable.exp(-(np.sqrt(s["dx_m"] ** 2 + s["dy_m"] ** 2) / 100.0) ** 2),
    "log(1 + abs(performance)) - performance * performance / 3":
        lambda s, p: portable.log(1 + np.abs(s["performance"])) - s["performance"] * s["performance"] / 3,
}


def states(rng, batch, agents=8):
    values = {}
    for q in QUANTITIES:
        shape = (batch, agents) if q.per == "agent" else (batch,)
        values[q.name] = rng.random(shape) < 0.5 if q.kind == "bool" else rng.uniform(q.low, q.high, shape)
    return values


@pytest.mark.parametrize("batch", [1, 256])
@pytest.mark.parametrize("source", FORMULAS)
def test_an_expression_gives_the_bits_of_its_hand_written_formula(source, batch):
    rng = np.random.default_rng(batch)
    expression = compile_expression(source, VOCABULARY, agents=8)
    for _ in range(5):
        now, before = states(rng, batch), states(rng, batch)
        got, expected = expression.evaluate(now, before), FORMULAS[source](now, before)
        assert got.dtype == expected.dtype == np.float64 and got.shape == expected.shape
        assert np.array_equal(got.view(np.uint64), expected.view(np.uint64)), source
