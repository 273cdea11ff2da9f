"""Layer 9, replay: `hivex replay`'s page, one self-contained HTML file that plays an episode back with every agent's
reward term by term. It sits beside train (it plays a checkpoint; train never imports it).

record.py rolls and records the episode, trace.py turns it into documented data (``--trace``), page.py builds the
page around it (assets/ holds its script, style and the vendored charting library), sources.py says what plays
(a named policy or a checkpoint), browser.py is the headless Chromium of the page's tests and screenshot. The
command's arguments are the CLI's (cli/replay_command.py). Imports: base, compiler, runtime, sim, evaluation, and
train for a checkpoint (torch, imported when one is played); never the CLI.
"""

from __future__ import annotations

import math
from contextlib import nullcontext
from pathlib import Path
from typing import Any, Callable, Optional, Sequence

from .page import FrameEncoder, MAX_MB, default_frame_step, page_html, write_page
from .record import DEFAULT_SPLIT, Episode, record
from .sources import Player
from .trace import FORMAT, trace_data, write_trace


def replay(players: Sequence[Player], output: Path, frame_step: Optional[int] = None, seed: Optional[int] = None,
           split: str = DEFAULT_SPLIT, steps: Optional[int] = None, max_mb: float = MAX_MB, trace: Optional[Path] = None,
           progress: Optional[Callable[[int], None]] = None) -> dict[str, Any]:
    """Record one episode per player (the same seed for each) and write the page to ``output`` (and the trace to
    ``trace``); -> what was written: {"path", "bytes", "frames", "decisions", "frame_step"}.

    ``frame_step`` defaults to :func:`hivex_dsl.replay.page.default_frame_step` of the longest episode; the page
    must stay within ``max_mb`` (a :class:`hivex_dsl.replay.page.TooLarge` says which frame step would fit)."""
    longest = max(p.compiled.episode_decisions if steps is None else min(steps, p.compiled.episode_decisions)
                  for p in players)
    step = frame_step or default_frame_step(longest)
    expected = len(players) * (math.ceil(longest / step) + 1)
    encoder = FrameEncoder(int(max_mb * 1e6 * 0.9), expected, step, max_mb)  # a tenth left for the data
    with _one_torch_thread(players):
        episodes = [record(p.compiled, p.policy, p.info, step, seed, split, steps, progress, encoder) for p in players]
    data = trace_data(episodes)
    if trace is not None:
        write_trace(data, trace)
    title = f"hivex replay: {episodes[0].compiled.name}" + (
        f" against {episodes[1].compiled.name}" if len(episodes) > 1 else "")
    text = page_html(data, [about(e) for e in episodes], [e.frames for e in episodes], title)
    size = write_page(text, output, max_mb, step)
    return {"path": output, "bytes": size, "frames": sum(len(e.frames) for e in episodes),
            "decisions": max(e.decisions for e in episodes), "frame_step": step}


def _one_torch_thread(players: Sequence[Player]):
    """A checkpoint's network on one torch thread, as `hivex evaluate` plays it: one world's few agents are batches
    too small to share, and on a busy machine torch's thread per core made each step many times slower."""
    if not any(p.info["kind"] == "checkpoint" for p in players):
        return nullcontext()
    from ..train.evaluate import limited_threads

    return limited_threads(1)


def about(episode: Episode) -> dict[str, Any]:
    """The episode's scenario as written (the file's text, when it came from one) and as resolved (its lock)."""
    source = Path(episode.compiled.source)
    written = source.read_text(encoding="utf-8") if source.is_file() else None
    return {"source": episode.compiled.source, "written": written, "lock": episode.compiled.to_lock()}


__all__ = ["Episode", "FORMAT", "MAX_MB", "Player", "about", "record", "replay", "trace_data"]
