"""Ocean Plastic Collection: how widely trained vessel lives spread, the original's and ours (issue 52).

The original's trained vessel-episodes last about 160 decisions on average; what ends them is not recorded. A
timer-like ending (a fuel, a shift) would give lives near their mean; crashes at a steady rate would spread them as
an exponential does, their standard deviation about their mean (coefficient of variation 1). Neither record keeps
single lives, but both keep summary points, each the mean life of the world-episodes that ended in it, and how much
those points scatter tells how widely the lives behind them spread:

- the original's band at a summary point spans its three runs' least and greatest value (a 95% bootstrap band of
  three runs), and the range of three draws of a normal is 1.693 of its standard deviation on average; a point of
  mean m pools n = 5,000 / m world-episodes (15,000 agent-steps of one world of three vessels, whose episodes end
  together), so the lives' deviation is mean range / 1.693 x sqrt(n);
- the original's mean line: successive points of the three runs' mean differ by the lives' deviation times
  sqrt((1 / n_i + 1 / n_j) / 3), offsets between the runs cancelling;
- ours: each seed's successive points differ by the lives' deviation times sqrt(1 / n_i + 1 / n_j) (n the
  world-episodes a point pools, a third of its agent-episodes).

Differences between runs widen the original's ranges and a trend widens successive differences, so each reads an
upper bound. How often the worlds crash, window by window: a summary point of the original's holds 5,000
decisions of one world, so its rate is 1,000 / its mean life (Episode Length plus the terminal decision ML-Agents
does not count) world-crashes a thousand world-decisions, each window the mean of its points' rates; ours is the
window's world-episodes over its decisions (nearly every life of either ends on a crash: the reward table's ending
note), and the original's rate is set among our seeds' (hivex_dsl.evaluation.original.seeds.among_seeds). Also,
for run folders given with --runs, each one's rates beside them, split into collisions and border crossings from
the reward terms its TensorBoard files log, and its policy entropy beside the original's Entropy panel:

    python benchmarks/opc_life_spread.py [--runs RUN_DIR ...]

reads the original's digitised curves and the committed record (benchmarks/baselines/ocean_plastic_collection.json).
"""

from __future__ import annotations

import argparse
import glob
import json
import sys
from pathlib import Path

import numpy as np

ENV = "ocean_plastic_collection"
RECORD = Path(__file__).resolve().parent / "baselines" / f"{ENV}.json"
FROM = 0.3  # of the budget: past the first learning, where lives have settled
BUDGET = 3_000_000
RANGE_OF_THREE = 1.693  # mean range of three draws of a standard normal
WORLD_DECISIONS = 5_000  # a summary point of 15,000 agent-steps: 5,000 decisions of each of one world's 3 vessels
FRACTIONS = (0.1, 0.25, 0.5, 0.75, 1.0)


def spread_of_ranges(means: np.ndarray, ranges: np.ndarray, world_decisions: float = WORLD_DECISIONS) -> dict:
    """Three runs' summary points: ``means`` (k,) and ``ranges`` (k,), the greatest less the least of the three at
    each -> the lives' mean and coefficient of variation (upper bound), as the module says."""
    worlds = world_decisions / means
    deviation = np.mean(ranges / RANGE_OF_THREE * np.sqrt(worlds))
    return {"mean": float(means.mean()), "cv": float(deviation / means.mean())}


def spread_of_successive(lengths: np.ndarray, worlds: np.ndarray) -> dict:
    """One run's summary points: mean lives ``lengths`` (k,) over ``worlds`` (k,) world-episodes each -> the lives'
    mean and coefficient of variation (upper bound), from how successive points differ."""
    scale = 1.0 / worlds[1:] + 1.0 / worlds[:-1]
    deviation = np.sqrt(np.mean(np.diff(lengths) ** 2 / scale))
    return {"mean": float(lengths.mean()), "cv": float(deviation / lengths.mean())}


def original_spreads(start: float = FROM) -> dict[str, dict]:
    """The original's main-task Episode Length from ``start`` of the budget on, read twice: from its band's ranges
    (``ranges``) and from its mean line's successive points (``mean_line``: the three runs' mean pools three times
    the world-episodes, and offsets between the runs cancel in its differences)."""
    from hivex_dsl.evaluation.original import compare

    training = compare.original_cell(ENV, 0, None).panel("Episode Length").training
    late = training.band_steps >= start * BUDGET
    means = training.mean_at(training.band_steps[late])
    return {"ranges": spread_of_ranges(means, training.upper[late] - training.lower[late]),
            "mean_line": spread_of_successive(means, 3.0 * WORLD_DECISIONS / means)}


