"""docs/ is generated from the live code: deterministic, fresh-checkable, faithful to the paper."""

from __future__ import annotations

import numpy as np

import json
import re
from pathlib import Path
from typing import Any

import pytest

from hivex_dsl.compiler import registry
from hivex_dsl.docsgen import MANIFEST, render_docs, stale_docs, write_docs
from hivex_dsl.docsgen.schema import SCHEMA_DIALECT, schema_of, scenario_json_schema, schema_text
from hivex_dsl.envs.wind_farm_control.simulator import WindFarmSimulator
from hivex_dsl.lang.loader import load_file
from hivex_dsl.base.resources import bundled_scenarios
from hivex_dsl.lang.spec.catalogue import PAPER_ENVIRONMENTS

WFC = "wind_farm_control"
WFC_PAGE = f"environments/{WFC}.md"
# The paper's WFC specification table: "Vector Observations (6)", three discrete actions in one branch.
PAPER_WFC_VECTOR_OBSERVATIONS = 6
PAPER_WFC_DISCRETE_ACTIONS = 3
# The paper's WFC reward scale table, row for row: (title, weight in task 0, weight in task 1).
PAPER_WFC_MATRIX = [("Generate Energy", "1", "0"), ("Avoid Damage", "0", "1")]


@pytest.fixture(scope="module")
def docs() -> dict[str, str | bytes]:
    return render_docs()


@pytest.fixture(scope="module")
def wfc_page(docs) -> str:
    return docs[WFC_PAGE]


def test_render_is_deterministic(docs):
    again = render_docs()
    assert list(again) == list(docs) == sorted(again)
    for path, content in again.items():
        if isinstance(content, np.ndarray):
            np.testing.assert_array_equal(content, docs[path])
        else:
            assert content == docs[path], path


def test_every_available_environment_has_a_page(docs):
    expected = {"index.md", "language.md", "hivex.schema.json"} | {f"environments/{e}.md" for e in registry.environments()}
    assert expected <= set(docs)
    assert {p for p in docs if p.endswith(".md")} - expected == {"generators.md", "fidelity.md", "ecosystem.md", "replay.md"}


def test_no_machine_specific_content(docs):
    for path, content in docs.items():
        if isinstance(content, np.ndarray):
            continue
        text = content if isinstance(content, str) else content.decode()
        assert " at 0x" not in text, path
        assert str(Path(__file__).resolve().parents[1]) not in text, path
        assert text.endswith("\n"), path


def test_write_then_fresh_and_idempotent(tmp_path):
    written = write_docs(tmp_path)
    assert set(written) == set(render_docs()) | {MANIFEST}
    assert stale_docs(tmp_path) == []
    assert write_docs(tmp_path) == []
    assert (tmp_path / MANIFEST).read_text().splitlines() == sorted(render_docs())


def test_stale_reports_exactly_the_edited_deleted_or_leftover_path(tmp_path):
    write_docs(tmp_path)
    (tmp_path / "index.md").write_text((tmp_path / "index.md").read_text() + "edited\n")
    assert stale_docs(tmp_path) == ["index.md"]
    write_docs(tmp_path)

    (tmp_path / WFC_PAGE).unlink()
    assert stale_docs(tmp_path) == [WFC_PAGE]
    write_docs(tmp_path)

    old = tmp_path / "environments" / "retired.md"
    old.write_text("from an older version\n")
    with (tmp_path / MANIFEST).open("a") as manifest:
        manifest.write("environments/retired.md\n")
    assert stale_docs(tmp_path) == ["environments/retired.md"]
    assert write_docs(tmp_path) == [MANIFEST, "environments/retired.md"]
    assert not old.exists() and stale_docs(tmp_path) == []


def test_write_never_touches_files_it_does_not_own(tmp_path):
    mine = tmp_path / "notes.md"
    mine.write_text("hand-written\n")
    outside = tmp_path.parent / f"{tmp_path.name}-outside.txt"
    outside.write_text("keep\n")
    write_docs(tmp_path)
    with (tmp_path / MANIFEST).open("a") as manifest:
        manifest.write(f"../{outside.name}\n")
    assert f"../{outside.name}" in stale_docs(tmp_path)
    write_docs(tmp_path)
    assert mine.read_text() == "hand-written\n" and outside.read_text() == "keep\n"
    assert stale_docs(tmp_path) == []


def test_missing_manifest_is_stale(tmp_path):
    write_docs(tmp_path)
    (tmp_path / MANIFEST).unlink()
    assert stale_docs(tmp_path) == [MANIFEST]


