"""A simulator step that crashes an agent on cue, for the tests of agent death (global state, TorchRL's masks)."""

from __future__ import annotations

import numpy as np

from hivex_dsl.runtime import StepOutcome


def first_agent_crashes_on(step_number: int):
    """A simulator step after which agent 0 terminates on the world's ``step_number``-th step (its world goes on)."""
    steps = [0]

    def step(sim, state, actions, rng):
        new, outcome = sim.step(state, actions, rng)
        steps[0] += 1
        terminated = np.array(outcome.terminated, bool)
        terminated[:, 0] |= steps[0] == step_number
        return new, StepOutcome(terminated, outcome.events)

    return step
