"""Context of docs/ecosystem.md: the ids, modules and adapter semantics, read from the live code."""

from __future__ import annotations

import inspect

from .. import registry
from ..adapters import flat, joint, gymnasium as vector_adapter, module_doc, pettingzoo as parallel_adapter
from ..adapters.registration import bundled_scenarios, camel


def ecosystem_context() -> dict:
    rows = []
    for env_id in registry.environments():
        rows.append({"env": env_id, "id": f"hivex/{camel(env_id)}-v0", "module": f"hivex_dsl.zoo.{env_id}_v0",
                     "scenarios": ", ".join(f"`hivex/{camel(env_id)}-{camel(name)}-v0`"
                                               for name in bundled_scenarios(env_id))})
    return {"rows": rows,
            "vector_doc": inspect.getdoc(vector_adapter),
            "parallel_doc": inspect.getdoc(parallel_adapter.HivexParallelEnv),
            "flat_doc": inspect.getdoc(flat),
            "joint_doc": inspect.getdoc(joint),
            "sb3_doc": module_doc("sb3"),
            "torchrl_doc": module_doc("torchrl"),
            "benchmarl_doc": module_doc("benchmarl")}
