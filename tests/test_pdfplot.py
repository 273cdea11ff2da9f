"""The PDF plot reader on pages matplotlib writes here with known data, independent of the original's PDFs."""

from __future__ import annotations

import matplotlib

matplotlib.use("Agg")

import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import pytest  # noqa: E402

from hivex_dsl.evaluation.original import digitise  # noqa: E402
from hivex_dsl.evaluation.original.heatmap import Annotation, read_heatmaps  # noqa: E402
from hivex_dsl.evaluation.original.pdfplot import (  # noqa: E402
    SIMPLIFY_THRESHOLD_PT, PlotReadError, read_page)

from .page_geometry import distance_to_polyline  # noqa: E402

STEPS = np.linspace(20_000, 2_000_000, 100)  # < 128 points: matplotlib writes every vertex
SIGNED = np.sin(STEPS / 3e5) * 0.8
OFFSET_X = 1e6 + np.arange(50.0)  # matplotlib labels this axis 0..50 with the offset "+1e6"
OFFSET_Y = 3e-5 + 1e-5 * np.cos(OFFSET_X)  # ... and this one 2.0..4.0 with "1e-5" (a minus glyph)
LONG_X = np.arange(300.0) * 1000  # >= 128 points: simplified on writing
LONG_Y = np.random.default_rng(0).normal(size=300).cumsum()


@pytest.fixture(scope="module")
def page_pdf(tmp_path_factory):
    fig, (signed, offsets, long) = plt.subplots(1, 3, figsize=(12, 3))
    signed.fill_between(STEPS, SIGNED - 0.1, SIGNED + 0.2, color="tab:red", alpha=0.2)
    signed.plot(STEPS, SIGNED, color="tab:red", label="training")
    signed.plot(STEPS[:20], -SIGNED[:20], color="tab:green", label="test")
    signed.legend(title="source")
    signed.set_title("Signed")
    offsets.plot(OFFSET_X, OFFSET_Y, color="tab:blue", label="training")
    offsets.legend()
    offsets.set_title("Offsets")
    long.plot(LONG_X, LONG_Y, color="tab:red", label="training")
    long.legend()
    long.set_title("Long")
    fig.suptitle("Round trip")
    path = tmp_path_factory.mktemp("pdfplot") / "page.pdf"
    fig.savefig(path)
    plt.close(fig)
    return path


@pytest.fixture(scope="module")
def page(page_pdf):
    return read_page(page_pdf)


def test_titles_and_legend_labels_are_read(page):
    assert page.title == "Round trip"
    assert [p.title for p in page.panels] == ["Signed", "Offsets", "Long"]
    assert set(page.panels[0].series) == {"training", "test"}


def test_lines_and_band_come_back_as_the_data(page):
    panel = page.panels[0]
    training, test = panel.series["training"], panel.series["test"]
    tolerance = 1e-5 * panel.y_per_pt  # 6-decimal coordinates, well inside 1e-5 pt
    np.testing.assert_allclose(training.line_x, STEPS, atol=1e-5 * panel.x_per_pt)
    np.testing.assert_allclose(training.line_y, SIGNED, atol=tolerance)
    np.testing.assert_allclose(test.line_y, -SIGNED[:20], atol=tolerance)  # negative tick labels read too
    np.testing.assert_allclose(training.band_x, STEPS, atol=1e-5 * panel.x_per_pt)
    np.testing.assert_allclose(training.lower, SIGNED - 0.1, atol=tolerance)
    np.testing.assert_allclose(training.upper, SIGNED + 0.2, atol=tolerance)
    assert len(test.band_x) == 0


def test_scientific_and_additive_offsets_are_applied(page):
    panel = page.panels[1]
    series = panel.series["training"]
    np.testing.assert_allclose(series.line_x, OFFSET_X, atol=1e-5 * panel.x_per_pt)
    np.testing.assert_allclose(series.line_y, OFFSET_Y, atol=1e-5 * panel.y_per_pt)


def test_a_simplified_line_keeps_exact_vertices_within_the_threshold_of_the_rest(page):
    panel = page.panels[2]
    series = panel.series["training"]
    assert len(series.line_x) < len(LONG_X)  # matplotlib dropped some
    kept = np.searchsorted(LONG_X, np.round(series.line_x))
    np.testing.assert_allclose(series.line_y, LONG_Y[kept], atol=1e-5 * panel.y_per_pt)
    on_page = np.column_stack([LONG_X / panel.x_per_pt, LONG_Y / panel.y_per_pt])
    line = np.column_stack([series.line_x / panel.x_per_pt, series.line_y / panel.y_per_pt])
    assert distance_to_polyline(on_page, line).max() <= SIMPLIFY_THRESHOLD_PT


