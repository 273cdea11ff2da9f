"""A matplotlib-written PDF page as pdfminer.six reads it: its strings, its painted paths, its axes.

pdfminer.six interprets the content stream (graphics state, transformation matrices, colours, Type 3 text with
its ToUnicode map); this module groups what it hands back as matplotlib drew it: each label one
:class:`Text` (the minus signs and ligatures matplotlib draws outside the first font joined back in), each
painted subpath one :class:`Shape` in drawing order, and each axes the paths and strings drawn from its white
background until the next axes' (:func:`axes_groups`).
"""

from __future__ import annotations

import re
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ...base.errors import HivexError

Box = tuple[float, float, float, float]  # x0, y0, x1, y1 in points


class PlotReadError(HivexError, ValueError):
    """A page is not a matplotlib plot this reader understands (named with the page and the panel)."""


@dataclass(frozen=True)
class Text:
    """One string the page shows (one text-showing operator), its box in points and its drawing order."""

    text: str
    x0: float
    y0: float
    x1: float
    y1: float
    order: int  # the page item index of its first character
    end: int  # one past the index of its last

    @property
    def cx(self) -> float:
        return (self.x0 + self.x1) / 2

    @property
    def cy(self) -> float:
        return (self.y0 + self.y1) / 2


@dataclass(frozen=True)
class Shape:
    """One painted subpath: its vertices (n, 2) in points, how it was painted, and its drawing order."""

    points: np.ndarray
    stroke: bool
    fill: bool
    closed: bool
    stroke_colour: tuple[float, ...]
    fill_colour: tuple[float, ...]
    order: int


def page_contents(path: Path, page_number: int) -> tuple[list[Text], list[Shape], float, float]:
    """One page's labels and painted subpaths in drawing order, and its width and height in points."""
    from pdfminer.converter import PDFPageAggregator
    from pdfminer.layout import LTCurve, LTFigure
    from pdfminer.pdfinterp import PDFPageInterpreter, PDFResourceManager
    from pdfminer.pdfpage import PDFPage

    texts: list[Text] = []

    class _StringCollector(PDFPageAggregator):
        """The aggregator, grouping the characters of each text-showing operator into one :class:`Text`."""

        def render_string(self, textstate, seq, ncs, graphicstate):  # noqa: ANN001 - pdfminer's signature
            before = len(self.cur_item)
            super().render_string(textstate, seq, ncs, graphicstate)
            chars = list(self.cur_item)[before:]
            if chars:
                texts.append(Text("".join(c.get_text() for c in chars), min(c.x0 for c in chars),
                                  min(c.y0 for c in chars), max(c.x1 for c in chars), max(c.y1 for c in chars),
                                  before, len(self.cur_item)))

    try:
        with path.open("rb") as handle:
            pages = list(PDFPage.get_pages(handle, pagenos=[page_number]))
            if not pages:
                raise PlotReadError(f"{path}: has no page {page_number + 1}")
            manager = PDFResourceManager()
            device = _StringCollector(manager, laparams=None)
            PDFPageInterpreter(manager, device).process_page(pages[0])
    except OSError as error:
        raise PlotReadError(f"{path}: cannot be read ({error.strerror or error})") from error
    except PlotReadError:
        raise
    except Exception as error:  # pdfminer's own parse errors have no common base class
        raise PlotReadError(f"{path}: is not a readable PDF ({type(error).__name__}: {error})") from error
    layout = device.get_result()
    shapes = [_shape(item, order) for order, item in enumerate(layout) if isinstance(item, LTCurve)]
    glyphs = [(order, item) for order, item in enumerate(layout) if isinstance(item, LTFigure)]
    texts = [_normalised(t) for t in _labels(texts + _glyph_texts(glyphs))]
    return texts, shapes, layout.width, layout.height


def _glyph_texts(figures: list) -> list[Text]:  # noqa: ANN001 - pdfminer LTFigures
    """The glyphs matplotlib 3.9 draws as form XObjects: a character outside a Type 3 font's 256 codes (the
    minus sign U+2212) is a ``Do`` of an XObject named ``F<n>-<font>-<glyph name>`` at the glyph's origin, right
    after the string's other characters. Their width is unknown: each is a zero-width text at its origin."""
    from pdfminer.encodingdb import name2unicode

    glyphs = []
    for order, figure in figures:
        if re.match(r"^F\d+-.+-.+$", figure.name):
            x, y = figure.matrix[4], figure.matrix[5]
            glyphs.append(Text(name2unicode(figure.name.rsplit("-", 1)[-1]), x, y, x, y, order, order + 1))
    return glyphs


def _joins(last: Text, piece: Text) -> bool:
    """Whether ``piece``, drawn right after ``last``, is more of the same label: on its line and touching it
    (matplotlib 3.10+ shows characters outside the first font's 256 codes in a second Type 3 font, within one
    text object), or a zero-width glyph within one em of it."""
    if piece.order != last.end:
        return False
    em = max(last.y1 - last.y0, piece.y1 - piece.y0)
    if piece.x0 == piece.x1 or last.x0 == last.x1:  # a glyph XObject's origin
        text, glyph = (last, piece) if piece.x0 == piece.x1 else (piece, last)
        return text.y0 <= glyph.y0 <= text.y1 and text.x0 - em <= glyph.x0 <= text.x1 + em
    overlap = min(last.y1, piece.y1) - max(last.y0, piece.y0)
    return overlap > em / 2 and abs(piece.x0 - last.x1) <= 1.0