def record_spreads(record: dict, start: float = FROM) -> dict[int, dict]:
    """Each training seed of a baseline record (its own and its ``other_seeds``) -> its lives' spread."""
    spreads = {}
    for run in [record, *record.get("other_seeds", [])]:
        steps = np.array([row[0] for row in run["curve"]], dtype=float)
        lengths = np.array(run["curve_panels"]["Episode Length"], dtype=float)
        worlds = np.array(run["curve_episodes"], dtype=float) / 3.0
        late = (steps >= start * BUDGET) & np.isfinite(lengths) & (worlds > 0)
        spreads[run["seed"]] = spread_of_successive(lengths[late], worlds[late])
    return spreads


RATE_WINDOW = 150_000  # agent-steps a window of the crash rates: ten of the original's summary points


def original_crash_rates(window: float = RATE_WINDOW) -> np.ndarray:
    """(w,) the original's world-crashes a thousand world-decisions in each ``window`` of its budget: the mean over
    the window's summary points of 1,000 / (Episode Length + 1)."""
    from hivex_dsl.evaluation.original import compare

    training = compare.original_cell(ENV, 0, None).panel("Episode Length").training
    rates = 1000.0 / (training.mean_at(training.band_steps) + 1.0)
    which = (training.band_steps // window).astype(int)
    return np.array([rates[which == w].mean() for w in range(int(np.ceil(BUDGET / window)))])


def crash_rates(steps: np.ndarray, lengths: np.ndarray, episodes: np.ndarray, window: float = RATE_WINDOW,
                budget: float = BUDGET) -> np.ndarray:
    """(w,) one run's world-crashes a thousand world-decisions in each ``window``: 1,000 x its points' world-episodes
    over their decisions, from each point's step, mean life (decisions) and agent-episodes (k,); NaN where a
    window holds no point."""
    known = np.isfinite(lengths) & (episodes > 0)
    which = (steps // window).astype(int)
    rates = np.full(int(np.ceil(budget / window)), np.nan)
    for w in range(len(rates)):
        here = known & (which == w)
        if here.any():
            rates[w] = 1000.0 * episodes[here].sum() / (lengths[here] * episodes[here]).sum()
    return rates


def record_crash_rates(record: dict, window: float = RATE_WINDOW) -> dict[int, np.ndarray]:
    """Each training seed of a baseline record -> :func:`crash_rates`."""
    return {run["seed"]: crash_rates(np.array([row[0] for row in run["curve"]], dtype=float),
                                     np.array(run["curve_panels"]["Episode Length"], dtype=float),
                                     np.array(run["curve_episodes"], dtype=float), window)
            for run in [record, *record.get("other_seeds", [])]}


def run_crash_rates(run_dir: Path, window: float = RATE_WINDOW) -> np.ndarray:
    """A run folder's :func:`crash_rates`, from its curve.json."""
    points = json.loads((Path(run_dir) / "curve.json").read_text())  # a list of summary points
    lengths = np.array([np.nan if p.get("length") is None else p["length"] for p in points], dtype=float)
    return crash_rates(np.array([p["agent_steps"] for p in points], dtype=float), lengths,
                       np.array([p.get("episodes", 0) for p in points], dtype=float), window)


def tb_scalars(run_dir: Path, tag: str) -> tuple[np.ndarray, np.ndarray]:
    """(steps, values) of one TensorBoard scalar over every event file of a run folder's tb/ (a resumed run writes a
    new file; a later file's value wins at a step both hold)."""
    from tensorboard.backend.event_processing.event_accumulator import EventAccumulator

    found: dict[int, float] = {}
    for name in sorted(glob.glob(str(Path(run_dir) / "tb" / "events.out.tfevents.*"))):
        events = EventAccumulator(name, size_guidance={"scalars": 0})
        events.Reload()
        if tag in events.Tags()["scalars"]:
            found.update({s.step: s.value for s in events.Scalars(tag)})
    steps = np.array(sorted(found), dtype=float)
    return steps, np.array([found[int(s)] for s in steps], dtype=float)


def crash_kinds(run_dir: Path, window: float = RATE_WINDOW, budget: float = BUDGET) -> dict[str, np.ndarray]:
    """(w,) world-crashes a thousand world-decisions by kind, from a run's logged reward terms (each point's mean
    over its vessel-episodes; the points of a window weighed alike): a border crossing charges its vessel -100, so
    a world-episode crosses 3 x (-term / 100) times; a collision charges both vessels, 1.5 x (-term / 100); each
    over the window's mean life (episode/length, decisions; a crash ends its world, so a vessel lives the world's
    life). NaN where a window holds no point."""
    steps, life = tb_scalars(run_dir, "episode/length")
    rates = {}
    for kind, tag, vessels in (("border", "reward_terms/crossed_border", 3.0),
                               ("collision", "reward_terms/collided_with_other_vessel", 1.5)):
        at, term = tb_scalars(run_dir, tag)
        per_world = dict(zip(at, -term / 100.0 * vessels))
        which = (steps // window).astype(int)
        rates[kind] = np.full(int(np.ceil(budget / window)), np.nan)
        for w in range(len(rates[kind])):
            here = [i for i in np.flatnonzero(which == w) if steps[i] in per_world]
            if here:
                rates[kind][w] = 1000.0 * np.mean([per_world[steps[i]] for i in here]) / life[here].mean()
    return rates


def entropy_at(run_dir: Path, fractions=FRACTIONS, window: float = 30_000) -> list[float | None]:
    """A run's mean logged policy entropy (losses/entropy) within ``window`` agent-steps of each fraction."""
    steps, values = tb_scalars(run_dir, "losses/entropy")
    near = [np.abs(steps - f * BUDGET) < window for f in fractions]
    return [float(values[n].mean()) if n.any() else None for n in near]


def _rate(value: float) -> str:
    return "-" if np.isnan(value) else f"{value:.1f}"


def print_crash_rates(runs: list[Path]) -> None:
    """Window by window: the original's rate, each seed of the record's, where the original's lies among them, and
    each of ``runs``'s (not counted among the record's seeds)."""
    from hivex_dsl.evaluation.original.seeds import among_seeds

    original, record = original_crash_rates(), record_crash_rates(json.loads(RECORD.read_text()))
    extra = {str(run): run_crash_rates(run) for run in runs}
    kinds = {str(run): crash_kinds(run) for run in runs}
    print(f"\nworld-crashes a thousand world-decisions, {RATE_WINDOW:,} agent-steps a window: the original | the "
          f"record's seeds {', '.join(map(str, record))} | the original among them"
          + (" | " + ", ".join(extra) + " (collisions + border crossings, from the logged terms)" if extra else ""))
    for w, theirs in enumerate(original):
        ours = [rates[w] for rates in record.values()]
        among = among_seeds(theirs, [None if np.isnan(v) else v for v in ours])
        more = "".join(f" | {_rate(r[w])} ({_rate(k['collision'][w])} + {_rate(k['border'][w])})"
                       for r, k in zip(extra.values(), kinds.values()))
        print(f"  {w * RATE_WINDOW / 1e6:.2f}M: {theirs:.1f} | " + " ".join(f"{v:.1f}" for v in ours)
              + f" | {among}{more}")


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--runs", nargs="*", type=Path, default=[],
                        help="run folders: their entropy (tb/) and crash rates (curve.json)")
    args = parser.parse_args(argv)
    original = original_spreads()
    print(f"the original, from {FROM:.0%} of the budget: mean life {original['ranges']['mean']:.0f} decisions, "
          f"coefficient of variation at most {original['ranges']['cv']:.2f} (its band's ranges) and "
          f"{original['mean_line']['cv']:.2f} (its mean line's successive points)")
    for seed, spread in record_spreads(json.loads(RECORD.read_text())).items():
        print(f"the record, seed {seed}: mean life {spread['mean']:.0f}, coefficient of variation at most "
              f"{spread['cv']:.2f}")
    print_crash_rates(args.runs)
    if args.runs:
        from hivex_dsl.evaluation.original import compare

        entropy = compare.original_cell(ENV, 0, None).panel("Entropy").training
        print("entropy at " + ", ".join(f"{f:.0%}" for f in FRACTIONS) + ": the original "
              + ", ".join(f"{entropy.mean_at(f * BUDGET):.2f}" for f in FRACTIONS))
        for run in args.runs:
            print(f"  {run}: " + ", ".join("-" if v is None else f"{v:.2f}" for v in entropy_at(run)))
    return 0


if __name__ == "__main__":
    sys.exit(main())
