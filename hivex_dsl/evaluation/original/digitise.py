"""Turn the original release's plot pages into ``hivex_dsl/data/original-curves.json.xz``.

Input: the folder of hivex-research/hivex-results' ``results/<Env>/baseline/plots/`` (commit 2cd9a01; a copy
is ``shared/paper/original-plots/``): one PDF per published cell, ``<Env>_results_difficulty_<level>_task_<t>.pdf``
(Wind Farm Control ``pattern_<p>``, Ocean Plastic Collection ``None_None``), each page a panel per logged
TensorBoard scalar with the training runs' mean and band and the test runs' mean and band against agent-steps;
and one ``<Env>_average_sheet.pdf`` per environment, a heatmap per scalar of each cell's average over its test
curve, read as the printed numbers (kept with their printed decimals).

Regenerate with ``python -m hivex_dsl.evaluation.original.digitise PLOTS_DIR [--out FILE]`` (needs the ``paper``
extra).

Precision: agent-steps are whole numbers (the PDF places them to 1e-6 pt, a few hundredths of a step); values
are rounded to the coarsest power of ten that is at most 0.001 pt of the panel's y axis (``y_decimals`` per
panel), a hundredth of matplotlib's 1/9 pt path-simplification threshold, which bounds how far the PDF's line
may lie from the points it dropped.
"""

from __future__ import annotations

import argparse
import json
import lzma
import math
import re
import sys
from pathlib import Path
from typing import Any

from .curves import DATA_FILE
from .heatmap import read_heatmaps
from .pdfplot import Panel, PlotReadError, Series, read_page

VALUE_RESOLUTION_PT = 1e-3  # values are kept to this fraction of a point of their panel's axis
# the plots' folder names -> this toolkit's environment ids
ENVIRONMENTS = {
    "AerialWildfireSuppression": "aerial_wildfire_suppression",
    "DroneBasedReforestation": "drone_based_reforestation",
    "OceanPlasticCollection": "ocean_plastic_collection",
    "WildfireResourceManagement": "wildfire_resource_management",
    "WindFarmControl": "wind_farm_control",
}
_CELL_FILE = re.compile(r"^(?P<env>[A-Za-z]+)_results_(?:difficulty_(?P<level>\d+)|pattern_(?P<pattern>\d+)|None_None)"
                        r"_task_(?P<task>\d+)\.pdf$")
SOURCE = ("hivex-research/hivex-results at 2cd9a01, results/<Env>/baseline/plots/*.pdf (matplotlib 3.9 vector "
          "pages, seaborn lineplot: mean line and 95% bootstrap band over three runs)")


_SHEET_FILE = re.compile(r"^(?P<env>[A-Za-z]+)_average_sheet\.pdf$")


def sheet_environment(name: str) -> str | None:
    """The environment id of an average sheet's file name; ``None`` for any other file."""
    match = _SHEET_FILE.match(name)
    return ENVIRONMENTS.get(match["env"]) if match else None


def digitise_sheet(path: Path) -> dict[str, dict[str, dict[str, list]]]:
    """One average sheet: tag -> task -> level (``"none"`` for a column labelled None) -> [value, decimals]."""
    sheet: dict[str, dict[str, dict[str, list]]] = {}
    for tag, cells in read_heatmaps(path).items():
        for (task, column), annotation in sorted(cells.items()):
            level = "none" if column == "None" else str(int(column))
            sheet.setdefault(tag, {}).setdefault(str(task), {})[level] = [annotation.value, annotation.decimals]
    return sheet


def cell_key(name: str) -> tuple[str, str, str] | None:
    """(environment id, task, level) of a cell page's file name, the level ``"none"`` for Ocean Plastic
    Collection; ``None`` for any other file (the average sheets)."""
    match = _CELL_FILE.match(name)
    if not match or match["env"] not in ENVIRONMENTS:
        return None
    level = match["level"] or match["pattern"] or "none"
    return ENVIRONMENTS[match["env"]], str(int(match["task"])), str(int(level)) if level != "none" else level


def _decimals(per_pt: float) -> int:
    """Decimal places of the coarsest power of ten no larger than VALUE_RESOLUTION_PT points of an axis."""
    return math.ceil(-math.log10(VALUE_RESOLUTION_PT * abs(per_pt)))


def _rounded(values, decimals: int) -> list:  # noqa: ANN001 - a numpy array
    if decimals <= 0:
        return [int(round(float(v), decimals)) for v in values]
    return [round(float(v), decimals) + 0.0 for v in values]  # + 0.0: no "-0.0"


