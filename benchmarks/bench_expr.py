"""Time expression terms against the same formulas written by hand: ``python benchmarks/bench_expr.py``.

Plain script, not collected by pytest. For each formula it prints the median time per call of the
hand-written NumPy function and of the compiled expression (both reading their inputs from the
same dicts of arrays) at batch 1 and batch 256 with 8 agents, and their ratio; issue 18 asks for
at most 1.5. Run it on an otherwise idle machine: each figure is the median of 7 repeats of a
timed loop of calls.
"""

from __future__ import annotations

import time
from typing import Callable

import numpy as np

from hivex_dsl.lang.expr import Quantity, compile_expression
from hivex_dsl.base.numeric import clamp, constant

AGENTS = 8
QUANTITIES = (
    Quantity("theta_deg", "agent", "number", "deg", 0.0, 180.0, "angle between wind and rotor facing"),
    Quantity("performance", "agent", "number", "1", -2.0, 3.0, "turbine performance"),
    Quantity("dx_m", "agent", "number", "m", -500.0, 500.0, "east offset"),
    Quantity("dy_m", "agent", "number", "m", -500.0, 500.0, "north offset"),
    Quantity("burning", "world", "number", "1", 0.0, 400.0, "burning trees"),
    Quantity("holding", "agent", "bool", "", 0.0, 1.0, "holds a seed"),
)
_0, _1, _2, _90 = constant(0.0), constant(1.0), constant(2.0), constant(90.0)

# (expression, hand-written formula over (now, before))
FORMULAS: tuple[tuple[str, Callable], ...] = (
    ("clip(performance, 0, 1)", lambda s, p: clamp(s["performance"], _0, _1)),
    ("where(theta_deg <= 90, theta_deg / 90, 2 - theta_deg / 90)",
     lambda s, p: np.where(s["theta_deg"] <= _90, s["theta_deg"] / _90, _2 - s["theta_deg"] / _90)),
    ("exp(-(sqrt(dx_m ** 2 + dy_m ** 2) / 100{m}) ** 2)",
     lambda s, p: np.exp(-(np.sqrt(s["dx_m"] ** 2 + s["dy_m"] ** 2) / 100.0) ** 2)),
    ("max(delta(performance), 0)", lambda s, p: np.maximum(s["performance"] - p["performance"], 0.0)),
    ("team_mean(performance) - burning / 400", lambda s, p: s["performance"].mean(axis=1) - s["burning"] / 400.0),
    ("where(prev(holding), -1 / 250, 0)", lambda s, p: np.where(p["holding"], -1.0 / 250, 0.0)),
)


def per_call_us(call: Callable[[], object], number: int = 2000, repeat: int = 7) -> float:
    """Median over ``repeat`` loops of ``number`` calls of the time per call, in microseconds."""
    call()
    loops = []
    for _ in range(repeat):
        start = time.perf_counter()
        for _ in range(number):
            call()
        loops.append((time.perf_counter() - start) / number)
    return 1e6 * float(np.median(loops))


def states(rng: np.random.Generator, batch: int) -> dict[str, np.ndarray]:
    values = {}
    for q in QUANTITIES:
        shape = (batch, AGENTS) if q.per == "agent" else (batch,)
        values[q.name] = rng.random(shape) < 0.5 if q.kind == "bool" else rng.uniform(q.low, q.high, shape)
    return values


def main() -> None:
    vocabulary = {q.name: q for q in QUANTITIES}
    rng = np.random.default_rng(0)
    print(f"{'formula':<62} {'batch':>5} {'hand us':>8} {'expr us':>8} {'ratio':>6}")
    for source, formula in FORMULAS:
        expression = compile_expression(source, vocabulary, agents=AGENTS)
        for batch in (1, 256):
            now, before = states(rng, batch), states(rng, batch)
            assert np.array_equal(expression.evaluate(now, before), formula(now, before))
            hand = per_call_us(lambda: formula(now, before))
            compiled = per_call_us(lambda: expression.evaluate(now, before))
            print(f"{source:<62} {batch:>5} {hand:>8.2f} {compiled:>8.2f} {compiled / hand:>6.2f}")


if __name__ == "__main__":
    main()
