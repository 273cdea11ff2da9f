"""BenchMARL tasks of every HIVEX environment and task (needs the ``benchmarl`` extra).

One ``Task`` enum per registered environment (made from the registry: :data:`TASKS`, or by name as
``OceanPlasticCollectionTask``), one member per task of its reward table, each with a
``TaskClass`` that builds the env as :func:`hivex_dsl.adapters.torchrl.torchrl_env` does (TorchRL's
``PettingZooWrapper`` with ``use_mask=True, done_on_any=False``, flat observations, WRM's and OPC's MultiDiscrete
actions as one joint Discrete action, DBR's and AWS's hybrid actions as one Box(-1, 1)), so BenchMARL's
``Experiment`` runs them with ``MappoConfig``, ``IppoConfig`` or any algorithm that takes their actions::

    from benchmarl.algorithms import MappoConfig
    from benchmarl.experiment import Experiment, ExperimentConfig
    from benchmarl.models import MlpConfig
    from hivex_dsl.adapters.benchmarl import OceanPlasticCollectionTask

    task = OceanPlasticCollectionTask.GROUP_UP.get_task({"max_cycles": 500})
    Experiment(task=task, algorithm_config=MappoConfig.get_from_yaml(), model_config=MlpConfig.get_from_yaml(),
               critic_model_config=MlpConfig.get_from_yaml(), seed=0, config=ExperimentConfig.get_from_yaml()).run()

A task's config (:class:`HivexTaskConfig`, every field optional): ``scenario`` (a bundled scenario's name such as
``"main"``, the default, ``"<env>/<name>"`` or a YAML path; the member's task is put over it), ``level`` (the
environment's ``pattern`` or ``terrain_level``) and ``max_cycles`` (the episode length in ``step()`` calls, which is
also the evaluation rollouts' ``max_steps``). ``get_task()`` without a config takes the defaults: BenchMARL's
own tasks read theirs from YAML files inside the benchmarl package, ours need none.

An environment whose action space is a Box or a hybrid Dict has continuous actions here (Drone Based
Reforestation and Aerial Wildfire Suppression, their discrete branches binned, see :mod:`hivex_dsl.adapters.flat`),
the others discrete ones (Wind Farm Control, Wildfire Resource Management, Ocean Plastic Collection). Every agent is one group, ``"agents"``. Every task has a global state (the
root ``"state"`` key, :mod:`hivex_dsl.runtime.global_state`), which MAPPO's centralised critic reads. With several environments per worker, the i-th copy is
seeded ``seed + i`` (BenchMARL's ``SerialEnv`` builds them one by one; with ``parallel_collection=True`` each
worker process counts from ``seed`` again, so seed the copies otherwise there).
"""

from __future__ import annotations

import itertools
import math
from dataclasses import asdict, dataclass
from functools import lru_cache
from typing import Any, Callable, Dict, Iterator, Mapping, Optional

from benchmarl.environments.common import Task, TaskClass
from gymnasium import spaces
from benchmarl.environments.pettingzoo.common import PettingZooClass
from benchmarl.utils import DEVICE_TYPING, _read_yaml_config
from torchrl.envs import EnvBase

from ..compiler import registry
from .flat import is_hybrid
from .registration import camel, make_scenario
from .torchrl import torchrl_env


@dataclass
class HivexTaskConfig:
    """A HIVEX task's BenchMARL config; every field is optional (see the module)."""

    scenario: Optional[str] = None
    level: Optional[int] = None
    max_cycles: Optional[int] = None


class HivexTaskClass(PettingZooClass):
    """A task of one HIVEX environment; BenchMARL's PettingZoo class reads the specs (observation, action, mask)."""

    environment: str = ""

    def compiled(self):
        return make_scenario(self.environment, self.config.get("scenario"), task=self.name.lower(),
                             level=self.config.get("level"), max_cycles=self.config.get("max_cycles"))

    def get_env_fun(self, num_envs: int, continuous_actions: bool, seed: Optional[int],
                    device: DEVICE_TYPING) -> Callable[[], EnvBase]:
        compiled = self.compiled()
        copies = itertools.count()  # SerialEnv builds num_envs copies with this function: seed + i for the i-th

        def make() -> EnvBase:
            copy_seed = None if seed is None else seed + next(copies)
            return torchrl_env(compiled, seed=copy_seed, device=device, render_mode="rgb_array")

        return make

    def supports_continuous_actions(self) -> bool:
        return continuous_actions(self.environment)

    def supports_discrete_actions(self) -> bool:
        return not continuous_actions(self.environment)

    def has_state(self) -> bool:
        return True  # hivex_dsl.runtime.global_state; BenchMARL's state_spec reads the env's "state" key

    def max_steps(self, env: EnvBase) -> int:
        compiled = self.compiled()
        return math.ceil(compiled.episode_length / compiled.decision_period)

    @classmethod
    def env_name(cls) -> str:  # a staticmethod in BenchMARL: here each environment's subclass answers
        return f"hivex_{cls.environment}"