def test_wfc_specification_table_comes_from_the_real_spaces(wfc_page):
    assert f"**Vector Observations ({PAPER_WFC_VECTOR_OBSERVATIONS})**" in wfc_page
    assert f"`Discrete({PAPER_WFC_DISCRETE_ACTIONS})`" in wfc_page
    assert "**Visual Observations (0)**" in wfc_page
    assert "**Continuous Actions (0)**" in wfc_page
    assert "**Discrete Actions (1)**" in wfc_page
    assert WindFarmSimulator.action_meanings in wfc_page
    assert "| Neighbour Count | 0 |" in wfc_page
    for group in ("Turbine location (2)", "Turbine direction (2)", "Wind direction (2)"):
        assert group in wfc_page


def test_observation_labels_must_match_the_space(monkeypatch):
    monkeypatch.setattr(WindFarmSimulator, "observation_labels", WindFarmSimulator.observation_labels[:5])
    with pytest.raises(RuntimeError, match="observation_labels names 5 components .* has 6"):
        render_docs()


def test_wfc_reward_matrix_matches_the_paper(wfc_page):
    assert "| Paper row | Reward term | `0 generate_energy` | `1 avoid_damage` |" in wfc_page
    rows = re.findall(r"^\| (\d+) \| ([A-Za-z ]+) \(`[a-z_]+`\) \| (\S+) \| (\S+) \|$", wfc_page, re.M)
    assert [(title, w0, w1) for _, title, w0, w1 in rows] == PAPER_WFC_MATRIX
    assert [number for number, *_ in rows] == ["1", "2"]


def test_every_term_param_task_and_pattern_appears(docs):
    for env_id, entry in registry.environments().items():
        page = docs[f"environments/{env_id}.md"]
        for term in entry.terms:
            assert f"`{term.name}`" in page
            assert term.contract.equation in page
        for name in entry.params_model.model_fields:
            assert f"| `{name}` |" in page
        for task in entry.reward_table.tasks:
            assert task.title in page and task.description in page
        for name in entry.level_names:
            assert f"`{name}`" in page
        for note in entry.notes:
            assert note.split("`")[0] in page


def test_params_show_bounds_and_source_tags(wfc_page):
    assert "| `rotation_speed_deg` | 0.1 | (0, 45] | [records] |" in wfc_page
    assert "| `alignment_threshold` | 0.5 | [0, 1) | [paper] |" in wfc_page
    assert "[orig]" in wfc_page


def test_bundled_scenarios_are_listed_with_their_size(wfc_page):
    for path in bundled_scenarios():
        if path.parent.name == WFC:
            assert f"`scenarios/{WFC}/{path.name}`" in wfc_page
    assert "| `wfc-paper` |" in wfc_page and "| 18 (sweeps pattern × task) |" in wfc_page
    assert "swept: 1, 2, 4, 8, 12, 16" in wfc_page


def test_index_lists_the_catalogue(docs):
    index = docs["index.md"]
    for info in [*PAPER_ENVIRONMENTS.values(), *(entry.info for entry in registry.environments().values())]:
        assert f"`{info.id}`" in index and info.title in index
    assert "(environments/wind_farm_control.md)" in index
    assert "(language.md)" in index and "(hivex.schema.json)" in index


def test_language_reference_lists_fields_and_limits(docs):
    language = docs["language.md"]
    for entry in registry.environments().values():
        for name in entry.scenario_model.model_fields:
            assert f"| `{name}` |" in language
    for constant in ("MAX_SWEEP_POINTS", "MAX_SWEEP_VALUES", "MAX_NODES", "MAX_DEPTH", "MAX_FILE_BYTES"):
        assert constant in language
    assert "| `tasks[].ends_on` |" in language


# --- the JSON Schema -------------------------------------------------------------------------


