"""Several training seeds of one cell beside the original's: the measure of :mod:`.compare` for each seed and their
mean, and where the original's mean falls among the seeds.

The original's three runs of a cell are one draw, not three: hivex's pipeline wrote them from one config that
differ only in --run-id, whose env_settings.seed is 5000 in every config that ran (../shared/paper/original-configs/
train), and mlagents-learn seeds torch, NumPy and the Unity environment from it, so they started from the same
weights in the same worlds and parted only by the threaded trainer's timing (the fidelity page's Wind Farm Control
note, where their 200 points correlate at 0.92-0.96). Its band is therefore the spread of that timing, which can be
narrower than the spread between seeds that differ in weights (:func:`band_over_range` says how much: a quarter of
it in Wind Farm Control, about as wide in Aerial Wildfire Suppression), so a seeds' mean outside it can still be a
run drawn as the original's was. :func:`among_seeds` asks that like-with-like question instead: does the original's mean (one run's
worth) fall within the range of our seeds' values, below all of them or above all? Were the original's run one more
draw of the same process as each of ours, it would do so at the shares :func:`exchangeable_shares` gives: with three
seeds half the time within, a quarter below all and a quarter above all.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Sequence

import numpy as np

from .compare import FRACTIONS, CompareError, Ours, RunCurve, measure, number, ours_cell, verdict
from .curves import OriginalCell
from .evidence import RETURN


@dataclass(frozen=True)
class SeedsRow:
    """One panel at one fraction of the original's budget: every training seed's value (``seeds``, in the runs'
    order) and their mean against the original's mean and band."""

    panel: str
    fraction: float
    step: int
    seeds: tuple[Ours, ...]
    mean: float
    lower: float
    upper: float

    @property
    def value(self) -> float | None:
        """The mean of the seeds that have a point near the step (None: none has)."""
        return mean_of_seeds([o.value for o in self.seeds])

    @property
    def verdict(self) -> str:
        """The seeds' mean within, above or below the original's band (``no point`` where no seed has one)."""
        return verdict(self.value, self.lower, self.upper)

    @property
    def among(self) -> str:
        """Where the original's mean falls among the seeds' values (:func:`among_seeds`)."""
        return among_seeds(self.mean, [o.value for o in self.seeds])


def among_seeds(value: float, seeds: Sequence[float | None]) -> str:
    """Where ``value`` (the original's mean, one run's worth: its three runs shared their seed) falls among the
    seeds' known values: ``within`` their range (its ends included), ``below all`` or ``above all`` of them;
    ``too few seeds`` where fewer than two are known."""
    known = [v for v in seeds if v is not None]
    if len(known) < 2:
        return "too few seeds"
    return "below all" if value < min(known) else "above all" if value > max(known) else "within"


def exchangeable_shares(seeds: int) -> dict[str, float]:
    """The shares of points at which one more run, drawn as each of ``seeds`` runs was, falls within their range,
    below all or above all of them: (n - 1) / (n + 1), 1 / (n + 1) and 1 / (n + 1) (n + 1 exchangeable draws,
    each equally likely to be the lowest or the highest)."""
    if seeds < 2:
        raise CompareError(f"a range needs two seeds or more, not {seeds}")
    return {"within": (seeds - 1) / (seeds + 1), "below all": 1 / (seeds + 1), "above all": 1 / (seeds + 1)}


def among_tally(rows: Sequence[SeedsRow]) -> dict[str, int]:
    """How many of ``rows`` hold the original's mean within the seeds' range, below all and above all (the rows with
    fewer than two seeds' values left out)."""
    found = [r.among for r in rows]
    return {word: found.count(word) for word in ("within", "below all", "above all")}


def band_over_range(rows: Sequence[SeedsRow]) -> float | None:
    """The median over ``rows`` of the original's band width over our seeds' range (greatest less least), where two
    or more seeds have values that differ: how much narrower the original's runs, parted by timing alone, spread
    than seeds that differ in weights (None where no row has such a range)."""
    ratios = []
    for r in rows:
        known = [o.value for o in r.seeds if o.value is not None]
        if len(known) >= 2 and max(known) > min(known):
            ratios.append((r.upper - r.lower) / (max(known) - min(known)))
    return float(np.median(ratios)) if ratios else None


SWING_WINDOW = 9  # summary points of the running mean that a point's swing is taken about


