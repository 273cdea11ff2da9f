"""The README's examples stay true: its YAML compiles, its Python runs."""

from __future__ import annotations

import re
from pathlib import Path

import hivex_dsl

README = (Path(__file__).resolve().parents[1] / "README.md").read_text()


def blocks(language: str) -> list[str]:
    return re.findall(rf"```{language}\n(.*?)```", README, flags=re.S)


def test_the_language_example_compiles(tmp_path):
    example, _ = blocks("yaml")
    path = tmp_path / "example.yaml"
    path.write_text(example)
    compiled = hivex_dsl.compile_all(path)
    assert [sc.agents for sc in compiled] == [1, 2, 4, 8, 12, 16]
    assert compiled[0].weights == {"generate_energy": 0.25, "avoid_damage": 1.0}


def test_the_generators_example_changes_only_what_it_writes():
    _, example = blocks("yaml")
    compiled = hivex_dsl.compile(hivex_dsl.lang.loader.load_text(example, "README.md").data)
    plain = hivex_dsl.compile({"hivex": 1, "environment": "aerial_wildfire_suppression", "terrain_level": 7})
    assert compiled.generators["forest"].ideal_height_m == 80.0
    assert compiled.generators["weather"].humidity_mean == 0.3
    assert compiled.generators["terrain"] == plain.generators["terrain"]
    assert compiled.generators["forest"].model_copy(update={"ideal_height_m": 55.0}) == plain.generators["forest"]


def test_the_python_example_runs(monkeypatch):
    monkeypatch.chdir(Path(__file__).resolve().parents[1])
    (example,) = blocks("python")
    namespace: dict = {}
    exec(compile(example, "README.md", "exec"), namespace)
    assert namespace["venv"].num_envs == 64 * 8
    assert len(namespace["suite"]) == 18


def test_the_one_line_ways_in_run():
    """The PettingZoo and Gymnasium rows of the "From RL libraries" table (SB3's runs in test_examples)."""
    rows = dict(re.findall(r"^\| (PettingZoo|Gymnasium|Stable-Baselines3) \| `([^`]*)`", README, flags=re.M))
    namespace: dict = {}
    exec(rows["PettingZoo"], namespace)
    assert namespace["env"].reset(seed=0)[0].keys() == {"vessel_0", "vessel_1", "vessel_2"} or namespace["env"].agents
    exec(rows["Gymnasium"], namespace)
    assert namespace["envs"].compiled.task_name == "find_fire" and namespace["envs"].num_worlds == 4
    assert "SB3VecEnv(" in rows["Stable-Baselines3"]
