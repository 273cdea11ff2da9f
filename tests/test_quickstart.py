"""docs/quickstart.md runs as written: its YAML is the task, and each `$ hivex ...` line is run in order."""

from __future__ import annotations

import json
import re
import shlex
from pathlib import Path

import pytest

pytest.importorskip("torch")

from hivex_dsl.cli import main  # noqa: E402

PAGE = (Path(__file__).resolve().parents[1] / "docs" / "quickstart.md").read_text()


def commands() -> list[list[str]]:
    return [shlex.split(line[len("$ hivex "):]) for block in re.findall(r"```console\n(.*?)```", PAGE, flags=re.S)
            for line in block.splitlines() if line.startswith("$ hivex ")]


def test_the_quickstart_runs_as_written_and_the_trained_policy_learns(tmp_path, monkeypatch, capsys):
    (task,) = re.findall(r"```yaml\n(.*?)```", PAGE, flags=re.S)
    monkeypatch.chdir(tmp_path)
    Path("my_task.yaml").write_text(task)
    steps = commands()
    assert [c[0] for c in steps] == ["validate", "compile", "audit", "train", "evaluate", "audit", "render", "replay"]
    for command in steps:
        assert main(command) == 0, command
    run = Path("runs/my-steady-farm")
    for name in ("checkpoint.pt", "curve.json", "summary.json", "config.json"):
        assert (run / name).is_file(), name
    assert list((run / "tb").glob("events.out.tfevents.*"))
    assert Path("my-steady-farm.gif").stat().st_size > 0
    assert 'id="replay-data"' in Path("my-steady-farm.html").read_text()
    # what the page says of the trained column: well above the trivial policies, most of the scripted return
    capsys.readouterr()
    assert main(["audit", "my_task.yaml", "--checkpoint", str(run / "checkpoint.pt"), "--json"]) == 0
    (audit,) = json.loads(capsys.readouterr().out)
    mean = {name: policy["return"]["mean"] for name, policy in audit["policies"].items()}
    trivial = max(mean["zeros"], mean["random"])
    assert mean["trained"] > trivial + 0.5 * (mean["scripted"] - trivial), mean
