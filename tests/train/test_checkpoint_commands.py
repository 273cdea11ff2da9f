"""A trained checkpoint in the other commands: `hivex audit --checkpoint` rolls its policy beside the trivial and
scripted ones (the evaluate path's policy, checked against the scenario as evaluate checks it), and `hivex evaluate`
and `hivex train`'s evaluation pass show a progress bar on a terminal only."""

from __future__ import annotations

import io
import json
import re
import sys

import pytest

from hivex_dsl.cli import main
from hivex_dsl.train.evaluate import evaluate

from .conftest import SCENARIOS, short_scenario

BAR = re.compile(r"\d+/\d+ \[\d\d:\d\d<")  # tqdm's "n/total [elapsed<remaining"
TINY = ["--set", "num_worlds=1", "--set", "hidden_units=8", "--set", "buffer_size=64", "--set", "batch_size=64"]


class Terminal(io.StringIO):
    def isatty(self) -> bool:
        return True


def on_terminal(monkeypatch) -> Terminal:
    """stderr replaced by a terminal, inside the test (pytest's capture resets it after the fixtures)."""
    tty = Terminal()
    monkeypatch.setattr(sys, "stderr", tty)
    return tty


@pytest.fixture(scope="module")
def trained(tmp_path_factory):
    """(scenario file, checkpoint) of a 64-agent-step Wind Farm Control run with 16-step episodes."""
    folder = tmp_path_factory.mktemp("trained")
    scenario = folder / "wfc.json"
    scenario.write_text(json.dumps(short_scenario("wind_farm_control", episode_length=16)))
    assert main(["train", str(scenario), "-o", str(folder / "run"), "--steps", "64", "--no-progress", *TINY]) == 0
    return scenario, folder / "run" / "checkpoint.pt"


def test_audit_sets_the_trained_policy_beside_the_others(trained, capsys):
    scenario, checkpoint = trained
    capsys.readouterr()
    assert main(["audit", str(scenario), "--episodes", "1", "--checkpoint", str(checkpoint), "--json"]) == 0
    (audit,) = json.loads(capsys.readouterr().out)
    assert list(audit["policies"]) == ["zeros", "random", "scripted", "trained"]
    assert audit["checkpoint"] == str(checkpoint)
    # the evaluate path's policy, on the same test episodes with the same sampling seed
    played = evaluate(checkpoint, episodes=1)["return"]["mean"]
    assert audit["policies"]["trained"]["return"]["mean"] == pytest.approx(played)
    assert main(["audit", str(scenario), "--episodes", "1", "--checkpoint", str(checkpoint)]) == 0
    text = capsys.readouterr().out
    assert f"trained: the policy of {checkpoint}" in text
    assert re.search(r"term \(weighted\) +zeros +random +scripted +trained", text)


def test_audit_refuses_a_checkpoint_of_another_environment(trained, capsys):
    _, checkpoint = trained
    other = SCENARIOS / "wildfire_resource_management" / "main.yaml"
    capsys.readouterr()
    assert main(["audit", str(other), "--episodes", "1", "--checkpoint", str(checkpoint)]) == 2
    assert capsys.readouterr().err == (
        "hivex: the checkpoint trained on wind_farm_control (scenario 'wfc-main') and cannot play "
        "wildfire_resource_management (scenario 'wrm-main'): a policy plays the environment it trained on\n")
    assert main(["audit", "--suite", "--checkpoint", str(checkpoint)]) == 2
    assert "not --suite" in capsys.readouterr().err
    assert main(["audit", str(other), "--checkpoint", str(checkpoint.parent / "missing.pt")]) == 2
    assert capsys.readouterr().err.startswith("hivex: no checkpoint at ")


def test_evaluate_shows_a_bar_on_a_terminal_only_and_never_under_json(trained, monkeypatch, capsys):
    _, checkpoint = trained
    capsys.readouterr()
    assert main(["evaluate", str(checkpoint), "--episodes", "1"]) == 0
    assert capsys.readouterr().err == ""
    terminal = on_terminal(monkeypatch)
    assert main(["evaluate", str(checkpoint), "--episodes", "1", "--json"]) == 0
    assert terminal.getvalue() == ""
    assert main(["evaluate", str(checkpoint), "--episodes", "1"]) == 0
    assert "evaluate wfc-main" in terminal.getvalue() and BAR.search(terminal.getvalue())


def test_the_evaluation_pass_of_train_shows_a_bar_on_a_terminal(trained, tmp_path, monkeypatch, capsys):
    scenario, _ = trained
    args = ["train", str(scenario), "-o", str(tmp_path / "run"), "--steps", "64", "--eval-episodes", "1", *TINY]
    assert main(args) == 0
    assert "evaluate wfc-main" not in capsys.readouterr().err  # not a terminal
    terminal = on_terminal(monkeypatch)
    assert main(args + ["--force", "--no-progress"]) == 0
    assert not BAR.search(terminal.getvalue())
    assert main(args + ["--force"]) == 0
    assert "evaluate wfc-main" in terminal.getvalue() and BAR.search(terminal.getvalue())
