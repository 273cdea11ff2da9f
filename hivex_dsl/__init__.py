"""hivex-dsl: declarative HIVEX scenarios compiled to batched NumPy multi-agent environments.

>>> import hivex_dsl
>>> sc = hivex_dsl.compile("scenarios/wind_farm_control/main.yaml")     # doctest: +SKIP
>>> env = hivex_dsl.parallel_env(sc, render_mode="rgb_array")           # doctest: +SKIP
"""

from __future__ import annotations

from .adapters.factory import ScenarioLike, parallel_env, vector_env
from .base.errors import ActionError, HivexError, KeywordError, ResetNeeded, ScenarioError
from .compiler import CompiledScenario, compile, compile_all

__version__ = "0.1.0"


def _register_gymnasium_ids() -> None:
    from .adapters.registration import register_gymnasium

    register_gymnasium()


_register_gymnasium_ids()


__all__ = ["ActionError", "CompiledScenario", "HivexError", "ResetNeeded", "ScenarioError", "compile",
           "compile_all", "parallel_env", "vector_env", "__version__"]
