"""Read the curves of a matplotlib-written vector PDF back as numbers.

A page drawn by matplotlib's PDF backend (seaborn ``lineplot`` panels: a line per series and, where several
runs were averaged, a filled band around it) keeps every curve as a path and every tick label as text. This
module reads one page with pdfminer.six (which applies the PDF's transformation matrices and colours) and maps
each panel's path coordinates to data coordinates from its tick marks and tick labels: an affine fit per axis,
checked to be linear, with matplotlib's scientific offset text (``1e6``, ``1e−5``, ``+4.8e3``) applied.

What a page yields, per panel (keyed by its title): per legend label (``"training"``, ``"test"``), the line's
vertices and, where drawn, the band's lower and upper edge at every x. Two facts of the backend bound what
can be read back: coordinates are written with 6 decimals (1e-6 pt), and lines of 128 or more vertices are
simplified on writing (matplotlib's ``path.simplify``: a vertex within ``path.simplify_threshold``, 1/9 pt,
of the straight run through its neighbours is dropped), so a line keeps a subset of its points, each exact,
while filled bands keep every point.
"""

from __future__ import annotations

import re
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from .pdfpage import (Box, PlotReadError, Shape, Text, axes_groups, axes_title, figure_title, number,
                      page_contents, tick_marks)

Affine = tuple[float, float]  # (slope, intercept): points = slope * value + intercept

SIMPLIFY_THRESHOLD_PT = 1 / 9  # matplotlib's default path.simplify_threshold, in points (the PDF's unit)
COORDINATE_DECIMALS = 6  # matplotlib's PDF backend writes path coordinates with this many decimals
_LINEARITY_PT = 1e-3  # a tick off the axis's affine fit by more than this is not on a linear axis
_OFFSET = re.compile(r"^(?:1e(?P<oom>[-+]?\d+))?(?P<shift>[-+]\d+(?:\.\d+)?(?:e[-+]?\d+)?)?$")


@dataclass
class Series:
    """One legend entry of a panel in data units: the line's vertices and the band's edges, if drawn.

    ``line_x``/``line_y`` (k,) are the vertices the PDF kept; ``band_x``/``lower``/``upper`` (n,) are every
    point of the band (empty when the series has none)."""

    line_x: np.ndarray
    line_y: np.ndarray
    band_x: np.ndarray = field(default_factory=lambda: np.empty(0))
    lower: np.ndarray = field(default_factory=lambda: np.empty(0))
    upper: np.ndarray = field(default_factory=lambda: np.empty(0))


@dataclass
class Panel:
    """One axes of a page: its title, the data units of one point on each axis, and its series by label."""

    title: str
    x_per_pt: float
    y_per_pt: float
    series: dict[str, Series]


@dataclass
class Page:
    """A page's title (the figure's suptitle, or ``""``) and its panels in drawing order."""

    title: str
    panels: list[Panel]


def read_page(path: str | Path, page_number: int = 0) -> Page:
    """Every panel of one page of a matplotlib PDF, in data units."""
    texts, shapes, width, height = page_contents(Path(path), page_number)
    groups = axes_groups(shapes, texts, width, height)
    if not groups:
        raise PlotReadError(f"{path}: page {page_number + 1} has no axes (no white axes background rectangle)")
    panels = [_panel(box, g_shapes, g_texts, f"{path}: panel {i + 1}") for i, (box, g_shapes, g_texts) in
              enumerate(groups)]
    return Page(figure_title(texts, groups, height), panels)


def _panel(box: Box, shapes: list[Shape], texts: list[Text], where: str) -> Panel:
    title = axes_title(box, texts, where)
    where = f"{where} ({title!r})"
    x_ticks, y_ticks = tick_marks(box, shapes)
    x_labels, y_labels = _tick_labels(x_ticks, y_ticks, box, texts, where)
    used = {id(t) for t in (*x_labels, *y_labels)}
    x_offset, y_offset = _offsets(box, [t for t in texts if id(t) not in used], where)
    to_x = _axis_map(x_ticks, x_labels, x_offset, f"{where} x axis")
    to_y = _axis_map(y_ticks, y_labels, y_offset, f"{where} y axis")
    series = _series(shapes, texts, to_x, to_y, where)
    return Panel(title, 1 / to_x[0], 1 / to_y[0], series)


def _tick_labels(x_ticks: np.ndarray, y_ticks: np.ndarray, box: Box, texts: list[Text], where: str
                 ) -> tuple[list[Text], list[Text]]:
    x0, y0, _, _ = box
    below = [t for t in texts if t.y1 <= y0 and number(t.text) is not None]
    left = [t for t in texts if t.x1 <= x0 and number(t.text) is not None]
    x_labels = [_nearest(below, lambda t, p=p: abs(t.cx - p), f"{where}: x tick at {p:.2f} pt") for p in x_ticks]
    y_labels = [_nearest(left, lambda t, p=p: abs(t.cy - p), f"{where}: y tick at {p:.2f} pt") for p in y_ticks]
    return x_labels, y_labels


def _nearest(candidates: list[Text], distance, what: str) -> Text:  # noqa: ANN001
    if not candidates:
        raise PlotReadError(f"{what} has no numeric label")
    return min(candidates, key=distance)


def _offsets(box: Box, texts: list[Text], where: str) -> tuple[tuple[float, float], tuple[float, float]]:
    """(scale, shift) of each axis from matplotlib's offset texts: the x axis's under the box's right half, the
    y axis's over its left half; (1, 0) where there is none."""
    x0, y0, x1, y1 = box
    x_text = [t for t in texts if t.cy < y0 and t.cx > (x0 + x1) / 2 and _OFFSET.match(t.text.strip())]
    y_text = [t for t in texts if t.cy > y1 and t.cx < (x0 + x1) / 2 and _OFFSET.match(t.text.strip())]
    return _offset(x_text, f"{where} x axis"), _offset(y_text, f"{where} y axis")


