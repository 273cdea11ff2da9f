"""The example environment (tests/example_env/bee_foraging) through every command and adapter, and the open
catalogue: the example copied under a new id into a copy of the source tree (no other file edited), and installed as
a separate package whose entry point the registry finds."""

from __future__ import annotations

import importlib
import json
import os
import shutil
import subprocess
import sys
import textwrap
from pathlib import Path

import numpy as np
import pytest
from pettingzoo.test import api_test, parallel_api_test

import hivex_dsl
from hivex_dsl.cli import main as hivex
from hivex_dsl.compiler import registry
from hivex_dsl.runtime import contract
from hivex_dsl.sim.reward import vocabulary as vocabularies

ROOT = Path(__file__).resolve().parents[1]
EXAMPLE_ROOT = Path(__file__).resolve().parent / "example_env"
EXAMPLE = EXAMPLE_ROOT / "bee_foraging"
ID = "bee_foraging"
SCENARIOS = EXAMPLE / "scenarios"


@pytest.fixture
def bees(monkeypatch):
    """The example asked for (``HIVEX_ENVIRONMENTS``), in a copy of the registry that is put back afterwards."""
    monkeypatch.setattr(registry, "_REGISTRY", dict(registry.environments()))  # before asking: it registers here
    monkeypatch.setattr(vocabularies, "_DECLARED", dict(vocabularies._DECLARED))
    monkeypatch.syspath_prepend(str(EXAMPLE_ROOT))
    monkeypatch.setenv("PYTHONPATH", os.pathsep.join([str(EXAMPLE_ROOT), *sys.path]))  # child processes (bench) too
    monkeypatch.setenv(registry.ENVIRONMENTS_VARIABLE, ID)
    module = importlib.import_module(ID)
    if ID not in registry._REGISTRY:  # imported by an earlier test: register it again in this copy
        registry.register(module.ENTRY)
    return registry.get(ID)


def test_the_example_is_not_in_the_catalogue_users_see():
    assert ID not in registry.environments() and registry.ENVIRONMENTS_VARIABLE not in os.environ


def test_asked_for_it_is_in_the_catalogue(bees):
    assert ID in registry.environments()


def test_after_asking_the_catalogue_is_as_it_was():
    assert ID not in registry.environments()


def test_asked_for_it_comes_after_the_paper_s_five(bees):
    assert list(registry.environments()) == [*list(registry.PAPER_ENVIRONMENTS), ID]
    assert bees.reward_table.task_names == ("feed_the_hive", "gather_nectar")
    assert [p.name for p in bees.scenario_files()] == ["gather_nectar.yaml", "main.yaml", "swarm_size.yaml"]


def test_its_simulator_fulfils_the_contract_and_a_simulator_that_does_not_is_named(bees):
    for entry in registry.environments().values():
        compiled = hivex_dsl.compile({"hivex": 1, "environment": entry.id})
        simulator = entry.make_simulator(compiled)
        assert contract.missing_members(simulator) == [] and isinstance(simulator, contract.Simulator), entry.id
    compiled = hivex_dsl.compile(f"{ID}/main")

    class NoPicture:
        def __init__(self, c):
            self.inner = bees.make_simulator(c)

        def __getattr__(self, name):
            if name == "render":
                raise AttributeError(name)
            return getattr(self.inner, name)

    import dataclasses

    broken = dataclasses.replace(compiled, entry=dataclasses.replace(bees, make_simulator=NoPicture))
    with pytest.raises(TypeError, match="NoPicture lacks render"):
        hivex_dsl.runtime.BatchedEnv(broken)


@pytest.mark.parametrize("words", [["validate", str(SCENARIOS / "main.yaml"), str(SCENARIOS / "swarm_size.yaml")],
                                   ["compile", f"{ID}/gather_nectar"], ["run", f"{ID}/main", "--policy", "random"],
                                   ["audit", f"{ID}/main", "--episodes", "1"], ["vocab", f"{ID}/main"], ["list"],
                                   ["schema"], ["bench", "--env", ID, "--seconds", "0.05", "--no-reference"]])
def test_every_command_takes_it(bees, words, capsys):
    assert hivex(words) == 0
    out = capsys.readouterr().out
    assert ID in out or "bf-" in out


