"""PettingZoo module of drone_based_reforestation: ``env()``, ``parallel_env()``, ``raw_env`` (see :mod:`hivex_dsl.zoo`)."""

from . import module_api

env, parallel_env, raw_env = module_api("drone_based_reforestation")
