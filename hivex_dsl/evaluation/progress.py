"""Progress bars of the long commands (run, evaluate, render, audit, preview, train): one tqdm bar on stderr with
the rate and the time left, shown only where stderr is a terminal and never under ``--json``.

A bar that is not shown prints nothing at all, so piped or logged output stays clean. Lines to print while a bar
is on screen go through :func:`echo`, which clears the bar first and redraws it after.
"""

from __future__ import annotations

import sys
from typing import Optional, TextIO

from tqdm import tqdm


def on_terminal(stream: TextIO) -> bool:
    """Whether ``stream`` is a terminal (a closed or odd stream is not)."""
    isatty = getattr(stream, "isatty", None)
    try:
        return bool(isatty is not None and isatty())
    except (ValueError, OSError):
        return False


def bar(total: Optional[float], desc: str = "", unit: str = "step", enabled: bool = True,
        stream: Optional[TextIO] = None, **options) -> tqdm:
    """A bar over ``total`` units on ``stream`` (stderr, looked up now); silent unless ``enabled`` and the stream is
    a terminal. Use it as a context manager, or close it; it leaves no line behind unless ``leave=True``.
    ``options`` go to tqdm (``initial``, ``unit_scale``, ...)."""
    stream = sys.stderr if stream is None else stream
    return tqdm(total=total, desc=desc, unit=unit, file=stream, disable=not (enabled and on_terminal(stream)),
                **{"dynamic_ncols": True, "leave": False, **options})


def echo(text: str, stream: Optional[TextIO] = None) -> None:
    """Print a line to ``stream`` (stdout) without tearing a bar that is on screen."""
    tqdm.write(text, file=sys.stdout if stream is None else stream)


class EpisodeBar:
    """What :func:`hivex_dsl.evaluation.rollout.rollout` reports of its episodes, on ``shown``, a bar over decisions:
    each episode counts as ``decisions`` long (the most it can last), and one that ends early jumps to its end.

    ``say`` (optional) is called with each finished episode's line (``hivex run`` prints them on stderr)."""

    def __init__(self, shown: tqdm, decisions: int, say=None):
        self.bar, self.decisions, self.say = shown, decisions, say

    def step(self, episode: int, step: int, length: int) -> None:
        if step <= self.decisions:
            self.bar.update(1)

    def episode_done(self, episode: int, mean_return: float, steps: int) -> None:
        self.bar.update(max(0, self.decisions - steps))
        if self.say is not None:
            self.say(episode, mean_return, steps)

    def close(self) -> None:
        self.bar.close()


__all__ = ["EpisodeBar", "bar", "echo", "on_terminal"]