def test_render_writes_a_gif(bees, tmp_path):
    assert hivex(["render", f"{ID}/main", "-o", str(tmp_path / "bees.gif")]) == 0
    assert (tmp_path / "bees.gif").read_bytes()[:6] == b"GIF89a"


def test_the_scripted_bees_bring_nectar_home_and_random_ones_barely(bees):
    from hivex_dsl.evaluation.audit import audit_all

    audit = audit_all([hivex_dsl.compile(f"{ID}/main")], 1, quiet=True)[0].as_dict()
    delivered = {policy: audit["policies"][policy]["terms"]["nectar_delivered"]["mean"]
                 for policy in ("zeros", "random", "scripted")}
    assert delivered["zeros"] == 0 and delivered["scripted"] > 1.0 > delivered["random"]


def test_pettingzoo_parallel_api_through_parallel_env_and_its_zoo_module(bees):
    parallel_api_test(hivex_dsl.parallel_env({"hivex": 1, "environment": ID, "episode_length": 40}), num_cycles=60)
    module = importlib.import_module(f"hivex_dsl.zoo.{ID}_v0")
    parallel_api_test(module.parallel_env(max_cycles=40), num_cycles=60)
    api_test(module.env(max_cycles=20), num_cycles=30)


def test_its_global_state_matches_its_facts_by_hand(bees):
    env = hivex_dsl.parallel_env(f"{ID}/main")
    env.reset(seed=3)
    for _ in range(20):
        state = env.state()
        for name, value in bees.state_facts(env.core.sim, env.core.state, env.core.compiled.params).items():
            np.testing.assert_allclose(state[env.global_state.slices[name]], value, rtol=1e-6, atol=1e-6)
        env.step({agent: 3 for agent in env.agents})  # every bee flies east


def test_gymnasium_ids_and_the_vector_env(bees, monkeypatch):
    import gymnasium
    from gymnasium.envs import registration as gymnasium_registration

    from hivex_dsl.adapters.registration import register_gymnasium

    monkeypatch.setattr(gymnasium_registration, "registry", dict(gymnasium_registration.registry))
    register_gymnasium()
    assert {"hivex/BeeForaging-v0", "hivex/BeeForaging-Main-v0", "hivex/BeeForaging-GatherNectar-v0"} <= \
        set(gymnasium_registration.registry)
    assert "hivex/BeeForaging-SwarmSize-v0" not in gymnasium_registration.registry  # a sweep is no single scenario
    venv = gymnasium.make_vec("hivex/BeeForaging-v0", num_envs=2, max_cycles=10)
    obs, _ = venv.reset(seed=0)
    assert obs.shape == (6, 8)
    truncations = []
    for _ in range(12):
        obs, rewards, terminated, truncated, _ = venv.step(venv.action_space.sample())
        truncations.append(truncated.all())
    assert truncations.index(True) == 9  # every slot at the 10th step: max_cycles=10


def test_benchmarl_and_torchrl_take_it(bees):
    pytest.importorskip("benchmarl")
    from hivex_dsl.adapters.benchmarl import TASKS, task

    assert list(TASKS)[-1] == ID
    assert [member.name for member in TASKS[ID]] == ["FEED_THE_HIVE", "GATHER_NECTAR"]
    bench_task = task(ID, "gather_nectar", max_cycles=5)
    assert bench_task.supports_discrete_actions() and not bench_task.supports_continuous_actions()
    env = bench_task.get_env_fun(1, False, 0, "cpu")()
    rollout = env.rollout(5)
    assert rollout.batch_size[0] == 5


def test_it_trains_on_the_stated_defaults_without_paper_hyperparameters(bees, tmp_path):
    from hivex_dsl.train.config import PPOConfig, has_paper_hyperparameters, make_config

    assert not has_paper_hyperparameters(ID) and make_config(ID) == PPOConfig()
    scenario = tmp_path / "short.yaml"
    scenario.write_text((SCENARIOS / "main.yaml").read_text().replace("episode_length: 300", "episode_length: 20"))
    assert hivex(["train", str(scenario), "-o", str(tmp_path / "run"), "--steps", "240", "--set", "buffer_size=120",
                  "--set", "batch_size=60", "--set", "num_worlds=2", "--set", "torch_threads=1", "--no-progress"]) == 0
    assert json.loads((tmp_path / "run" / "summary.json").read_text())["agent_steps"] >= 240
    assert hivex(["evaluate", str(tmp_path / "run" / "checkpoint.pt"), "--episodes", "1", "--json"]) == 0


