"""`hivex bench` part: an expression term against the hand-written term of the same formula.

Both are timed on the same Wind Farm Control states at batch 1 and 256, in a fresh one-core
process like the other measurements. The expression's time includes reading the quantities it
needs from the state (the QuantityFeed's work each step), so the ratio is what a task author pays
for writing the term in YAML instead of Python. The issue's target: at most 1.5x.
"""

from __future__ import annotations

import json
import os
import statistics
import subprocess
import sys
import time
from typing import Any

import numpy as np

ENVIRONMENT = "wind_farm_control"
# registered term -> the same formula over the vocabulary (tests/expressions/test_wfc_as_expressions.py
# checks that they are bit-identical)
PAIRS = {
    "generate_energy": "clip(performance, 0, 1)",
    "avoid_damage": "where(wind_angle_deg <= 90, wind_angle_deg / 90, 2 - wind_angle_deg / 90)",
}
BATCHES = (1, 256)
TARGET_RATIO = 1.5


def _interleaved_us(first, second, seconds: float) -> tuple[float, float]:
    """Median microseconds per call of ``first`` and of ``second``, timed in alternating blocks of calls
    for about ``seconds`` in all, so a change of the machine's load weighs on both alike."""
    first(), second()
    block, samples, start = 64, ([], []), time.perf_counter()
    while time.perf_counter() - start < seconds or len(samples[0]) < 5:
        for call, out in zip((first, second), samples):
            began = time.perf_counter()
            for _ in range(block):
                call()
            out.append((time.perf_counter() - began) / block * 1e6)
    return statistics.median(samples[0]), statistics.median(samples[1])


def measure(term: str, batch: int, seconds: float) -> dict[str, Any]:
    """Microseconds per step of the registered ``term`` and of its expression twin, on the same states."""
    from ..compiler import compile
    from ..runtime import BatchedEnv

    name = f"{term}_expr"
    compiled = compile({"hivex": 1, "environment": ENVIRONMENT, "terms": {name: {"expr": PAIRS[term]}},
                        "weights": {term: 1.0}})
    env = BatchedEnv(compiled, batch=batch)
    env.reset(seed=0)
    prev = env.state
    env.step(np.random.default_rng(0).integers(0, 3, env.shape))
    state, params, feed = env.state, compiled.params, env.feed
    hand = compiled.entry.terms[term].fn
    expression = env.composer.registry[name].fn

    def written_in_yaml():
        feed.advance(state, {})
        return expression(prev, state, None, params)

    hand_us, expr_us = _interleaved_us(lambda: hand(prev, state, None, params), written_in_yaml, seconds)
    return {"term": term, "expression": PAIRS[term], "batch": batch, "agents": compiled.agents,
            "hand_written_us": hand_us, "expression_us": expr_us, "ratio": expr_us / hand_us,
            "target_ratio": TARGET_RATIO}


def run(seconds: float, repeats: int, env: dict[str, str]) -> list[dict[str, Any]]:
    """Every pair at every batch, each ``repeats`` times in a fresh process with ``env``; medians."""
    code = ("import json, sys; from hivex_dsl.evaluation import bench_expressions as b; "
            "print(json.dumps(b.measure(*json.loads(sys.argv[1]))))")
    results = []
    for term in PAIRS:
        for batch in BATCHES:
            runs = []
            for _ in range(repeats):
                out = subprocess.run([sys.executable, "-c", code, json.dumps([term, batch, seconds])],
                                     env=dict(os.environ, **env), capture_output=True, text=True, check=False)
                if out.returncode != 0:
                    raise RuntimeError(f"expression benchmark {term} batch {batch} failed:\n{out.stderr.strip()}")
                runs.append(json.loads(out.stdout.strip().splitlines()[-1]))
            best = dict(runs[0])
            for key in ("hand_written_us", "expression_us"):
                best[key] = statistics.median(r[key] for r in runs)
            best["ratio"] = best["expression_us"] / best["hand_written_us"]
            best["meets_target"] = bool(best["ratio"] <= TARGET_RATIO)
            results.append(best)
    return results


def format_table(results: list[dict[str, Any]]) -> str:
    head = f"{'expression term vs hand-written':<32} {'batch':>5} {'hand us':>9} {'expr us':>9} {'ratio':>6} {'goal':>10}"
    lines = [head, "-" * len(head)]
    for r in results:
        goal = f"{'ok' if r['meets_target'] else 'MISSED'} <={r['target_ratio']:g}x"
        lines.append(f"{r['term']:<32} {r['batch']:>5} {r['hand_written_us']:>9.1f} {r['expression_us']:>9.1f} "
                     f"{r['ratio']:>6.2f} {goal:>10}")
    return "\n".join(lines)
