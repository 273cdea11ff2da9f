"""PettingZoo module of wildfire_resource_management: ``env()``, ``parallel_env()``, ``raw_env`` (see :mod:`hivex_dsl.zoo`)."""

from . import module_api

env, parallel_env, raw_env = module_api("wildfire_resource_management")
