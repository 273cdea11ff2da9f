"""What the refill loop at the island's coast pays in Aerial Wildfire Suppression's main task, against what the
original's planes logged at the end of their training.

    python benchmarks/aws_loop.py [--levels 1,5,7,10] [--worlds 8] [--params '{"drop_ground": "island"}']
                                  [--generators '{"terrain": {"sea_level_m": 10}}']

The coast looper flies to the nearest point of the island's edge and then circles across it at full turn, asking
for the drop at every step. Past the edge it refills (Pick Up Water, +1); back over the coast, its last frame's
terrain cast on land, it drops and wets the coastal forest (Preparing Trees, +1 a tree); so it refills and drops
about every other step while its circle straddles the coast, and drifts along it. It reads only its own position
and heading from the vector observation, as the scripted pilot does. Beside each level the script prints the
original's training curves at the end of its budget (the mean of its three runs and their lowest and highest: the
fidelity page's band), so the reader sees whether a plane that does nothing but this loop logs what the original's
trained planes logged. The reward table's notes record what it printed (issue 52).
"""

from __future__ import annotations

import argparse
import json
import sys
from typing import Callable

import numpy as np

import hivex_dsl
from hivex_dsl import HivexError
from hivex_dsl.envs.aerial_wildfire_suppression.scripted import coast_target, steer_towards
from hivex_dsl.evaluation.original.curves import original_curves
from hivex_dsl.evaluation.original.evidence import curve_points
from hivex_dsl.evaluation.rollout import rollout

ENVIRONMENT = "aerial_wildfire_suppression"
CIRCLE_FROM_M = 40.0  # the looper starts circling this near its edge point (a full turn's radius is 57 m)
PANELS = ("Cumulative Reward", "Water Drop", "Preparing Trees", "Extinguishing Trees", "Episode Length")


def coast_looper(compiled) -> Callable[[dict], dict]:
    """observations {vector (B, A, 8), ...} -> actions {continuous (B, A, 1), discrete (B, A, 1)}: steer for the
    nearest point of the island's edge, then hold full left turn; always ask for the drop."""
    p = compiled.params
    scale, edge, turn = p.border_half_extent_m, p.island_half_extent_m, np.radians(p.turn_rate_deg)

    def act(observations: dict) -> dict:
        vector = observations["vector"].astype(np.float64)
        position, heading = vector[..., 0:2] * scale, np.arctan2(vector[..., 3], vector[..., 2])
        target = coast_target(position, edge, edge)  # a ring of no width: the edge's nearest point
        far = np.hypot(*np.moveaxis(target - position, -1, 0)) > CIRCLE_FROM_M
        steer = np.where(far, steer_towards(position, heading, target, turn), 1.0)
        drop = np.ones(position.shape[:-1] + (1,), np.int64)
        return {"continuous": steer[..., None].astype(np.float32), "discrete": drop}

    return act


def original_end(level: int) -> dict[str, tuple[float, float, float]]:
    """The original's training mean, lowest and highest run at the end of its budget, per panel of PANELS."""
    cell = original_curves(ENVIRONMENT, 0, level)
    out = {}
    for name in PANELS:
        panel = cell.panel(name) if cell is not None else None
        if panel is not None and panel.training is not None and len(panel.training.band_steps):
            point = curve_points(panel.training, (1.0,))[0]
            out[name] = (point.mean, point.lower, point.upper)
    return out


def looped(level: int, worlds: int, params: dict, generators: dict | None = None) -> dict[str, float]:
    """The looper's plane-episodes over ``worlds`` test episodes (one world each) at ``level``, under the scenario
    ``params`` and ``generators`` overrides: the mean of the return, of Episode Length (decisions) and of every
    logged statistic, by its panel name."""
    compiled = hivex_dsl.compile({"hivex": 1, "environment": ENVIRONMENT, "task": 0, "agents": 3,
                                  "terrain_level": level, "params": params, "generators": generators or {}})
    played = rollout(compiled, coast_looper(compiled), worlds, split="test")
    decisions = np.ceil(played.lengths / compiled.decision_period)
    ours = {"Cumulative Reward": float(played.returns.mean()), "Episode Length": float(decisions.mean())}
    ours.update({name: float(values.mean()) for name, values in played.statistics.items()})
    return ours


def report(level: int, worlds: int, params: dict, generators: dict | None = None) -> list[str]:
    """:func:`looped` at ``level`` beside the original's training at the end of its budget."""
    ours, theirs = looped(level, worlds, params, generators), original_end(level)
    lines = [f"L{level}: coast looper over {worlds} test worlds against the original's training at its end "
             "(mean [lowest run-highest run])"]
    for name in PANELS:
        there = theirs.get(name)
        band = f"{there[0]:.1f} [{there[1]:.1f}-{there[2]:.1f}]" if there else "-"
        lines.append(f"    {name:20s} {ours.get(name, np.nan):8.1f}   original {band}")
    return lines


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--levels", default="1,5,7,10", help="terrain levels, comma-separated")
    parser.add_argument("--worlds", type=int, default=8, help="test worlds (three planes each) a level")
    parser.add_argument("--params", default="{}", help="AWS params as JSON, e.g. '{\"drop_ground\": \"island\"}'")
    parser.add_argument("--generators", default="{}",
                        help="a scenario's generators overrides as JSON, e.g. '{\"terrain\": {\"sea_level_m\": 10}}'")
    args = parser.parse_args(argv)
    try:
        levels = [int(x) for x in args.levels.split(",")]
    except ValueError:
        print(f"aws_loop: --levels: expected terrain levels separated by commas, got {args.levels!r}", file=sys.stderr)
        return 2
    overrides = {}
    for name in ("params", "generators"):
        text = getattr(args, name)
        try:
            overrides[name] = json.loads(text)
        except json.JSONDecodeError as error:
            print(f"aws_loop: --{name}: expected a JSON object, got {text!r} ({error})", file=sys.stderr)
            return 2
    try:
        for level in levels:
            print("\n".join(report(level, args.worlds, overrides["params"], overrides["generators"])), flush=True)
    except (HivexError, ValueError) as error:
        print(f"aws_loop: {error}", file=sys.stderr)
        return 2
    return 0


if __name__ == "__main__":
    sys.exit(main())
