"""The replay page: one self-contained HTML file (no server, no network) that plays recorded episodes back.

Everything is inlined: the page's own script and style (``assets/replay.js``, ``assets/replay.css``), the charting
library uPlot (``assets/uPlot.iife.min.js``, MIT, its licence beside it), the trace (:mod:`hivex_dsl.replay.trace`)
gzip-compressed and base64-encoded (the browser's ``DecompressionStream`` opens it), and the frames as data URIs,
each the smaller of a PNG quantised to 256 colours like `hivex render`'s GIF frames and a WebP. A page larger than
its bound is refused with the frame step that would fit.
"""

from __future__ import annotations

import base64
import gzip
import html
import io
import json
import math
from importlib import resources
from pathlib import Path
from typing import Any, Sequence

import numpy as np

from ..base.errors import HivexError

MAX_MB = 5.0  # the default bound of a page (MB, 10^6 bytes): a default main-task episode of every environment fits
DEFAULT_FRAMES = 100  # a default frame step keeps about this many frames of a whole episode
MIN_FRAME_STEP = 10  # `hivex render`'s default frame step: the default never samples more often
WEBP_QUALITY = 80


def default_frame_step(decisions: int) -> int:
    """`hivex render`'s step, or larger for a long episode so that about :data:`DEFAULT_FRAMES` frames are kept."""
    return max(MIN_FRAME_STEP, math.ceil(decisions / DEFAULT_FRAMES))


class TooLarge(HivexError):
    """The page would exceed its size bound."""


class FrameEncoder:
    """Turns rendered frames into data URIs and refuses early, after a few frames, a page whose frames alone would
    exceed ``budget`` bytes (the projection: the mean size so far times the frames to come)."""

    def __init__(self, budget: int, expected: int, frame_step: int, bound_mb: float):
        self.budget, self.expected, self.frame_step, self.bound_mb = budget, expected, frame_step, bound_mb
        self.count = self.bytes = 0

    def __call__(self, frame: np.ndarray) -> str:
        uri = frame_uri(frame)
        self.count += 1
        self.bytes += len(uri)
        projected = self.bytes / self.count * max(self.expected, self.count)
        if self.count >= 3 and projected > self.budget:
            raise TooLarge(too_large(projected, self.bound_mb, self.frame_step))
        return uri

    def __repr__(self) -> str:  # shows in a progress description
        return f"FrameEncoder({self.count} frames, {self.bytes} bytes)"


def frame_uri(frame: np.ndarray) -> str:
    """One (H, W, 3) uint8 frame as a data URI: a PNG of at most 256 colours (undithered, as `hivex render`'s GIF
    frames) or a lossy WebP, whichever is smaller (the palette suits flat drawings, WebP a shaded terrain)."""
    from PIL import Image

    image = Image.fromarray(np.ascontiguousarray(frame))
    png = io.BytesIO()
    image.quantize(colors=256, method=Image.Quantize.FASTOCTREE, dither=Image.Dither.NONE).save(png, "PNG",
                                                                                                optimize=True)
    webp = io.BytesIO()
    image.save(webp, "WEBP", quality=WEBP_QUALITY)
    mime, data = min((("image/png", png.getvalue()), ("image/webp", webp.getvalue())), key=lambda c: len(c[1]))
    return f"data:{mime};base64,{base64.b64encode(data).decode('ascii')}"


def too_large(size: float, bound_mb: float, frame_step: int) -> str:
    """The refusal of a page of ``size`` bytes over ``bound_mb``, with a frame step that would bring it under."""
    factor = size / (bound_mb * 1e6)
    return (f"the replay would be about {size / 1e6:.1f} MB, over its bound of {bound_mb:g} MB: give a larger "
            f"--frame-step (at least {math.ceil(frame_step * factor * 1.2)}, now {frame_step}), fewer --steps, or a "
            f"larger --max-mb")


def _asset(name: str) -> str:
    return resources.files("hivex_dsl.replay").joinpath("assets", name).read_text(encoding="utf-8")


def packed(data: Any) -> str:
    """``data`` as compact JSON, gzip-compressed, base64-encoded (what the page's script unpacks)."""
    raw = json.dumps(data, separators=(",", ":"), allow_nan=False).encode("utf-8")
    return base64.b64encode(gzip.compress(raw, compresslevel=9, mtime=0)).decode("ascii")


def page_html(trace: dict[str, Any], about: Sequence[dict[str, Any]], frames: Sequence[Sequence[str]], title: str
              ) -> str:
    """The page: ``trace`` (:func:`hivex_dsl.replay.trace.trace_data`), ``about`` each episode's scenario as written
    and as resolved, and ``frames`` each episode's data URIs."""
    page = _asset("page.html")
    parts = {
        "@@TITLE@@": html.escape(title),
        "@@UPLOT_CSS@@": _asset("uPlot.min.css"),
        "@@CSS@@": _asset("replay.css"),
        "@@UPLOT_JS@@": _asset("uPlot.iife.min.js"),
        "@@JS@@": _asset("replay.js"),
        "@@DATA@@": packed({"trace": trace, "about": list(about)}),
        "@@FRAMES@@": json.dumps([list(f) for f in frames]),
    }
    for marker, text in parts.items():
        page = page.replace(marker, text.replace("</script", "<\\/script"))
    return page


def write_page(text: str, path: Path, bound_mb: float, frame_step: int) -> int:
    """Write the page to ``path`` unless it exceeds ``bound_mb``; -> its size in bytes."""
    size = len(text.encode("utf-8"))
    if size > bound_mb * 1e6:
        raise TooLarge(too_large(size, bound_mb, frame_step))
    path.write_text(text, encoding="utf-8")
    return size


__all__ = ["DEFAULT_FRAMES", "FrameEncoder", "MAX_MB", "TooLarge", "default_frame_step", "frame_uri", "packed",
           "page_html", "write_page"]
