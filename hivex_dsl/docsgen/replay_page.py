"""docs/replay.md's values, read from the code: the trace's fields and format, the page's defaults."""

from __future__ import annotations

import re
from importlib import resources
from typing import Any

PAGE = "replay.md"


def replay_context() -> dict[str, Any]:
    from ..replay import page, trace
    from ..replay.record import DEFAULT_SPLIT

    library = resources.files("hivex_dsl.replay").joinpath("assets", "uPlot.iife.min.js").read_text(encoding="utf-8")
    version = re.search(r"uPlot \(v([0-9.]+)\)", library[:200])
    return {"fields": trace.FIELDS, "format": trace.FORMAT, "digits": trace.DIGITS, "default_split": DEFAULT_SPLIT,
            "min_frame_step": page.MIN_FRAME_STEP, "default_frames": page.DEFAULT_FRAMES, "max_mb": f"{page.MAX_MB:g}",
            "uplot_version": version.group(1) if version else "(unknown version)"}
