"""PettingZoo module of ocean_plastic_collection: ``env()``, ``parallel_env()``, ``raw_env`` (see :mod:`hivex_dsl.zoo`)."""

from . import module_api

env, parallel_env, raw_env = module_api("ocean_plastic_collection")