def _offset(texts: list[Text], where: str) -> tuple[float, float]:
    found = [t for t in texts if t.text.strip()]
    if len(found) > 1:
        raise PlotReadError(f"{where}: more than one offset text ({', '.join(t.text for t in found)})")
    if not found:
        return 1.0, 0.0
    match = _OFFSET.match(found[0].text.strip())
    assert match is not None  # filtered by the caller
    scale = 10.0 ** int(match["oom"]) if match["oom"] else 1.0
    return scale, float(match["shift"]) if match["shift"] else 0.0


def _axis_map(ticks: np.ndarray, labels: list[Text], offset: tuple[float, float], where: str) -> Affine:
    """(slope, intercept) with ``points = slope * value + intercept``, fitted to the ticks; checked linear."""
    if len(ticks) < 2:
        raise PlotReadError(f"{where}: {len(ticks)} labelled tick(s), 2 are needed to place the axis")
    scale, shift = offset
    values = np.array([number(t.text) for t in labels], dtype=float) * scale + shift
    if len(set(values)) != len(values):
        raise PlotReadError(f"{where}: two ticks carry the same value {sorted(values)}")
    slope, intercept = np.polyfit(values, ticks, 1)
    worst = float(np.max(np.abs(slope * values + intercept - ticks)))
    if worst > _LINEARITY_PT:
        raise PlotReadError(f"{where}: ticks are not on a linear axis ({worst:.3g} pt off the affine fit; "
                            "log or categorical axes are not read)")
    return float(slope), float(intercept)


def _series(shapes: list[Shape], texts: list[Text], to_x: Affine, to_y: Affine, where: str
            ) -> dict[str, Series]:
    """Each legend label's line and band, matched to the legend handles by colour."""
    handles, frame = _legend(shapes, texts, where)
    inside = [s for s in shapes if s.order < frame.order]  # the legend's own handles come after its frame
    series = {}
    for label, colour in handles.items():
        lines = [s.points for s in inside if s.stroke and not s.fill and s.stroke_colour == colour]
        bands = [s.points for s in inside if s.fill and s.closed and s.fill_colour == colour and len(s.points) > 4]
        if not lines:
            continue
        line = _to_data(np.concatenate(lines), to_x, to_y)
        series[label] = Series(line[:, 0], line[:, 1], *_bands(bands, to_x, to_y, f"{where} {label!r}"))
    if not series:
        raise PlotReadError(f"{where}: no line in the colour of any legend entry")
    return series


def _legend(shapes: list[Shape], texts: list[Text], where: str) -> tuple[dict[str, tuple[float, ...]], Shape]:
    """The legend's entries (label -> line colour) and its frame: the handles are the short coloured lines drawn
    inside the frame after it, each labelled by the string beside it."""
    frames = [s for s in shapes if s.fill and s.stroke and s.closed and len(s.points) > 4
              and s.fill_colour[:3] == (1.0, 1.0, 1.0)]
    if not frames:
        raise PlotReadError(f"{where}: has no legend to tell its series apart")
    frame = frames[-1]
    (fx0, fy0), (fx1, fy1) = frame.points.min(axis=0), frame.points.max(axis=0)
    handles = [s for s in shapes if s.order > frame.order and s.stroke and not s.fill and len(s.points) >= 2
               and np.all((s.points >= (fx0, fy0)) & (s.points <= (fx1, fy1)))]
    words = [t for t in texts if fx0 <= t.x0 and t.x1 <= fx1 and fy0 <= t.y0 and t.y1 <= fy1]
    entries = {}
    for handle in handles:
        hx, hy = handle.points[:, 0].max(), handle.points[:, 1].mean()
        right = [t for t in words if t.x0 >= hx]
        if right:
            entries[min(right, key=lambda t: abs(t.cy - hy)).text.strip()] = handle.stroke_colour
    if not entries:
        raise PlotReadError(f"{where}: the legend has no labelled line")
    return entries, frame


def _to_data(points: np.ndarray, to_x: Affine, to_y: Affine) -> np.ndarray:
    """(n, 2) points in pt -> data units."""
    return np.column_stack([(points[:, 0] - to_x[1]) / to_x[0], (points[:, 1] - to_y[1]) / to_y[0]])


def _bands(polygons: list[np.ndarray], to_x: Affine, to_y: Affine, where: str
           ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """x, lower and upper edge of ``fill_between`` polygons: start, the n points of one edge, end, and the n
    points of the other edge reversed (matplotlib's vertex order)."""
    xs, lows, highs = [], [], []
    for polygon in polygons:
        n, odd = divmod(len(polygon) - 2, 2)
        first, second = polygon[1:n + 1], polygon[n + 2:][::-1]
        if odd or n < 1 or not np.allclose(first[:, 0], second[:, 0], atol=10 ** -COORDINATE_DECIMALS):
            raise PlotReadError(f"{where}: a filled band is not a fill_between polygon ({len(polygon)} vertices)")
        a, b = _to_data(first, to_x, to_y), _to_data(second, to_x, to_y)
        xs.append(a[:, 0])
        lows.append(np.minimum(a[:, 1], b[:, 1]))
        highs.append(np.maximum(a[:, 1], b[:, 1]))
    if not polygons:
        return np.empty(0), np.empty(0), np.empty(0)
    return np.concatenate(xs), np.concatenate(lows), np.concatenate(highs)


__all__ = ["COORDINATE_DECIMALS", "Page", "Panel", "PlotReadError", "SIMPLIFY_THRESHOLD_PT", "Series",
           "read_page"]