def test_a_log_axis_is_refused(tmp_path):
    fig, ax = plt.subplots()
    ax.plot([1, 10, 100, 1000], [1, 2, 3, 4], color="tab:red", label="training")
    ax.set_xscale("log")
    ax.legend()
    ax.set_title("Log")
    fig.savefig(tmp_path / "log.pdf")
    plt.close(fig)
    with pytest.raises(PlotReadError, match="Log"):
        read_page(tmp_path / "log.pdf")


def test_a_file_that_is_no_pdf_is_refused(tmp_path):
    (tmp_path / "not.pdf").write_text("hello")
    with pytest.raises(PlotReadError, match="not a readable PDF"):
        read_page(tmp_path / "not.pdf")
    with pytest.raises(PlotReadError, match="cannot be read"):
        read_page(tmp_path / "missing.pdf")


def test_the_command_writes_the_folder_s_cell_pages(page_pdf, tmp_path, capsys):
    plots = tmp_path / "plots" / "WindFarmControl"
    plots.mkdir(parents=True)
    (plots / "WindFarmControl_results_pattern_3_task_1.pdf").write_bytes(page_pdf.read_bytes())
    (plots / "WindFarmControl_notes.pdf").write_text("neither a cell page nor an average sheet: not read")
    out = tmp_path / "curves.json.xz"
    assert digitise.main([str(tmp_path / "plots"), "--out", str(out)]) == 0
    import json
    import lzma

    data = json.loads(lzma.decompress(out.read_bytes()))
    assert data["average_sheets"] == {}
    cell = data["cells"]["wind_farm_control"]["1"]["3"]
    assert cell["file"] == "WindFarmControl_results_pattern_3_task_1.pdf" and cell["title"] == "Round trip"
    signed = cell["panels"]["Signed"]
    assert signed["training"]["line"][0] == [int(round(s)) for s in STEPS]
    resolution = 10.0 ** -signed["y_decimals"]
    assert resolution <= 1e-3 * signed["y_per_pt"] * 1.000001
    np.testing.assert_allclose(signed["training"]["band"][1], SIGNED - 0.1, atol=resolution)


def test_the_command_refuses_a_folder_without_cell_pages(tmp_path, capsys):
    assert digitise.main([str(tmp_path / "absent")]) == 2
    assert "is not a folder" in capsys.readouterr().err
    assert digitise.main([str(tmp_path)]) == 2
    assert "holds no cell page" in capsys.readouterr().err


def test_cell_keys_follow_the_file_names():
    assert digitise.cell_key("DroneBasedReforestation_results_difficulty_10_task_6.pdf") == (
        "drone_based_reforestation", "6", "10")
    assert digitise.cell_key("WindFarmControl_results_pattern_0_task_1.pdf") == ("wind_farm_control", "1", "0")
    assert digitise.cell_key("OceanPlasticCollection_results_None_None_task_3.pdf") == (
        "ocean_plastic_collection", "3", "none")
    assert digitise.cell_key("OceanPlasticCollection_average_sheet.pdf") is None


def test_an_annotated_heatmap_comes_back_with_its_rows_and_columns(tmp_path):
    """As seaborn draws them: row 0 at the top, crowded row labels thinned to every other row, string columns."""
    values = np.arange(5 * 3, dtype=float).reshape(5, 3) * 1.5 - 4
    columns = ["10", "1", "None"]
    fig, (ax, colour) = plt.subplots(1, 2, figsize=(6, 3), gridspec_kw={"width_ratios": [10, 1]})
    mesh = ax.pcolormesh(values, cmap="viridis")
    fig.colorbar(mesh, cax=colour)
    for (row, column), value in np.ndenumerate(values):
        ax.text(column + 0.5, row + 0.5, f"{value:.1f}", ha="center", va="center")
    ax.set_xticks(np.arange(3) + 0.5, columns)
    ax.set_yticks(np.arange(0, 5, 2) + 0.5, ["0", "2", "4"], rotation=90, va="center")
    ax.invert_yaxis()
    ax.set_title("Average Values for Tag: Policy/Entropy")
    fig.savefig(tmp_path / "sheet.pdf")
    plt.close(fig)
    cells = read_heatmaps(tmp_path / "sheet.pdf")["Policy/Entropy"]
    assert cells == {(row, columns[column]): Annotation(float(f"{value:.1f}"), 1)
                     for (row, column), value in np.ndenumerate(values)}
