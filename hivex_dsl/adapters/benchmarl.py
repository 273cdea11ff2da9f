"""BenchMARL tasks of every HIVEX environment and task (needs the ``benchmarl`` extra).

One ``Task`` enum per environment, one member per task of its reward table (``rewards/<env>.yaml``), each with a
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

Wind Farm Control, Wildfire Resource Management and Ocean Plastic Collection have discrete actions, Drone Based
Reforestation and Aerial Wildfire Suppression continuous ones (their discrete branches binned, see
:mod:`hivex_dsl.adapters.flat`). Every agent is one group, ``"agents"``. Every task has a global state (the
root ``"state"`` key, :mod:`hivex_dsl.runtime.global_state`), which MAPPO's centralised critic reads. With several environments per worker, the i-th copy is
seeded ``seed + i`` (BenchMARL's ``SerialEnv`` builds them one by one; with ``parallel_collection=True`` each
worker process counts from ``seed`` again, so seed the copies otherwise there).
"""

from __future__ import annotations

import itertools
import math
from dataclasses import asdict, dataclass
from typing import Any, Callable, Dict, Optional

from benchmarl.environments.common import Task, TaskClass
from benchmarl.environments.pettingzoo.common import PettingZooClass
from benchmarl.utils import DEVICE_TYPING, _read_yaml_config
from torchrl.envs import EnvBase

from .registration import make_scenario
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
    continuous: bool = False

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
        return self.continuous

    def supports_discrete_actions(self) -> bool:
        return not self.continuous

    def has_state(self) -> bool:
        return True  # hivex_dsl.runtime.global_state; BenchMARL's state_spec reads the env's "state" key

    def max_steps(self, env: EnvBase) -> int:
        compiled = self.compiled()
        return math.ceil(compiled.episode_length / compiled.decision_period)

    @classmethod
    def env_name(cls) -> str:  # a staticmethod in BenchMARL: here each environment's subclass answers
        return f"hivex_{cls.environment}"


class HivexTask(Task):
    """The tasks of a HIVEX environment; their configs come from :class:`HivexTaskConfig`, not from YAML files."""

    def get_task(self, config: Optional[Dict[str, Any]] = None) -> TaskClass:
        checked = asdict(HivexTaskConfig(**(config or {})))  # an unknown key is a TypeError here, not later
        return self.associated_class()(name=self.name, config=checked)

    def get_from_yaml(self, path: Optional[str] = None) -> TaskClass:
        return self.get_task(None if path is None else _read_yaml_config(path))


class WindFarmControlClass(HivexTaskClass):
    environment = "wind_farm_control"


class WildfireResourceManagementClass(HivexTaskClass):
    environment = "wildfire_resource_management"


class OceanPlasticCollectionClass(HivexTaskClass):
    environment = "ocean_plastic_collection"


class DroneBasedReforestationClass(HivexTaskClass):
    environment = "drone_based_reforestation"
    continuous = True


class AerialWildfireSuppressionClass(HivexTaskClass):
    environment = "aerial_wildfire_suppression"
    continuous = True


class WindFarmControlTask(HivexTask):
    GENERATE_ENERGY = None
    AVOID_DAMAGE = None

    @staticmethod
    def associated_class():
        return WindFarmControlClass


class WildfireResourceManagementTask(HivexTask):
    MAIN = None
    KEEP_ALL = None
    DISTRIBUTE_ALL = None

    @staticmethod
    def associated_class():
        return WildfireResourceManagementClass


class OceanPlasticCollectionTask(HivexTask):
    PLASTIC_COLLECTION = None
    FIND_HIGHEST_POLLUTED_AREA = None
    GROUP_UP = None
    AVOID_PLASTIC = None

    @staticmethod
    def associated_class():
        return OceanPlasticCollectionClass


class DroneBasedReforestationTask(HivexTask):
    MAIN = None
    FIND_CLOSEST_TREE = None
    GROUP_UP = None
    PICK_UP_SEED = None
    DROP_SEED = None
    FIND_HIGH_POTENTIAL_AREA = None
    FIND_HIGH_TERRAIN = None
    EXPLORE_FURTHEST = None

    @staticmethod
    def associated_class():
        return DroneBasedReforestationClass


class AerialWildfireSuppressionTask(HivexTask):
    MAIN = None
    EXTINGUISH_BURNING_TREES = None
    PREPARE_TREES = None
    MINIMIZE_FIRE_TIME = None
    PROTECT_VILLAGE = None
    PICK_UP_WATER = None
    DROP_WATER = None
    FIND_FIRE = None
    FIND_VILLAGE = None

    @staticmethod
    def associated_class():
        return AerialWildfireSuppressionClass


TASKS: dict[str, type[HivexTask]] = {
    "wind_farm_control": WindFarmControlTask,
    "wildfire_resource_management": WildfireResourceManagementTask,
    "ocean_plastic_collection": OceanPlasticCollectionTask,
    "drone_based_reforestation": DroneBasedReforestationTask,
    "aerial_wildfire_suppression": AerialWildfireSuppressionTask,
}


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
