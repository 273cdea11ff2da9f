"""Progress bars (hivex_dsl.evaluation.progress): the time left on stderr where it is a terminal, nothing under --json
or when stderr is piped or logged, for every long command."""

from __future__ import annotations

import io
import re
import sys

import pytest

from hivex_dsl.cli import main
from hivex_dsl.evaluation.progress import EpisodeBar, bar

BAR = re.compile(r"\d+/\d+ \[\d\d:\d\d<")  # tqdm's "n/total [elapsed<remaining": a bar with its time left
SCENARIO = "hivex: 1\nname: tiny\nenvironment: wind_farm_control\nagents: 2\nepisode_length: 20\n"


class Terminal(io.StringIO):
    """A stream that says it is a terminal."""

    def isatty(self) -> bool:
        return True


def on_terminal(monkeypatch) -> Terminal:
    """stderr replaced by a terminal (read back with .getvalue()); called in the test itself, since pytest's
    capture puts its own stderr back after the fixtures."""
    tty = Terminal()
    monkeypatch.setattr(sys, "stderr", tty)
    return tty


def commands(tmp_path) -> dict[str, list[str]]:
    """Each long command of the core CLI on a tiny scenario, with the bar's label."""
    scenario = tmp_path / "tiny.yaml"
    scenario.write_text(SCENARIO)
    return {"audit tiny": ["audit", str(scenario), "--episodes", "1"],
            "render tiny": ["render", str(scenario), "-o", str(tmp_path / "tiny.gif"), "--steps", "10",
                            "--frame-step", "5"],
            "preview": ["preview", "-o", str(tmp_path / "figures")],
            "run": ["run", str(scenario)],
            "replay tiny": ["replay", str(scenario), "-o", str(tmp_path / "tiny.html"), "--frame-step", "5"]}


def test_a_bar_shows_the_time_left_on_a_terminal_only():
    tty, pipe, quiet = Terminal(), io.StringIO(), Terminal()
    for stream, enabled in ((tty, True), (pipe, True), (quiet, False)):
        with bar(10, "work", stream=stream, enabled=enabled) as shown:
            shown.update(10)
    assert "work" in tty.getvalue() and BAR.search(tty.getvalue())
    assert pipe.getvalue() == "" and quiet.getvalue() == ""


def test_an_episode_counts_whole_on_the_bar_even_when_it_ends_early():
    with bar(30, stream=Terminal()) as shown:
        episodes = EpisodeBar(shown, decisions=10)
        for step in range(1, 5):
            episodes.step(0, step, 10)
        assert shown.n == 4
        episodes.episode_done(0, 0.0, 4)
        assert shown.n == 10


@pytest.mark.parametrize("label", ["audit tiny", "render tiny", "preview", "run", "replay tiny"])
def test_each_long_command_shows_a_bar_on_a_terminal(label, tmp_path, monkeypatch):
    terminal = on_terminal(monkeypatch)
    assert main(commands(tmp_path)[label]) == 0
    shown = terminal.getvalue()
    assert label in shown and BAR.search(shown)


@pytest.mark.parametrize("label", ["audit tiny", "render tiny", "preview", "run", "replay tiny"])
def test_no_bar_when_stderr_is_not_a_terminal(label, tmp_path, capsys):
    assert main(commands(tmp_path)[label]) == 0
    err = capsys.readouterr().err
    assert not BAR.search(err) and "\r" not in err


def test_no_bar_under_json_even_on_a_terminal(tmp_path, monkeypatch, capsys):
    terminal = on_terminal(monkeypatch)
    assert main(commands(tmp_path)["audit tiny"] + ["--json"]) == 0
    assert terminal.getvalue() == ""
