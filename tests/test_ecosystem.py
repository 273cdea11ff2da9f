"""docs/ecosystem.md's tables: the library x environment table is exactly what the marked tests cover (pytest's own
collection agrees with the static reading), the reader refuses what it cannot read, and the overhead table shows the
ratios of benchmarks/ecosystem_overhead.py's report, which the script writes."""

from __future__ import annotations

import importlib.util
import json
import subprocess
import sys
import textwrap
from pathlib import Path

import pytest

from hivex_dsl.compiler import registry
from hivex_dsl.docsgen import render_docs
from hivex_dsl.docsgen.ecosystem_matrix import LIBRARIES, EcosystemScanError, cells, matrix_context, read_proofs

ROOT = Path(__file__).resolve().parents[1]
ENV_IDS = list(registry.environments())
# Run in a fresh process: collect every test under tests/ and write each marked item's libraries and environment.
COLLECT = """
import json, sys, pytest

class Collect:
    def pytest_collection_finish(self, session):
        found = []
        for item in session.items:
            libraries = [arg for mark in item.iter_markers("ecosystem") for arg in mark.args]
            params = getattr(item, "callspec", None)
            params = params.params if params else {}
            env = params.get("env_id", params.get("environment"))
            if libraries:
                found.append([item.nodeid.split("[")[0], libraries, env])
        with open(sys.argv[2], "w") as out:
            json.dump(found, out)

code = pytest.main(["--collect-only", "-q", "-p", "no:cacheprovider", "-o", "addopts=--import-mode=importlib",
                    sys.argv[1]], plugins=[Collect()])
sys.exit(0 if code in (0, 5) else code)
"""


def collected_cells(tests: Path, tmp_path: Path) -> dict[tuple[str, str], set[str]]:
    """(library, environment) -> node ids, as pytest collects the marked tests under ``tests``."""
    out = tmp_path / "collected.json"
    done = subprocess.run([sys.executable, "-c", COLLECT, str(tests), str(out)], cwd=tests.parent,
                          capture_output=True, text=True, timeout=300)
    assert done.returncode == 0, done.stdout[-3000:] + done.stderr[-3000:]
    found: dict[tuple[str, str], set[str]] = {}
    for nodeid, libraries, env in json.loads(out.read_text()):
        assert env is not None, f"{nodeid} is marked ecosystem but runs on no environment"
        for library in libraries:
            found.setdefault((library, env), set()).add(nodeid)
    return found


def statically(tests: Path) -> dict[tuple[str, str], set[str]]:
    return {cell: set(ids) for cell, ids in cells(read_proofs(tests)).items()}


def test_the_table_s_cells_are_exactly_what_the_marked_tests_cover(tmp_path):
    assert statically(ROOT / "tests") == collected_cells(ROOT / "tests", tmp_path)


def test_every_library_is_proven_on_every_environment():
    """Today's claim: no cell of the table is '-' (a test removed or narrowed fails this, and the docs check)."""
    proven = cells(read_proofs(ROOT / "tests"))
    assert [(library, env) for library in LIBRARIES for env in ENV_IDS if (library, env) not in proven] == []


def write_tests(folder: Path, source: str) -> Path:
    """A tests/ folder holding one module, test_mod.py."""
    tests = folder / "tests"
    tests.mkdir(exist_ok=True)
    (tests / "test_mod.py").write_text(textwrap.dedent(source))
    return tests


MARKED = """
    import pytest
    from hivex_dsl.compiler import registry

    ENV_IDS = list(registry.environments())
    LENGTH = {"ocean_plastic_collection": 4}

    @pytest.mark.ecosystem("torchrl")
    @pytest.mark.parametrize("env_id", ENV_IDS)
    def test_everywhere(env_id):
        pass

    @pytest.mark.ecosystem("sb3")
    @pytest.mark.parametrize("mode", [1, 2])
    @pytest.mark.parametrize("environment", list(LENGTH))
    def test_one(environment, mode):
        pass

    class TestPairs:
        @pytest.mark.ecosystem("supersuit")
        @pytest.mark.parametrize("env_id, n", [("wind_farm_control", 1), ("drone_based_reforestation", 2)])
        def test_pairs(self, env_id, n):
            pass
"""


def test_the_reader_follows_names_dicts_pairs_and_classes_as_pytest_does(tmp_path):
    tests = write_tests(tmp_path, MARKED)
    assert statically(tests) == collected_cells(tests, tmp_path)
    page = matrix_context(tests)["matrix"]
    row = {r["title"]: r["cells"] for r in page["rows"]}
    def only(numbered: dict[str, str]) -> list[str]:
        return [numbered.get(env_id, "-") for env_id in ENV_IDS]

    assert row["SuperSuit"] == only({"wind_farm_control": "1", "drone_based_reforestation": "1"})
    assert row["Stable-Baselines3"] == only({"ocean_plastic_collection": "2"})
    assert row["TorchRL"] == ["3"] * len(ENV_IDS) and row["RLlib"] == ["-"] * len(ENV_IDS)  # numbered row by row
    assert [t["nodeid"] for t in page["tests"]] == ["tests/test_mod.py::TestPairs::test_pairs",
                                                     "tests/test_mod.py::test_one", "tests/test_mod.py::test_everywhere"]