def _steps(values) -> list[int]:  # noqa: ANN001
    return [int(round(float(v))) for v in values]


def _series_data(series: Series, decimals: int) -> dict[str, Any]:
    data: dict[str, Any] = {"line": [_steps(series.line_x), _rounded(series.line_y, decimals)]}
    if len(series.band_x):
        data["band"] = [_steps(series.band_x), _rounded(series.lower, decimals), _rounded(series.upper, decimals)]
    return data


def panel_data(panel: Panel) -> dict[str, Any]:
    """One panel as JSON-ready data: its scales, its value precision and each legend entry's series."""
    decimals = _decimals(panel.y_per_pt)
    data: dict[str, Any] = {"x_per_pt": float(f"{panel.x_per_pt:.6g}"), "y_per_pt": float(f"{panel.y_per_pt:.6g}"),
                            "y_decimals": decimals}
    data.update({label: _series_data(s, decimals) for label, s in panel.series.items()})
    return data


def digitise_file(path: Path) -> dict[str, Any]:
    """One cell page: its file name, its title and its panels by title."""
    page = read_page(path)
    titles = [p.title for p in page.panels]
    if len(set(titles)) != len(titles):
        raise PlotReadError(f"{path}: two panels share a title ({sorted(titles)})")
    return {"file": path.name, "title": page.title, "panels": {p.title: panel_data(p) for p in page.panels}}


def digitise_folder(plots: Path) -> dict[str, Any]:
    """Every cell page under ``plots`` (searched recursively), keyed environment -> task -> level, and every
    environment's average sheet."""
    files = sorted(p for p in plots.rglob("*.pdf") if cell_key(p.name))
    if not files:
        raise PlotReadError(f"{plots}: holds no cell page (<Env>_results_..._task_<n>.pdf)")
    cells: dict[str, dict[str, dict[str, Any]]] = {}
    for path in files:
        env, task, level = cell_key(path.name)  # type: ignore[misc]
        cells.setdefault(env, {}).setdefault(task, {})[level] = digitise_file(path)
    sheets = {sheet_environment(p.name): digitise_sheet(p) for p in sorted(plots.rglob("*.pdf"))
              if sheet_environment(p.name)}
    return {"source": SOURCE, "layout": LAYOUT, "precision": PRECISION, "cells": cells, "average_sheets": sheets}


LAYOUT = ("cells: environment id -> task index as in the file name (task_<n>, not remapped) -> level (WFC pattern, "
          "terrain level, or none) -> {file, title (the page's), panels: panel title (the TensorBoard scalar's last "
          "name) -> {x_per_pt, y_per_pt (data units per point of the page), y_decimals, training and test: "
          "{line: [steps, mean] at the vertices the PDF kept, band: [steps, lower, upper] at every point}}}. "
          "average_sheets: environment id -> tag (as the sheet titles it) -> task -> level -> [value, printed "
          "decimals]: each cell's average over its test curve as the sheet prints it")
PRECISION = ("steps: whole agent-steps (placed to about 0.04 step). values: rounded to y_decimals, a power of ten "
             "at most 0.001 pt of the panel's axis. The line keeps the vertices matplotlib's path simplification "
             "kept (exact); the points it dropped lie within 1/9 pt of the line, perpendicular, on the page. The "
             "band is seaborn's 95% bootstrap interval over three runs (random: inside the runs' min and max).")


def write(data: dict[str, Any], out: Path) -> None:
    """xz-compressed JSON (the standard library's lzma: a quarter smaller than gzip on these curves)."""
    raw = json.dumps(data, separators=(",", ":")).encode()
    out.write_bytes(lzma.compress(raw, preset=9 | lzma.PRESET_EXTREME))


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog="python -m hivex_dsl.evaluation.original.digitise",
                                     description=__doc__.splitlines()[0])
    parser.add_argument("plots", type=Path, help="the original's plots folder (e.g. ../shared/paper/original-plots)")
    parser.add_argument("--out", type=Path, default=Path(__file__).resolve().parents[2] / "data" / DATA_FILE)
    args = parser.parse_args(argv)
    if not args.plots.is_dir():
        print(f"error: {args.plots} is not a folder", file=sys.stderr)
        return 2
    try:
        data = digitise_folder(args.plots)
    except PlotReadError as error:
        print(f"error: {error}", file=sys.stderr)
        return 2
    write(data, args.out)
    count = sum(len(levels) for tasks in data["cells"].values() for levels in tasks.values())
    print(f"{count} cell pages and {len(data['average_sheets'])} average sheets -> {args.out} "
          f"({args.out.stat().st_size / 1e6:.2f} MB)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
