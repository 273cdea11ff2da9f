"""Wind Farm Control as a batched NumPy simulator (no Python loop over worlds or turbines in step)."""

from __future__ import annotations

import numpy as np
from gymnasium import spaces

from ...base.numeric import clamp, constant
from ...runtime.batched import StepOutcome
from ...sim.batching import assemble, evolve
from ...sim.procgen.layouts import turbine_layout
from ...sim.procgen.wind import probe_wind, wind_reset, wind_reset_where, wind_step, wrap_angle
from .global_state import state_components, world_state
from .params import WindFarmControlParams
from .types import WindFarmState

RANDOM_PATTERN = 8
# action -> rotation sign: 0 do nothing, 1 rotate left (counter-clockwise), 2 rotate right
ROTATION_SIGN = np.array([0.0, 1.0, -1.0])
# float64 operands as 0-d arrays (see hivex_dsl.base.numeric)
_ZERO, _ONE, _MINUS_ONE, _PI = constant(0.0), constant(1.0), constant(-1.0), constant(np.pi)


def angle_between(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Unsigned angle between directions ``a`` and ``b`` (radians, any shape) in [0, pi]."""
    return np.abs(wrap_angle(a - b))


def alignment(heading: np.ndarray, wind: np.ndarray) -> np.ndarray:
    """How squarely the rotor faces into the wind, in [0, 1]: 1 facing upwind, 0 facing downwind.

    The paper's theta: the angle between the rotor's facing and the upwind direction, mapped
    linearly from [0, 180] degrees to [1, 0].
    """
    return _ONE - angle_between(heading, wind + _PI) / _PI


def wind_force(align: np.ndarray, threshold: float, span: float | None = None) -> np.ndarray:
    """The paper's W(theta): 0 below the threshold, Map(theta, threshold, 1, 0, 1) above it.

    ``span`` is 1 - threshold, for a caller that keeps both as 0-d operands (see hivex_dsl.base.numeric)."""
    return clamp((align - threshold) / (1.0 - threshold if span is None else span), _ZERO, _ONE)


def next_performance(performance: np.ndarray, force: np.ndarray, acceleration: float, drag: float) -> np.ndarray:
    """The paper's update P <- P + d + W * a_turbine with d = -drag * P."""
    return performance - drag * performance + force * acceleration


class WindFarmSimulator:
    """B worlds of one compiled Wind Farm Control scenario."""

    action_meanings = "0 do nothing, 1 rotate left, 2 rotate right"
    observation_labels = ("turbine location x", "turbine location y", "turbine direction x", "turbine direction y", "wind direction x", "wind direction y")
    render_fps = 30

    def __init__(self, compiled):
        params: WindFarmControlParams = compiled.params
        self.params = params
        self.agents = compiled.agents
        self.pattern = compiled.level
        self.observation_space = spaces.Box(-1.0, 1.0, (6,), np.float32)
        self.action_space = spaces.Discrete(3)
        self.wind_spec = params.wind_spec()
        self._turn_by_action = np.radians(params.rotation_speed_deg) * ROTATION_SIGN  # (3,) radians per step
        self._threshold = constant(params.alignment_threshold)
        self._threshold_span = constant(1.0 - params.alignment_threshold)
        self._drag, self._acceleration = constant(params.drag), constant(params.motor_acceleration)
        self._half_extent = constant(params.farm_half_extent_m)
        self._fixed_layout = None if self.pattern == RANDOM_PATTERN else self._layout(None)

    def _layout(self, rng: np.random.Generator | None) -> np.ndarray:
        p = self.params
        return turbine_layout(self.pattern, self.agents, p.turbine_spacing_m, p.farm_half_extent_m, rng)

    def _layouts(self, rng: np.random.Generator, count: int) -> np.ndarray:
        """(count, A, 2) turbine positions; Random draws one layout per world (reset only)."""
        if self._fixed_layout is not None:
            return np.broadcast_to(self._fixed_layout, (count, self.agents, 2)).copy()
        return np.stack([self._layout(rng) for _ in range(count)]) if count else np.zeros((0, self.agents, 2))

    def _headings(self, rng: np.random.Generator, count: int) -> np.ndarray:
        """(count, A) start headings: one draw per world, each turbine within the spread around it."""
        shared = rng.uniform(-np.pi, np.pi, (count, 1))
        half = np.radians(self.params.initial_heading_spread_deg) / 2.0
        return wrap_angle(shared + rng.uniform(-half, half, (count, self.agents)))

    def reset(self, rng: np.random.Generator, batch: int) -> WindFarmState:
        positions = self._layouts(rng, batch)
        heading = self._headings(rng, batch)
        wind = wind_reset(rng, batch, self.wind_spec)
        wind_here, probe = probe_wind(wind, positions, self.wind_spec)
        return WindFarmState(positions=positions, heading=heading, performance=np.zeros((batch, self.agents)),
                             local_wind=wind_here, wind=wind, wind_probe=probe)

    def reset_where(self, state: WindFarmState, mask: np.ndarray, rng: np.random.Generator) -> WindFarmState:
        """New episodes where ``mask`` (B,): P restarts at 0; the turbines and the wind go on where they were
        (``episodes_continue``) or are drawn afresh."""
        performance = state.performance.copy()
        performance[mask] = 0.0
        if self.params.episodes_continue:
            return evolve(state, performance=performance)
        count = int(np.count_nonzero(mask))
        positions, heading = state.positions.copy(), state.heading.copy()
        positions[mask] = self._layouts(rng, count)
        heading[mask] = self._headings(rng, count)
        wind = wind_reset_where(state.wind, mask, rng, self.wind_spec)
        wind_here, probe = probe_wind(wind, positions, self.wind_spec)
        return WindFarmState(positions=positions, heading=heading, performance=performance,
                             local_wind=wind_here, wind=wind, wind_probe=probe)

    def step(self, state: WindFarmState, actions: np.ndarray, rng: np.random.Generator) -> tuple[WindFarmState, StepOutcome]:
        """actions (B, A) ints in {0, 1, 2}: rotate, move the wind, then update each turbine's performance."""
        heading = wrap_angle(state.heading + self._turn_by_action[actions])
        wind = wind_step(state.wind, rng, self.wind_spec)
        wind_here, probe = probe_wind(wind, state.positions, self.wind_spec, state.wind_probe)
        force = wind_force(alignment(heading, wind_here), self._threshold, self._threshold_span)
        performance = next_performance(state.performance, force, self._acceleration, self._drag)
        new = assemble(WindFarmState, positions=state.positions, heading=heading, performance=performance,
                       local_wind=wind_here, wind=wind, wind_probe=probe)
        return new, StepOutcome(np.zeros(heading.shape, bool), {})

    def observe(self, state: WindFarmState) -> np.ndarray:
        """(B, A, 6) float32: position / half extent (2), heading (cos, sin), local wind (cos, sin)."""
        out = np.empty(state.heading.shape + (6,), np.float32)
        out[..., 0:2] = clamp(state.positions / self._half_extent, _MINUS_ONE, _ONE)
        np.cos(state.heading, out=out[..., 2])
        np.sin(state.heading, out=out[..., 3])
        np.cos(state.local_wind, out=out[..., 4])
        np.sin(state.local_wind, out=out[..., 5])
        return out

    state_components = state_components  # the global state's world facts: see global_state.py
    world_state = world_state

    def render(self, state: WindFarmState, index: int) -> np.ndarray:
        from .render import draw_wind_farm

        return draw_wind_farm(state, index, self.params, self.wind_spec)