def test_its_docs_page_the_guide_and_the_shared_pages(bees):
    from hivex_dsl.docsgen import _jinja
    from hivex_dsl.docsgen.adding import adding_context
    from hivex_dsl.docsgen.baselines import hyperparameter_table
    from hivex_dsl.docsgen.context import environment_context, index_context
    from hivex_dsl.docsgen.fidelity_page import fidelity_context
    from hivex_dsl.evaluation.fidelity import FIDELITY_FILE

    page = _jinja().get_template("environment.md.j2").render(**environment_context(bees))
    assert page.startswith("<!-- Generated") and "# Bee Foraging (BF)" in page
    assert "Paper row" not in page and "## Notes\n" in page and "No paper hyperparameters ship for bee_foraging" in page
    assert "| Nectar Delivered (`nectar_delivered`) | 1 | 0 |" in page  # the reward table, without a paper column
    assert f"tests/example_env/{ID}/scenarios/main.yaml" in page
    guide = _jinja().get_template("adding_an_environment.md.j2").render(**adding_context(ROOT / "tests"))
    for field in ("make_simulator", "content_dir", "state_facts", "quantities"):
        assert f"| `{field}` |" in guide
    for member in ("reset_where", "world_state", "respawn_where", "observation_labels"):
        assert f"`{member}" in guide
    assert (EXAMPLE / "simulator.py").read_text() in guide  # the walk-through shows the example as it is
    assert ID not in {env["id"] for env in fidelity_context(ROOT / FIDELITY_FILE)["environments"]}  # no cell
    table = hyperparameter_table()
    assert table["hp_defaulted"] == [ID] and ID not in {row["environment"] for row in table["hp_rows"]}
    assert [row["id"] for row in index_context()["environments"]][-1] == ID


def test_a_bad_entry_is_refused(bees):
    import dataclasses

    with pytest.raises(ValueError, match="registered twice"):
        registry.register(bees)
    with pytest.raises(ValueError, match="lower-case Python name"):
        registry.register(dataclasses.replace(bees, info=dataclasses.replace(bees.info, id="Bee-Foraging")))
    with pytest.raises(ValueError, match="differs from the paper"):
        registry.register(dataclasses.replace(registry.get("wind_farm_control"),
                                              info=dataclasses.replace(bees.info, id="wind_farm_control")))


def copy_example(target: Path, new_id: str) -> None:
    """The example's folder at ``target`` with its id replaced by ``new_id`` in every file."""
    shutil.copytree(EXAMPLE, target, ignore=shutil.ignore_patterns("__pycache__"))
    for path in target.rglob("*"):
        if path.is_file():
            path.write_text(path.read_text().replace(ID, new_id))


CHECKS = """
import importlib, sys
from pettingzoo.test import parallel_api_test
import hivex_dsl
from hivex_dsl.cli import main as hivex
from hivex_dsl.compiler import registry
new = sys.argv[1]
assert list(registry.environments())[-1] == new, list(registry.environments())
for words in (["validate", f"{new}/main"], ["compile", f"{new}/swarm_size"], ["run", f"{new}/main"]):
    assert hivex(words) == 0, words
parallel_api_test(hivex_dsl.parallel_env({"hivex": 1, "environment": new, "episode_length": 30}), num_cycles=40)
parallel_api_test(importlib.import_module(f"hivex_dsl.zoo.{new}_v0").parallel_env(max_cycles=30), num_cycles=40)
from hivex_dsl.docsgen.context import environment_context
from hivex_dsl.docsgen import _jinja
page = _jinja().get_template("environment.md.j2").render(**environment_context(registry.get(new)))
assert f"Environment id `{new}`" in page, page[:300]
print("checked", new)
"""