def shared_swings(runs: Sequence[RunCurve], panel: str = RETURN, window: int = SWING_WINDOW) -> float | None:
    """How much of their point-to-point swings the training seeds ``runs`` share on ``panel``: the median, over
    pairs of seeds, of the correlation of each one's swings (its values less their running mean over ``window``
    points, the edges left out) at the first seed's summary steps where every seed has a curve (the others
    interpolated). About 1 where the worlds set the swings and the seeds met the same worlds (Wildfire Resource
    Management's fires on the scenario's training worlds: 0.97-0.98); about 0 where each seed's swings are its own,
    and only then does the seeds' range hold the worlds' spread, as :func:`among_seeds` needs it to. None with fewer than two seeds that
    log ``panel``, too few points, or no pair whose swings both vary."""
    logging = [run for run in runs if panel in run.panels]
    if len(logging) < 2:
        return None
    low, high = max(run.steps.min() for run in logging), min(run.steps.max() for run in logging)
    steps = logging[0].steps[(logging[0].steps >= low) & (logging[0].steps <= high)]
    if len(steps) < 3 * window:
        return None
    kernel = np.ones(window) / window
    swings = []
    for run in logging:
        values = np.interp(steps, run.steps, run.panels[panel])
        swings.append((values - np.convolve(values, kernel, mode="same"))[window:-window])
    pairs = [np.corrcoef(a, b)[0, 1] for i, a in enumerate(swings) for b in swings[i + 1:] if a.std() > 0 < b.std()]
    return float(np.median(pairs)) if pairs else None


def swings_words(runs: Sequence[RunCurve]) -> str:
    """A sentence saying how much of their return's swings the seeds ``runs`` share (:func:`shared_swings`), or ""
    where that is not measured."""
    shared = shared_swings(runs)
    if shared is None:
        return ""
    return (f"their return's swings from point to point correlate at {shared:.2f} between seeds (near 1: they met "
            "the same worlds, whose spread their range then leaves out; near 0: each seed's own)")


def among_words(rows: Sequence[SeedsRow], seeds: int) -> str:
    """A sentence counting where the original's mean falls among ``seeds`` seeds over ``rows`` (the points where two
    or more have a value), beside the shares of :func:`exchangeable_shares`."""
    found, shares = among_tally(rows), exchangeable_shares(seeds)
    return (f"the original's mean among our {seeds} seeds, at the {sum(found.values())} points where two or more "
            f"have a value: within their range at {found['within']}, below all at {found['below all']}, above "
            f"all at {found['above all']} (one more seed drawn as ours were: {shares['within']:.0%}, "
            f"{shares['below all']:.0%} and {shares['above all']:.0%} of points; the original's three runs shared "
            "one seed, so its band is their timing's spread, not a seed's)")


def mean_of_seeds(values: Sequence[float | None]) -> float | None:
    """The unweighted mean of the seeds' values that are known, one a seed as the original's mean is of its three
    runs (None where none is)."""
    known = [v for v in values if v is not None]
    return sum(known) / len(known) if known else None


def measure_seeds(runs: Sequence[RunCurve], cell: OriginalCell,
                  fractions: Sequence[float] = FRACTIONS) -> list[SeedsRow]:
    """:func:`measure` of every run (a seed without a point at a panel's fraction counts as none there), and their
    mean, per panel any run shares with the original, in the first run's order."""
    if not runs:
        raise CompareError("no training seed to measure")
    measured = [{(r.panel, r.fraction): r for r in measure(run, cell, fractions)} for run in runs]
    keys = list(dict.fromkeys(key for rows in measured for key in rows))
    rows = []
    for key in keys:
        first = next(m[key] for m in measured if key in m)
        seeds = tuple(m[key].ours if key in m else Ours(None) for m in measured)
        rows.append(SeedsRow(first.panel, first.fraction, first.step, seeds, first.mean, first.lower, first.upper))
    return rows


def seeds_table(rows: Sequence[SeedsRow], labels: Sequence[str]) -> str:
    """:func:`measure_seeds` as a Markdown table: panel, fraction, the original's step, each seed (``labels``: its
    value, the steps it pools, its verdict), the seeds' mean, the original's mean and band, the mean's verdict, and
    where the original's mean falls among the seeds (:func:`among_seeds`)."""
    seeds = "".join(f" {label} |" for label in labels)
    lines = [f"| panel | budget | agent-step |{seeds} mean of seeds | original mean | original band | verdict | "
             "original among seeds |",
             "| --- | --- | --- |" + " --- |" * len(labels) + " --- | --- | --- | --- | --- |"]
    for r in rows:
        each = "".join(f" {ours_cell(o)}{'' if o.value is None else ', ' + verdict(o.value, r.lower, r.upper)} |"
                       for o in r.seeds)
        mean = "-" if r.value is None else number(r.value)
        lines.append(f"| {r.panel} | {r.fraction:.0%} | {r.step:,} |{each} {mean} | {number(r.mean)} | "
                     f"{number(r.lower)} - {number(r.upper)} | {r.verdict} | {r.among} |")
    return "\n".join(lines)


__all__ = ["SeedsRow", "among_seeds", "among_tally", "among_words", "band_over_range", "exchangeable_shares", "mean_of_seeds",
           "measure_seeds", "seeds_table", "shared_swings", "swings_words"]
