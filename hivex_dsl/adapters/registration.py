"""Ways in by name: Gymnasium ids for ``make_vec`` and PettingZoo's module convention.

Gymnasium: ``import hivex_dsl`` registers ``hivex/<EnvName>-v0`` for each environment (keyword
arguments ``scenario``, ``task``, ``level`` and any top-level scenario field) and
``hivex/<EnvName>-<Scenario>-v0`` for each bundled single scenario (e.g.
``hivex/AerialWildfireSuppression-FindFire-v0``). ``make_vec``'s ``num_envs`` is the number of
copies of the environment, i.e. of worlds; the vector env's own ``num_envs`` is then
worlds x agents, its slot count.

PettingZoo: ``hivex_dsl.zoo.<env id>_v0`` modules offer ``env()`` (AEC), ``parallel_env()`` and
``raw_env``, with ``max_cycles`` the episode length.
"""

from __future__ import annotations

from typing import Any, Optional

from ..base.errors import is_integer
from ..compiler import CompiledScenario, compile, registry
from ..lang.loader import load_file

NAMESPACE = "hivex"


def camel(name: str) -> str:
    """``wind_farm_control`` -> ``WindFarmControl``."""
    return "".join(part.capitalize() for part in name.split("_"))


def make_scenario(environment: Optional[str], scenario: Any = None, task: Optional[str] = None, level: Any = None,
                  max_cycles: Optional[int] = None, **fields: Any) -> CompiledScenario:
    """A compiled scenario: ``scenario`` (a bundled scenario's name such as ``"main"`` -- the
    default --, ``"<env>/<name>"``, a path, a dict or a CompiledScenario) with ``task``, ``level``
    (the environment's level field: ``pattern`` or ``terrain_level``), ``max_cycles`` (the episode
    length in ``step()`` calls, each a decision: ``episode_length`` is ``max_cycles x decision_period``)
    and other top-level ``fields`` put over it. ``environment`` may be None when the
    scenario names it."""
    overrides = dict(fields)
    if task is not None:
        overrides["task"] = task
    if isinstance(scenario, CompiledScenario):
        if overrides or level is not None or max_cycles is not None:
            taken = sorted(overrides) + ["max_cycles"] * (max_cycles is not None) + ["level"] * (level is not None)
            raise ValueError(f"a compiled scenario cannot take {taken}: change its source instead")
        return scenario
    if environment is not None and (scenario is None or (isinstance(scenario, str) and "/" not in scenario
                                                         and not scenario.endswith(".yaml"))):
        scenario = f"{environment}/{scenario or 'main'}"
    if isinstance(scenario, dict):
        data = dict(scenario)
    elif overrides or level is not None or max_cycles is not None:
        data = load_file(registry.resolve_scenario(str(scenario))).data
    else:
        return compile(scenario)
    environment = environment or data.get("environment")
    data.setdefault("environment", environment)
    if data.get("environment") != environment:
        raise ValueError(f"the scenario is of {data.get('environment')!r}, not {environment!r}")
    if level is not None:
        entry = registry.environments().get(environment)
        level_field = entry.info.level_field if entry else None
        if level_field is None:
            raise ValueError(f"{environment} has no difficulty levels; leave level out")
        overrides[level_field] = level
    if max_cycles is not None:  # PettingZoo's cycles are step() calls: decisions of decision_period physics steps
        entry = registry.environments().get(environment)
        default = entry.info.default_decision_period if entry else 1
        period = overrides.get("decision_period", data.get("decision_period", default))
        overrides["episode_length"] = max_cycles * period if is_integer(max_cycles) and is_integer(period) \
            else max_cycles
    return compile({**data, **overrides})


def bundled_scenarios(environment: str) -> list[str]:
    """Names of the bundled scenarios of ``environment`` that are one scenario each (no sweep)."""
    return [p.stem for p in registry.get(environment).scenario_files() if "\nsweep:" not in p.read_text()]


def make_vector(environment: str, num_envs: int = 1, num_worlds: Optional[int] = None, scenario: Any = None,
                task: Optional[str] = None, level: Any = None, render_mode: Optional[str] = None,
                split: str = "train", autoreset_mode: Any = "next_step", **fields: Any):
    """The vector entry point of the ids: ``num_envs`` (make_vec's copies) counts worlds."""
    from . import gymnasium as adapter

    if num_worlds is not None and num_envs != 1:
        raise ValueError("give num_worlds or make_vec's num_envs (which counts worlds here), not both")
    compiled = make_scenario(environment, scenario, task, level, **fields)
    return adapter.HivexVectorEnv(compiled, num_worlds=num_worlds or num_envs, render_mode=render_mode,
                                  split=split, autoreset_mode=autoreset_mode)


def not_single_agent(environment: str, scenario: Any = None, **_: Any):
    """The ids' ``entry_point``: ``gymnasium.make`` builds a single-agent env, which a HIVEX environment is not,
    so it says where to go instead of Gymnasium's 'registered but entry_point is not specified'."""
    from ..base.errors import HivexError

    env_id = f"{NAMESPACE}/{camel(environment)}{'-' + camel(scenario) if isinstance(scenario, str) else ''}-v0"
    raise HivexError(f"{env_id} is a multi-agent environment, which gymnasium.make cannot build: "
                     f"gymnasium.make_vec({env_id!r}, num_envs=N) gives N worlds with a slot per agent, and "
                     f"hivex_dsl.zoo.{environment}_v0.parallel_env() gives PettingZoo's parallel API")


def register_gymnasium() -> None:
    """Register the ids (idempotent: a second call changes nothing)."""
    from gymnasium.envs.registration import register, registry as gymnasium_ids

    for environment in registry.environments():
        ids = {f"{NAMESPACE}/{camel(environment)}-v0": {}}
        for name in bundled_scenarios(environment):
            ids[f"{NAMESPACE}/{camel(environment)}-{camel(name)}-v0"] = {"scenario": name}
        for env_id, kwargs in ids.items():
            if env_id not in gymnasium_ids:
                register(id=env_id, entry_point=f"{__name__}:not_single_agent",
                         vector_entry_point=f"{__name__}:make_vector", kwargs={"environment": environment, **kwargs})
