"""Read the annotated heatmaps of a matplotlib-written PDF page back as numbers.

The original's ``<Env>_average_sheet.pdf`` pages hold one seaborn heatmap per logged scalar, titled ``Average
Values for Tag: <tag>``: a row per task, a column per level, each cell annotated with the value as text. Every
annotation is read with its row (from the row tick marks and their labels) and the column label under it.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np

from .pdfpage import PlotReadError, Text, axes_groups, axes_title, number, page_contents, tick_marks

TITLE_PREFIX = "Average Values for Tag: "


@dataclass(frozen=True)
class Annotation:
    """One heatmap cell: its value and the decimals it was printed with (its resolution is half a unit of the
    last one)."""

    value: float
    decimals: int


def _annotation(text: str) -> Annotation:
    mantissa = text.strip().lower().split("e")[0]
    return Annotation(float(text), len(mantissa.split(".")[1]) if "." in mantissa else 0)


def _rows(ticks: np.ndarray, labels: list[Text], cells: list[Text], where: str) -> list[int]:
    """Each annotation's row index. Seaborn thins crowded row labels (AWS's 9 tasks show 0, 2, 4, 6, 8), so the
    index is read off a straight line through the labelled rows' tick marks, and must land on a whole row."""
    if len(labels) != len(ticks):
        raise PlotReadError(f"{where}: {len(labels)} row labels for {len(ticks)} row ticks")
    heights = np.sort(ticks)
    values = np.array([number(t.text) for t in sorted(labels, key=lambda t: t.cy)], dtype=float)
    if len(labels) < 2:
        if len(labels) == 1 and len(cells) and all(abs(c.cy - heights[0]) < 2 for c in cells):
            return [int(values[0])] * len(cells)
        raise PlotReadError(f"{where}: too few row labels to place its rows")
    slope, intercept = np.polyfit(heights, values, 1)
    rows = slope * np.array([c.cy for c in cells]) + intercept
    # a text's box sits a little off its anchor (the same for every annotation): one common offset is allowed
    offset = float(np.median(rows - np.round(rows))) if len(rows) else 0.0
    if abs(offset) > 0.4 or np.any(np.abs(rows - offset - np.round(rows - offset)) > 0.05):
        raise PlotReadError(f"{where}: an annotation lies between rows")
    return [int(r) for r in np.round(rows - offset)]


def _columns(labels: list[Text], cells: list[Text], where: str) -> list[str]:
    """Each annotation's column label: the tick label under it, within half a column."""
    found = []
    for cell in cells:
        label = min(labels, key=lambda t: abs(t.cx - cell.cx))
        if abs(label.cx - cell.cx) > 2:
            raise PlotReadError(f"{where}: no column label under the annotation {cell.text!r}")
        found.append(label.text.strip())
    return found


def read_heatmaps(path: str | Path, page_number: int = 0) -> dict[str, dict[tuple[int, str], Annotation]]:
    """Per heatmap titled ``Average Values for Tag: <tag>``: (row index, column label) -> its annotation."""
    texts, all_shapes, width, height = page_contents(Path(path), page_number)
    maps: dict[str, dict[tuple[int, str], Annotation]] = {}
    for i, (box, shapes, group) in enumerate(axes_groups(all_shapes, texts, width, height)):
        try:
            title = axes_title(box, group, f"{path}: axes {i + 1}")
        except PlotReadError:
            continue  # a colour bar: no title
        if not title.startswith(TITLE_PREFIX):
            continue
        where = f"{path}: heatmap {title!r}"
        x0, y0, x1, y1 = box
        below = [t for t in group if t.cy < y0]
        columns = [t for t in below if t.cy > max(b.cy for b in below) - 1]  # the tick labels, over the axis label
        rows = [t for t in group if t.cx < x0 and number(t.text) is not None]
        cells = [t for t in group if x0 < t.cx < x1 and y0 < t.cy < y1 and number(t.text) is not None]
        row_ticks = tick_marks(box, shapes)[1]
        keys = zip(_rows(row_ticks, rows, cells, where), _columns(columns, cells, where))
        maps[title[len(TITLE_PREFIX):]] = {key: _annotation(c.text) for key, c in zip(keys, cells)}
    if not maps:
        raise PlotReadError(f"{path}: page {page_number + 1} has no heatmap titled {TITLE_PREFIX!r}...")
    return maps


__all__ = ["Annotation", "TITLE_PREFIX", "read_heatmaps"]
