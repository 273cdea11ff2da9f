"""The replay page in a real browser (headless Chromium, see conftest's ``browser``), used as a person would: it
opens from disk with no network and no console error, the slider moves the frame and every chart's cursor, the
values shown at a decision are the trace's and add up to what the environment paid, another agent changes the
charts, and the comparison shows both episodes."""

from __future__ import annotations

import json

import numpy as np
import pytest

from hivex_dsl.cli import main
from hivex_dsl.compiler import compile
from hivex_dsl.replay.browser import open_page

from .conftest import short_scenario
from .test_replay import env_rewards

DECISIONS, FRAME_STEP, SEED = 60, 5, 3


@pytest.fixture(scope="module")
def single(tmp_path_factory):
    """(page, trace, compiled) of 60 decisions of Ocean Plastic Collection's main task, scripted, seed 3."""
    folder = tmp_path_factory.mktemp("single")
    # decision period 1 (OPC's default is 5): DECISIONS decisions in as many physics steps, a quick episode
    scenario = short_scenario(folder, "ocean_plastic_collection", episode_length=DECISIONS, decision_period=1)
    page, trace = folder / "single.html", folder / "single.json"
    assert main(["replay", str(scenario), "-o", str(page), "--trace", str(trace), "--frame-step", str(FRAME_STEP),
                 "--seed", str(SEED)]) == 0
    return page, json.loads(trace.read_text())["episodes"][0], compile(str(scenario))


@pytest.fixture(scope="module")
def opened(browser, single):
    page, errors = open_page(browser, single[0])
    yield page, errors
    page.close()


def charts_cursor(page) -> list:
    return page.evaluate("window.replay.view.charts.map(u => u.cursor.idx)")


def test_the_page_opens_from_disk_without_network_and_without_a_console_error(opened):
    page, errors = opened
    assert page.url.startswith("file://")
    assert errors == []
    assert page.locator("#frame-0").get_attribute("src").startswith("data:image/")
    assert page.locator(".uplot").count() == 2 + len(page.evaluate("window.replay.trace.episodes[0].statistics"))


def test_the_slider_moves_the_frame_and_every_charts_cursor(opened, single):
    page, errors = opened
    frames = page.evaluate("JSON.parse(document.getElementById('replay-frames').textContent)[0]")
    for decision in (1, 23, DECISIONS):
        page.locator("#slider").fill(str(decision))
        shown = (decision // FRAME_STEP) if decision < DECISIONS else len(frames) - 1
        assert page.locator("#frame-0").get_attribute("src") == frames[shown]
        assert f"after decision {single[1]['frame_decisions'][shown]}" in page.locator("#caption-0").inner_text()
        assert charts_cursor(page) == [decision - 1] * len(charts_cursor(page))
        assert page.locator("#position").inner_text() == f"decision {decision} of {DECISIONS}"
    page.locator("#slider").fill("10")
    page.keyboard.press("ArrowRight")
    assert page.locator("#slider").input_value() == "11" and set(charts_cursor(page)) == {10}
    page.keyboard.press("Shift+ArrowLeft")
    assert page.locator("#slider").input_value() == "1"
    assert errors == []


def shown_terms(page, episode: int = 0) -> dict[str, float]:
    cells = page.locator(f"td[data-episode='{episode}'][data-column='weighted']")
    return {cells.nth(i).get_attribute("data-term"): float(cells.nth(i).get_attribute("data-value"))
            for i in range(cells.count())}


def test_the_terms_shown_are_the_traces_and_add_up_to_what_the_environment_paid(opened, single):
    page, errors = opened
    _, trace, compiled = single
    paid = env_rewards(compiled, DECISIONS, seed=SEED)  # the environment itself, not the trace
    agent = int(np.count_nonzero(paid, axis=0).argmax())  # the vessel that collected the most
    paying = [int(d) + 1 for d in np.flatnonzero(paid[:, agent])]
    page.select_option("#agent", str(agent))
    checked = 0
    for decision in sorted(set(range(1, DECISIONS + 1, 7)) | set(paying)):
        page.locator("#slider").fill(str(decision))
        shown = shown_terms(page)
        assert shown == {term: trace["weighted"][term][decision - 1][agent] for term in trace["terms"]}
        assert sum(shown.values()) == pytest.approx(paid[decision - 1, agent], rel=1e-5, abs=1e-6)
        reward = page.locator("td[data-episode='0'][data-column='reward']").get_attribute("data-value")
        assert float(reward) == pytest.approx(paid[decision - 1, agent], rel=1e-5, abs=1e-9)
        checked += any(shown.values())
    assert checked == len(paying) > 0  # the decisions that paid something were among them
    assert errors == []


def test_picking_another_agent_redraws_the_charts_with_its_terms(opened, single):
    page, errors = opened
    trace = single[1]
    running = {}
    for agent in (0, 2):
        page.select_option("#agent", str(agent))
        # the running-total chart's last series is the agent's return so far
        running[agent] = page.evaluate("window.replay.view.agentCharts[1].data.at(-1)")
        expected = np.cumsum([row[agent] for row in trace["reward"]])
        np.testing.assert_allclose(running[agent], expected, rtol=1e-9, atol=1e-9)
        assert page.locator("#agent-title").inner_text().startswith(trace["agents"][agent])
    assert running[0] != running[2]
    assert errors == []


def test_the_comparison_shows_both_episodes_on_one_timeline(browser, tmp_path):
    first = short_scenario(tmp_path, "wind_farm_control", episode_length=30)
    other = tmp_path / "other.json"
    other.write_text(json.dumps(json.loads(first.read_text()) | {"name": "wfc-other",
                                                                  "weights": {"generate_energy": 2.0}}))
    page_path = tmp_path / "compare.html"
    assert main(["replay", str(first), "--compare", str(other), "-o", str(page_path), "--frame-step", "10"]) == 0
    page, errors = open_page(browser, page_path)
    try:
        assert page.locator("#frame-0").is_visible() and page.locator("#frame-1").is_visible()
        assert page.locator("#caption-1").inner_text().startswith("B: ")
        page.locator("#slider").fill("12")
        a, b = shown_terms(page, 0), shown_terms(page, 1)
        assert b["generate_energy"] == pytest.approx(2.0 * a["generate_energy"], rel=1e-5)
        assert page.locator("td[data-episode='1'][data-column='weight']").first.inner_text() == "2"
        assert page.locator(".uplot").count() == 4 + 2  # stacked and running per episode, two statistics
        assert set(charts_cursor(page)) == {11}
        assert "B: wfc-other" in page.locator("#summary").inner_text()
        assert errors == []
    finally:
        page.close()