def test_a_removed_test_removes_its_claim(tmp_path):
    tests = write_tests(tmp_path, MARKED.replace('@pytest.mark.ecosystem("torchrl")', ""))
    page = render_docs(tests=tests)["ecosystem.md"]
    assert "| TorchRL | - | - | - | - | - |" in page and "test_everywhere" not in page


@pytest.mark.parametrize("source, message", [
    ('@pytest.mark.ecosystem("torchrl")\n@pytest.mark.parametrize("env_id", [e for e in ENV_IDS])\n'
     "def test_x(env_id): pass\n", "cannot read the environments"),
    ('@pytest.mark.ecosystem("torchrl")\ndef test_x(): pass\n', "not parametrized by env_id or environment"),
    ('@pytest.mark.ecosystem("ray")\n@pytest.mark.parametrize("env_id", ENV_IDS)\ndef test_x(env_id): pass\n',
     "name one of"),
    ('@pytest.mark.ecosystem("torchrl")\n@pytest.mark.parametrize("env_id", ["chess"])\ndef test_x(env_id): pass\n',
     "are no environments"),
])
def test_what_the_reader_cannot_read_is_an_error_never_a_claim(tmp_path, source, message):
    tests = write_tests(tmp_path, "import pytest\nfrom hivex_dsl.compiler import registry\n"
                                  "ENV_IDS = list(registry.environments())\n" + source)
    with pytest.raises(EcosystemScanError, match=message):
        read_proofs(tests)


def test_without_the_tests_the_page_claims_nothing(tmp_path):
    page = render_docs(tests=tmp_path / "missing")["ecosystem.md"]
    assert "read from the tests of a checkout" in page and "| PettingZoo API suite |" not in page


HAND_WRITTEN = {
    "machine": "a test machine", "date": "2026-01-02", "steps": 10, "worlds": 2, "repeats": 1, "episode_length": 5,
    "threads": 1, "versions": {},
    "integrations": {"parallel": {"label": "PettingZoo parallel env", "what": "one per world"},
                     "torchrl": {"label": "TorchRL rollout", "what": "`torchrl_env`"}},
    "skipped": {"sb3": "stable_baselines3 is not installed"},
    "results": [{"environment": "wind_farm_control", "agents": 8, "raw_agent_steps_per_s": 123456.7,
                 "integrations": {"parallel": {"agent_steps_per_s": 61728.4, "ratio": 0.5},
                                  "torchrl": {"agent_steps_per_s": 12345.7, "ratio": 0.1}}},
                {"environment": "ocean_plastic_collection", "agents": 3, "raw_agent_steps_per_s": 1000.0,
                 "integrations": {"parallel": {"agent_steps_per_s": 987.0, "ratio": 0.987}}}],
}


def test_the_page_shows_the_report_s_ratios(tmp_path):
    path = tmp_path / "ecosystem.json"
    path.write_text(json.dumps(HAND_WRITTEN))
    page = render_docs(overhead=path)["ecosystem.md"]
    assert "| Environment | agents | raw vector env (agent-steps/s) | PettingZoo parallel env | TorchRL rollout |" in page
    assert "| `wind_farm_control` | 8 | 123,457 | 0.50 | 0.10 |" in page
    assert "| `ocean_plastic_collection` | 3 | 1,000 | 0.99 | - |" in page  # TorchRL not measured there
    assert "same worlds: 2 per environment" in page and "on a test machine, 2026-01-02.\n" in page
    assert "`sb3` was not measured: stable_baselines3 is not installed" in page
    assert "No overhead report" in render_docs(overhead=tmp_path / "missing.json")["ecosystem.md"]


def overhead_script():
    """benchmarks/ecosystem_overhead.py as a module (the benchmarks are scripts, not part of the package)."""
    spec = importlib.util.spec_from_file_location("ecosystem_overhead", ROOT / "benchmarks" / "ecosystem_overhead.py")
    script = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(script)
    return script


def test_the_benchmark_writes_rates_and_ratios_the_page_shows(tmp_path):
    script = overhead_script()
    out = tmp_path / "ecosystem.json"
    report = script.main(["--env", "ocean_plastic_collection", "--steps", "4", "--repeats", "1", "--worlds", "2",
                          "--episode-length", "3", "-o", str(out)])
    assert json.loads(out.read_text()) == report
    ready, skipped = script.available(list(script.INTEGRATIONS))
    assert list(report["integrations"]) == ready and report["skipped"] == skipped
    (result,) = report["results"]
    assert result["environment"] == "ocean_plastic_collection" and result["agents"] == 3
    for key in ready:
        measured = result["integrations"][key]
        assert measured["agent_steps_per_s"] > 0
        assert measured["ratio"] == pytest.approx(measured["agent_steps_per_s"] / result["raw_agent_steps_per_s"])
    page = render_docs(overhead=out)["ecosystem.md"]
    ratios = " | ".join(f"{result['integrations'][k]['ratio']:.2f}" for k in ready)
    assert f"| `ocean_plastic_collection` | 3 | {result['raw_agent_steps_per_s']:,.0f} | {ratios} |" in page