def _labels(pieces: list[Text]) -> list[Text]:
    """The page's labels: strings drawn one after another on one line, touching, joined in reading order."""
    labels: list[Text] = []
    for piece in sorted(pieces, key=lambda t: t.order):
        last = labels[-1] if labels else None
        if last is not None and _joins(last, piece):
            text = piece.text + last.text if piece.x0 < last.x0 else last.text + piece.text
            labels[-1] = Text(text, min(last.x0, piece.x0), min(last.y0, piece.y0), max(last.x1, piece.x1),
                              max(last.y1, piece.y1), last.order, piece.end)
        else:
            labels.append(piece)
    return labels


def _normalised(text: Text) -> Text:
    """A text with matplotlib's minus sign (U+2212) as ASCII ``-``, so numbers parse."""
    return Text(text.text.replace("\u2212", "-"), text.x0, text.y0, text.x1, text.y1, text.order, text.end)


def _colour(value: object) -> tuple[float, ...]:
    if value is None:
        return ()
    if isinstance(value, (int, float)):
        return (float(value),) * 3  # a grey level
    return tuple(float(v) for v in value)  # type: ignore[union-attr]


def _shape(item, order: int) -> Shape:  # noqa: ANN001 - a pdfminer LTCurve
    ops = item.original_path or []
    points = np.array([op[-1] for op in ops if op[0] in "ml"], dtype=float).reshape(-1, 2)
    closed = bool(ops) and ops[-1][0] == "h"
    return Shape(points, bool(item.stroke), bool(item.fill), closed, _colour(item.stroking_color),
                 _colour(item.non_stroking_color), order)


def _is_axes_background(shape: Shape, width: float, height: float) -> bool:
    """Matplotlib's axes patch: a white, filled, unstroked rectangle smaller than the page."""
    if not (shape.fill and not shape.stroke and shape.closed and len(shape.points) == 4):
        return False
    if shape.fill_colour[:3] != (1.0, 1.0, 1.0):
        return False
    (x0, y0), (x1, y1) = shape.points.min(axis=0), shape.points.max(axis=0)
    return not (x0 <= 0 and y0 <= 0 and x1 >= width and y1 >= height)




def axes_groups(shapes: list[Shape], texts: list[Text], width: float, height: float
                 ) -> list[tuple[Box, list[Shape], list[Text]]]:
    """Each axes' box and the shapes and strings drawn from its background until the next axes' background
    (matplotlib draws one axes whole before the next)."""
    starts = [s for s in shapes if _is_axes_background(s, width, height)]
    groups = []
    for i, start in enumerate(starts):
        end = starts[i + 1].order if i + 1 < len(starts) else float("inf")
        (x0, y0), (x1, y1) = start.points.min(axis=0), start.points.max(axis=0)
        groups.append(((x0, y0, x1, y1), [s for s in shapes if start.order < s.order < end],
                       [t for t in texts if start.order <= t.order < end]))
    return groups


def figure_title(texts: list[Text], groups: list, height: float) -> str:
    """The figure's suptitle: the topmost string above every axes (``""`` if none)."""
    top = max(box[3] for box, _, _ in groups)
    above = [t for t in texts if t.y0 > top and t.y1 <= height]
    return max(above, key=lambda t: t.y0).text.strip() if above else ""


def axes_title(box: Box, texts: list[Text], where: str) -> str:
    """The axes title: the string centred over the box, just above it."""
    x0, _, x1, y1 = box
    over = [t for t in texts if abs(t.cx - (x0 + x1) / 2) < 1.0 and y1 <= t.y0 < y1 + 20]
    if len(over) != 1:
        raise PlotReadError(f"{where}: expected one title centred above the axes, found {len(over)}")
    return over[0].text.strip()


def _is_black(colour: tuple[float, ...]) -> bool:
    return colour[:3] == (0.0, 0.0, 0.0)


def tick_marks(box: Box, shapes: list[Shape]) -> tuple[np.ndarray, np.ndarray]:
    """Positions (pt) of the x ticks (short black marks down from the bottom spine) and the y ticks (left of the
    left spine)."""
    x0, y0, _, _ = box
    xs, ys = [], []
    for s in shapes:
        if len(s.points) != 2 or not s.stroke or not _is_black(s.stroke_colour):
            continue
        (ax, ay), (bx, by) = s.points
        if ax == bx and max(ay, by) == y0 and min(ay, by) < y0:
            xs.append(ax)
        elif ay == by and max(ax, bx) == x0 and min(ax, bx) < x0:
            ys.append(ay)
    return np.array(sorted(xs)), np.array(sorted(ys))


def number(text: str) -> float | None:
    """A label's number (``"-0.5"``, ``"1e6"``), or ``None`` for a word."""
    try:
        return float(text.strip())
    except ValueError:
        return None


__all__ = ["Box", "PlotReadError", "Shape", "Text", "axes_groups", "axes_title", "figure_title", "number", "tick_marks",
           "page_contents"]