@lru_cache(maxsize=None)
def continuous_actions(environment: str) -> bool:
    """Whether the environment's actions reach BenchMARL as a Box (a Box or hybrid action space, see the module),
    read off the simulator of its bundled main scenario."""
    compiled = make_scenario(environment)
    space = compiled.entry.make_simulator(compiled).action_space
    return is_hybrid(space) or isinstance(space, spaces.Box)


class HivexTask(Task):
    """The tasks of a HIVEX environment; their configs come from :class:`HivexTaskConfig`, not from YAML files."""

    def get_task(self, config: Optional[Dict[str, Any]] = None) -> TaskClass:
        checked = asdict(HivexTaskConfig(**(config or {})))  # an unknown key is a TypeError here, not later
        return self.associated_class()(name=self.name, config=checked)

    def get_from_yaml(self, path: Optional[str] = None) -> TaskClass:
        return self.get_task(None if path is None else _read_yaml_config(path))


def _task_enum(environment: str) -> type[HivexTask]:
    """``<Env>Task``, the Task enum of one environment (a member per task of its reward table), with its
    ``<Env>Class``; both made from the registry, so a new environment has them without an edit here."""
    entry = registry.get(environment)
    name = camel(environment)
    task_class = type(f"{name}Class", (HivexTaskClass,), {"environment": environment, "__module__": __name__})
    members = [(task.name.upper(), None) for task in entry.reward_table.tasks]
    enum = HivexTask(f"{name}Task", members, module=__name__, qualname=f"{name}Task")
    enum.associated_class = staticmethod(lambda: task_class)
    return enum


_ENUMS: dict[str, type[HivexTask]] = {}


def task_enum(environment: str) -> type[HivexTask]:
    """The Task enum of ``environment`` (made once)."""
    if environment not in _ENUMS:
        _ENUMS[environment] = _task_enum(environment)
    return _ENUMS[environment]


class _Tasks(Mapping[str, type[HivexTask]]):
    """Environment id -> its Task enum, for every registered environment, in the registry's order."""

    def __getitem__(self, environment: str) -> type[HivexTask]:
        if environment not in registry.environments():
            raise KeyError(environment)
        return task_enum(environment)

    def __iter__(self) -> Iterator[str]:
        return iter(registry.environments())

    def __len__(self) -> int:
        return len(registry.environments())


TASKS: Mapping[str, type[HivexTask]] = _Tasks()


def __getattr__(name: str) -> type:
    """``OceanPlasticCollectionTask`` and ``OceanPlasticCollectionClass``: the enum and task class of a registered
    environment, by their names."""
    for environment in registry.environments():
        enum = task_enum(environment)
        if name == enum.__name__:
            return enum
        if name == enum.associated_class().__name__:
            return enum.associated_class()
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


def task(environment: str, name: Optional[str] = None, **config: Any) -> TaskClass:
    """The BenchMARL task of ``environment``'s task ``name`` (default: its bundled main scenario's task) with
    ``config`` (:class:`HivexTaskConfig`'s fields): ``task("ocean_plastic_collection", "group_up", max_cycles=50)``."""
    if environment not in TASKS:
        raise KeyError(f"unknown environment {environment!r}; expected one of: {', '.join(TASKS)}")
    enum = TASKS[environment]
    if name is None:
        name = make_scenario(environment, config.get("scenario")).task_name
    members = {member.name.lower(): member for member in enum}
    if name not in members:
        raise KeyError(f"{environment} has no task {name!r}; its tasks: {', '.join(members)}")
    return members[name].get_task(config)
