"""The README's examples stay true: its YAML compiles, its Python runs."""

from __future__ import annotations

import re
from pathlib import Path

import hivex_dsl

README = (Path(__file__).resolve().parents[1] / "README.md").read_text()


def blocks(language: str) -> list[str]:
    return re.findall(rf"```{language}\n(.*?)```", README, flags=re.S)


def test_the_language_example_compiles(tmp_path):
    (example,) = blocks("yaml")
    path = tmp_path / "example.yaml"
    path.write_text(example)
    compiled = hivex_dsl.compile_all(path)
    assert [sc.agents for sc in compiled] == [1, 2, 4, 8, 12, 16]
    assert compiled[0].weights == {"generate_energy": 0.25, "avoid_damage": 1.0}


def test_the_python_example_runs(monkeypatch):
    monkeypatch.chdir(Path(__file__).resolve().parents[1])
    (example,) = blocks("python")
    namespace: dict = {}
    exec(compile(example, "README.md", "exec"), namespace)
    assert namespace["venv"].num_envs == 64 * 8
    assert len(namespace["suite"]) == 18
