"""Every `hivex` command on every environment's main scenario at the smallest size, in-process (``main([...])``).

A command that dies on one environment only (as `hivex bench` did on Ocean Plastic Collection, issue 54) fails
here. Each environment plays its main scenario cut to a few steps (a temporary copy); `train` trains one step of
every slot, `evaluate` plays one episode of what it trained. Commands that take no environment (`preview`, `docs
--check`) run once. Adding a command is one line of :data:`COMMANDS` (or :data:`ONCE`): its arguments from a
:class:`Smoke` (the scenario file, the environment, a scratch folder, the trained checkpoint).
"""

from __future__ import annotations

from pathlib import Path
from typing import Callable

import pytest
import yaml

from hivex_dsl.cli import main
from hivex_dsl.compiler import registry

ROOT = Path(__file__).resolve().parents[1]
ENV_IDS = list(registry.environments())
EPISODE = 10  # physics steps per episode of the smoke scenarios: whole decisions of every default period (1, 5)


class Smoke:
    """One environment's smoke scenario and scratch folder; :meth:`checkpoint` trains it once, the first time."""

    def __init__(self, env_id: str, folder: Path):
        self.env_id, self.folder = env_id, folder
        data = yaml.safe_load((ROOT / "scenarios" / env_id / "main.yaml").read_text())
        self.scenario = str(folder / "smoke.yaml")
        Path(self.scenario).write_text(yaml.safe_dump(data | {"name": f"{env_id}-smoke", "episode_length": EPISODE}))
        self.run_dir = folder / "run"
        self._trained: int | None = None

    def out(self, name: str) -> str:
        return str(self.folder / name)

    def train(self) -> int:
        if self._trained is None:
            # one world's agents (16 at most) through one whole episode, so the run's curve has a point (`curves`)
            self._trained = main(["train", self.scenario, "-o", str(self.run_dir), "--steps", str(16 * EPISODE),
                                  "--no-progress", "--set", "num_worlds=1"])
        return self._trained

    def checkpoint(self) -> str:
        assert self.train() == 0, "hivex train failed"
        return str(self.run_dir / "checkpoint.pt")


# command -> its arguments for one environment; `train` is Smoke.train (evaluate and the like reuse its checkpoint)
COMMANDS: dict[str, Callable[[Smoke], list[str]]] = {
    "validate": lambda s: ["validate", s.scenario],
    "compile": lambda s: ["compile", s.scenario, "-o", s.out("lock.json")],
    "run": lambda s: ["run", s.scenario, "--episodes", "1"],
    "render": lambda s: ["render", s.scenario, "-o", s.out("episode.gif"), "--steps", "4", "--frame-step", "2"],
    "audit": lambda s: ["audit", s.scenario, "--episodes", "1"],
    "bench": lambda s: ["bench", "--env", s.env_id, "--seconds", "0.05", "--repeats", "1", "--batch", "2",
                        "--no-reference"],
    "vocab": lambda s: ["vocab", s.env_id],
    "train": lambda s: [],
    "evaluate": lambda s: ["evaluate", s.checkpoint(), s.scenario, "--episodes", "1"],
    "replay": lambda s: ["replay", s.checkpoint(), "-o", s.out("episode.html"), "--trace", s.out("trace.json")],
    "curves": lambda s: ["curves", str(Path(s.checkpoint()).parent), s.scenario, "-o", s.out("curves.png")],
}
# commands that take no environment: run once
ONCE: dict[str, Callable[[Path], list[str]]] = {
    "preview": lambda folder: ["preview", "-o", str(folder / "preview")],
    "docs --check": lambda folder: ["docs", "--check", "--dir", str(ROOT / "docs")],
}


@pytest.fixture(scope="module")
def smokes(tmp_path_factory) -> dict[str, Smoke]:
    return {env_id: Smoke(env_id, tmp_path_factory.mktemp(env_id)) for env_id in ENV_IDS}


@pytest.mark.parametrize("env_id", ENV_IDS)
@pytest.mark.parametrize("command", list(COMMANDS))
def test_every_command_on_every_environment(command, env_id, smokes, capsys):
    smoke = smokes[env_id]
    code = smoke.train() if command == "train" else main(COMMANDS[command](smoke))
    out, err = capsys.readouterr()
    assert code == 0, f"hivex {command} on {env_id} exited {code}:\n{err[-3000:]}"
    assert "Traceback" not in out + err


@pytest.mark.parametrize("command", list(ONCE))
def test_every_command_without_an_environment(command, tmp_path, capsys):
    code = main(ONCE[command](tmp_path))
    out, err = capsys.readouterr()
    assert code == 0, f"hivex {command} exited {code}:\n{err[-3000:]}"


def test_the_matrix_covers_every_command_of_the_cli():
    """A new `hivex` command is added to the matrix, or named here as left out (with why)."""
    from hivex_dsl.cli import build_parser

    left_out = {"schema": "prints a constant JSON Schema; tests/test_docs.py checks it",
                "list": "lists the bundled scenarios; tests/test_cli.py checks it"}
    commands = set(build_parser()._subparsers._group_actions[0].choices)
    covered = set(COMMANDS) | {name.split()[0] for name in ONCE} | set(left_out)
    assert commands == covered, f"not in the smoke matrix: {sorted(commands - covered)}"
