"""The world facts of Wind Farm Control's global state (:mod:`hivex_dsl.runtime.global_state`)."""

from __future__ import annotations

import numpy as np

from ...runtime.global_state import StateComponent
from .types import WindFarmState


def state_components(self) -> tuple[StateComponent, ...]:
    """The main wind and its target (what every turbine's local wind deviates from), and each turbine's
    performance P, which drives the Generate Energy reward and no turbine observes."""
    return (
        StateComponent("main wind", 2, -1.0, 1.0, "Direction the main wind blows to (cos, sin); each turbine's "
                       "local wind is this turned by the noise field."),
        StateComponent("wind target", 2, -1.0, 1.0, "Direction the main wind eases toward (cos, sin); it turns "
                       "by the target shift once reached."),
        StateComponent("performance", 1, 0.0, 1.0, "The turbine's performance P clamped to [0, 1], as the "
                       "Generate Energy reward reads it.", per_agent=True),
    )


def world_state(self, state: WindFarmState) -> tuple[np.ndarray, np.ndarray]:
    """(vectors (B, A, 6) float32 the turbines' observations, world (B, 4 + A) float64: main wind (2), wind
    target (2), performance (A))."""
    wind = state.wind
    world = np.concatenate([np.stack([np.cos(wind.main), np.sin(wind.main), np.cos(wind.target),
                                      np.sin(wind.target)], axis=1), np.clip(state.performance, 0.0, 1.0)], axis=1)
    return self.observe(state), world


def state_facts(simulator, state: WindFarmState, params) -> dict[str, list[float]]:
    """World 0's main wind and performance read straight off the state, for the tests to compare with
    :func:`world_state` (:attr:`hivex_dsl.compiler.registry.EnvironmentEntry.state_facts`)."""
    return {"main wind": [float(np.cos(state.wind.main[0])), float(np.sin(state.wind.main[0]))],
            "performance": [min(max(float(p), 0.0), 1.0) for p in state.performance[0]]}
