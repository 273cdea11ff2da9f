"""PettingZoo module of aerial_wildfire_suppression: ``env()``, ``parallel_env()``, ``raw_env`` (see :mod:`hivex_dsl.zoo`)."""

from . import module_api

env, parallel_env, raw_env = module_api("aerial_wildfire_suppression")