def _check(schema: dict[str, Any], value: Any, root: dict[str, Any], path: str = "") -> list[str]:
    """A small JSON Schema check (the keywords this schema uses); returns the problems."""
    if "$ref" in schema:
        schema = root["$defs"][schema["$ref"].rsplit("/", 1)[-1]]
    if "anyOf" in schema:
        return [] if any(not _check(s, value, root, path) for s in schema["anyOf"]) else [f"{path}: no option fits"]
    if "oneOf" in schema and "discriminator" in schema:
        key = schema["discriminator"]["propertyName"]
        if not isinstance(value, dict) or key not in value:
            return [f"{path}: missing {key}"]
        options = [root["$defs"][o["$ref"].rsplit("/", 1)[-1]] for o in schema["oneOf"]]
        chosen = [o for o in options if o["properties"][key].get("const") == value[key]]
        return _check(chosen[0], value, root, path) if chosen else [f"{path}: unknown {key}"]
    problems = []
    if "const" in schema and value != schema["const"]:
        problems.append(f"{path}: not {schema['const']!r}")
    if "enum" in schema and value not in schema["enum"]:
        problems.append(f"{path}: not in enum")
    kinds = {"integer": int, "number": (int, float), "string": str, "object": dict, "array": list, "null": type(None)}
    if "type" in schema and not isinstance(value, kinds[schema["type"]]):
        return problems + [f"{path}: not {schema['type']}"]
    if isinstance(value, (int, float)) and not isinstance(value, bool):
        if value < schema.get("minimum", value) or value > schema.get("maximum", value):
            problems.append(f"{path}: out of range")
    if isinstance(value, dict):
        properties = schema.get("properties", {})
        problems += [f"{path}: missing {k}" for k in schema.get("required", ()) if k not in value]
        for key, item in value.items():
            if key in properties:
                problems += _check(properties[key], item, root, f"{path}.{key}")
            elif schema.get("additionalProperties") is False:
                problems.append(f"{path}: unknown key {key}")
            elif isinstance(schema.get("additionalProperties"), dict):
                problems += _check(schema["additionalProperties"], item, root, f"{path}.{key}")
    if isinstance(value, list) and "items" in schema:
        for i, item in enumerate(value):
            problems += _check(schema["items"], item, root, f"{path}[{i}]")
    return problems


def test_schema_file_is_the_schema_text(docs):
    assert docs["hivex.schema.json"] == schema_text()
    assert json.loads(schema_text()) == json.loads(json.dumps(scenario_json_schema()))


def _variant(schema: dict[str, Any], env_id: str) -> dict[str, Any]:
    """The object schema of one environment's scenarios (the whole schema while only one is available)."""
    if "oneOf" not in schema:
        return schema
    refs = [option["$ref"].rsplit("/", 1)[-1] for option in schema["oneOf"]]
    return next(schema["$defs"][r] for r in refs if schema["$defs"][r]["properties"]["environment"]["const"] == env_id)


def test_schema_describes_the_language():
    schema = scenario_json_schema()
    assert schema["$schema"] == SCHEMA_DIALECT and schema["title"] == "hivex-dsl scenario"
    wfc = _variant(schema, WFC)
    assert {"hivex", "environment"} <= set(wfc["properties"])
    assert {"hivex", "environment"} <= set(wfc["required"])
    assert wfc["properties"]["agents"]["maximum"] == PAPER_ENVIRONMENTS[WFC].max_agents == 16


def test_schema_accepts_every_bundled_scenario_and_rejects_mistakes():
    schema = scenario_json_schema()
    for path in bundled_scenarios():
        data = load_file(path).data
        assert _check(schema, data, schema) == [], path
        assert path.read_text().startswith("# yaml-language-server: $schema=../../docs/hivex.schema.json\n")
    assert _check(schema, {"hivex": 1, "environment": WFC, "agents": 17}, schema) == [".agents: out of range"]
    assert _check(schema, {"hivex": 1}, schema) == [": missing environment"]
    assert _check(schema, {"hivex": 1, "environment": WFC, "agnets": 3}, schema) == [": unknown key agnets"]


def test_schema_of_several_environments_is_a_discriminated_union():
    models = [registry.get(WFC).scenario_model, registry.get("ocean_plastic_collection").scenario_model]
    schema = schema_of(models)
    assert schema["title"] == "hivex-dsl scenario" and schema["$schema"] == SCHEMA_DIALECT
    assert schema["discriminator"]["propertyName"] == "environment"
    assert len(schema["oneOf"]) == 2


def test_pictures_are_compared_by_pixels_and_referenced(tmp_path, docs):
    write_docs(tmp_path)
    images = [p for p, c in docs.items() if isinstance(c, np.ndarray)]
    assert images and all(p.startswith("images/") and p.endswith(".png") for p in images)
    page = docs["generators.md"]
    assert all(f"]({p})" in page for p in images)
    from PIL import Image

    target = tmp_path / images[0]
    pixels = np.asarray(Image.open(target).convert("RGB")).copy()
    pixels[0, 0] = np.abs(pixels[0, 0].astype(int) - 1)      # off by one level: still fresh
    Image.fromarray(pixels).save(target)
    assert stale_docs(tmp_path) == []
    pixels[5:40, 5:40] = 0                                   # a real change: stale
    Image.fromarray(pixels).save(target)
    assert stale_docs(tmp_path) == [images[0]]


def test_checking_docs_where_there_are_none_says_so(tmp_path, monkeypatch, capsys):
    """Outside a checkout `hivex docs --check` reported every page stale instead of saying there is no docs/."""
    from hivex_dsl.cli import main

    monkeypatch.chdir(tmp_path)
    assert main(["docs", "--check"]) == 2
    assert capsys.readouterr().err.startswith("hivex: no docs/ here to check: run `hivex docs --check` in a checkout")
