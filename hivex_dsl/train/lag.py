"""The weights a rollout acts with under ML-Agents' threaded trainer (``policy_lag_steps``).

Every config that ran says ``threaded: true``: ML-Agents' trainer updates in a thread of its own while the main
thread steps the environment on, acting with the same policy object whose weights the update is changing. So the
first steps of the trajectories that fill the next buffer were acted by weights from before the update (or partway
through it), and the next update weighs them by their probability ratio to those weights, its trust region centred
there. The original's Wind Farm Control runs (hivex-research/hivex-results' run_logs/timers.json of pattern 0, task
0, runs 0-2) spent 2.91-3.14 s an update while the environment took 3.59-3.78 ms a step: about 800 steps of each
2,048-step trajectory acted during the update before it.

``policy_lag_steps: N`` reproduces that, deterministically: the first N steps of every rollout act with the weights
from before the last update (the update's start, the most stale reading of "partway"), the rest with the updated
ones. The first rollout has no earlier weights (both are the initial ones); a resumed run starts its lag from the
weights it resumed with. 0, the default, acts every step with the current weights (a trainer with ``threaded:
false``). Measured (issue 52, session 83; the reward tables' notes 'The threaded trainer' of Wind Farm Control and
'Keeping over training' of Wildfire Resource Management): 820 steps slow Wind Farm Control's learning at every
point of its budget and leave its policy about as decided; a whole rollout stale leaves Wildfire Resource
Management's keeping where it was. Updates here move the policy little (approximate KL about 0.002), so a ratio one
update stale stays well inside the trust region, and the default stays 0.
"""

from __future__ import annotations

import copy

from torch import nn


class PolicyLag:
    """The weights from before the last update, and how many steps of a rollout act with them."""

    def __init__(self, agent: nn.Module, steps: int):
        self.steps = steps
        self.before = copy.deepcopy(agent)
        self.before.requires_grad_(False)

    def keep(self, agent: nn.Module) -> None:
        """Keep ``agent``'s weights as they are now (called just before an update changes them)."""
        self.before.load_state_dict(agent.state_dict())

    def actor(self, agent: nn.Module, step: int) -> nn.Module:
        """Who acts at ``step`` of a rollout (0-based): the kept weights for its first :attr:`steps`, else
        ``agent``."""
        return self.before if step < self.steps else agent