def test_a_copy_under_a_new_id_in_a_copy_of_the_tree_needs_no_other_edit(tmp_path):
    tree = tmp_path / "tree"
    for name in ("hivex_dsl", "rewards", "scenarios", "generators", "benchmarks/results", "tests/bad", "docs",
                 "examples"):
        shutil.copytree(ROOT / name, tree / name, ignore=shutil.ignore_patterns("__pycache__", "*.png", "*.gif"))
    shutil.copy(ROOT / "README.md", tree / "README.md")
    for name in ("conftest.py", "crashes.py", "test_bad_scenarios.py", "test_public_api.py", "test_global_state.py",
                 "test_fidelity.py", "test_layers.py"):
        shutil.copy(ROOT / "tests" / name, tree / "tests" / name)
    shutil.copy(ROOT / "pyproject.toml", tree / "pyproject.toml")
    before = {p.relative_to(tree): p.read_bytes() for p in tree.rglob("*") if p.is_file()}
    copy_example(tree / "hivex_dsl" / "envs" / "orchard_bees", "orchard_bees")
    after = {p.relative_to(tree): p.read_bytes() for p in tree.rglob("*") if p.is_file()}
    assert {path for path in after if path not in before or after[path] != before[path]} == \
        {path for path in after if path.parts[:3] == ("hivex_dsl", "envs", "orchard_bees")}  # no other file edited
    env = {**os.environ, "PYTHONPATH": str(tree)}
    env.pop(registry.ENVIRONMENTS_VARIABLE, None)
    done = subprocess.run([sys.executable, "-c", CHECKS, "orchard_bees"], cwd=tree, env=env, capture_output=True,
                          text=True, timeout=300)
    assert done.returncode == 0 and "checked orchard_bees" in done.stdout, done.stderr[-3000:]
    tests = ["tests/test_bad_scenarios.py::test_bad_scenario_reports_exactly_its_problem",
             "tests/test_public_api.py::test_every_zoo_module_has_the_pettingzoo_functions",
             "tests/test_global_state.py",
             "tests/test_fidelity.py::test_the_suite_is_the_whole_published_grid_and_every_task_at_its_first_level",
             "tests/test_fidelity.py::test_the_stored_suite_was_measured_on_the_scenarios_as_they_are_now",
             "tests/test_layers.py"]
    selected = "missing_environment or misspelt_environment or orchard_bees or suite or layer or import or circle" \
               " or top or private"
    done = subprocess.run([sys.executable, "-m", "pytest", "-rA", "-p", "no:cacheprovider", "-x", "-k", selected,
                           *tests], cwd=tree, env=env, capture_output=True, text=True, timeout=400)
    assert done.returncode == 0, done.stdout[-4000:]
    for test in ("test_global_state.py::test_world_facts_match_values_computed_by_hand_from_the_simulator_state",
                 "test_global_state.py::test_pettingzoo_state_test",
                 "test_public_api.py::test_every_zoo_module_has_the_pettingzoo_functions"):
        assert f"PASSED tests/{test}[orchard_bees]" in done.stdout, test
    assert "PASSED tests/test_bad_scenarios.py::test_bad_scenario_reports_exactly_its_problem[missing_environment]" \
        in done.stdout


def test_an_installed_package_s_entry_point_adds_its_environment(tmp_path):
    """A separate distribution (its dist-info on the path, as pip writes it) declaring the entry point."""
    site = tmp_path / "site"
    copy_example(site / "meadow_bees", "meadow_bees")
    info = site / "meadow_bees-0.1.dist-info"
    info.mkdir()
    (info / "METADATA").write_text("Metadata-Version: 2.1\nName: meadow-bees\nVersion: 0.1\n")
    (info / "entry_points.txt").write_text(textwrap.dedent(f"""
        [{registry.ENTRY_POINT_GROUP}]
        meadow_bees = meadow_bees:ENTRY
        broken = no_such_module_here
        """))
    env = {**os.environ, "PYTHONPATH": os.pathsep.join([str(site), str(ROOT)])}
    env.pop(registry.ENVIRONMENTS_VARIABLE, None)
    done = subprocess.run([sys.executable, "-W", "always", "-c", CHECKS, "meadow_bees"], cwd=tmp_path, env=env,
                          capture_output=True, text=True, timeout=300)
    assert done.returncode == 0 and "checked meadow_bees" in done.stdout, done.stderr[-3000:]
    assert "environment plugin 'broken' (no_such_module_here)" in done.stderr  # named, and the others still load
