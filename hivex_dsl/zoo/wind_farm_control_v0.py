"""PettingZoo module of wind_farm_control: ``env()``, ``parallel_env()``, ``raw_env`` (see :mod:`hivex_dsl.zoo`)."""

from . import module_api

env, parallel_env, raw_env = module_api("wind_farm_control")
