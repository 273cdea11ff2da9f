"""The HIVEX wind model, batched over worlds and steppable over time.

From the original release's shared Wind component: a main direction eases toward a target;
once within a tolerance of it, the target turns by +/- a fixed shift (random sign). The wind at
a point is the main direction rotated by a smooth noise field value mapped to +/- a maximum
deviation; the noise field drifts with the wind over time (the release keeps it still while training).

Two easing laws: ``ease`` moves the main direction by a constant share of the remaining angle every
step; ``original`` is the release's Wind.CalcMainWind, which runs once a rendered frame (every
``frame_steps`` academy steps under mlagents-learn's defaults) and lerps the unnormalised main vector
toward the target by a fraction that grows by ``lerp_speed`` x the frame's seconds and restarts at 0 on
every retarget: slow at first, then faster.

Angles are radians, directions are where the wind blows *to*, lengths are metres.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any, ClassVar

import numpy as np
from pydantic import Field

from ...base import portable
from ...base.numeric import constant
from ...lang.spec.common import AS_DEFAULT, StrictModel
from ..batching import assemble, pad_by_world, replace_worlds, select_worlds
from .noise import blend_corners, corner_gradients, draw_lattice, octave_frequencies, sum_octaves

TWO_PI = 2.0 * np.pi
FIXED_STEP_S = 0.02  # [orig] the release's TimeManager fixed timestep: game seconds an academy step
_PI, _TWO_PI = constant(np.pi), constant(TWO_PI)


@dataclass(frozen=True)
class WindSpec:
    """Constants of the wind model (the environments expose them as bounded params)."""

    ease_rate: float  # fraction of the remaining angle to the target covered per step
    target_shift_deg: float  # how far the target turns once reached
    retarget_tolerance_deg: float  # "reached" means within this angle
    deviation_max_deg: float  # local deviation at noise value +/-1
    noise_scale_m: float  # size of one noise lattice cell
    noise_octaves: int
    drift_m: float  # distance the noise field moves with the wind per step
    law: str = "ease"  # "ease" (a constant share a step) or "original" (the release's growing lerp a frame)
    lerp_speed: float = 0.001  # original: the lerp fraction's growth per second of game time
    frame_steps: float = 50.0 / 3.0  # original: academy steps per rendered frame
    operands: "_WindOperands" = field(init=False, repr=False, compare=False)

    def __post_init__(self):
        object.__setattr__(self, "operands", _WindOperands(self))


class _WindOperands:
    """The spec's numbers as 0-d float64 arrays, the cheap operands of a step (see :mod:`hivex_dsl.base.numeric`)."""

    def __init__(self, spec: WindSpec):
        self.ease_rate = constant(spec.ease_rate)
        self.frame_steps = float(spec.frame_steps)
        self.lerp_growth = spec.lerp_speed * spec.frame_steps * FIXED_STEP_S  # fraction gained a frame
        self.tolerance = constant(math.radians(spec.retarget_tolerance_deg))
        self.shift = math.radians(spec.target_shift_deg)
        self.deviation = constant(math.radians(spec.deviation_max_deg))
        self.noise_scale = constant(spec.noise_scale_m)
        self.drift = constant(spec.drift_m)


class WindParams(StrictModel):
    """The wind fields of an environment's params (Wind Farm Control, Aerial Wildfire Suppression)."""

    wind_original_law: int = Field(0, ge=0, le=1, description=(
        "How the main wind eases toward its target. 0 [ours]: by wind_ease_rate of the remaining angle every "
        "step. 1 [orig]: the release's Wind.CalcMainWind, once a rendered frame (wind_frame_steps), a lerp of the "
        "main vector toward the target by a fraction that grows by wind_lerp_speed a second of game time and "
        "restarts at 0 on every retarget."))
    wind_ease_rate: float = Field(0.01, gt=0.0, le=1.0, description=(
        "[ours] Under wind_original_law 0, the fraction of the remaining angle to the target that the main wind "
        "covers per step (0.01: a 60 degree shift takes about 250 steps)."))
    wind_lerp_speed: float = Field(0.001, gt=0.0, le=1.0, description=(
        "[orig] Under wind_original_law 1, the lerp fraction's growth per second of game time (Wind.speed; the AWS "
        "scene of the release sets 0.001: a 60 degree shift every 1,940 steps)."))
    wind_frame_steps: float = Field(50.0 / 3.0, ge=1.0, le=1_000.0, description=(
        "[orig] Under wind_original_law 1, academy steps per rendered frame: mlagents-learn's time scale 20 and "
        "capture frame rate 60 make a frame 1/3 s of game time, 16.7 fixed steps of 0.02 s."))
    wind_target_shift_deg: float = Field(60.0, ge=0.0, le=180.0, description="[orig] How far the wind target turns once it is reached.")
    wind_retarget_tolerance_deg: float = Field(5.0, gt=0.0, le=90.0, description="[orig] The target counts as reached within this angle.")
    wind_deviation_max_deg: float = Field(90.0, ge=0.0, le=180.0, description="[orig] Local wind deviation at noise value +/-1.")
    wind_noise_scale_m: float = Field(400.0, ge=10.0, le=100_000.0, description="[ours] Size of one cell of the wind noise lattice in metres.")
    wind_noise_octaves: int = Field(2, ge=1, le=8, description="[ours] Octaves of the wind noise field.")
    wind_drift_m: float = Field(1.0, ge=0.0, le=100.0, description="[ours] Metres the wind noise field moves with the main wind per step.")

    ADDED_FIELDS: ClassVar[dict[str, Any]] = dict.fromkeys(
        ("wind_original_law", "wind_lerp_speed", "wind_frame_steps"), AS_DEFAULT)

    def wind_spec(self) -> WindSpec:
        return WindSpec(ease_rate=self.wind_ease_rate, target_shift_deg=self.wind_target_shift_deg,
                        retarget_tolerance_deg=self.wind_retarget_tolerance_deg,
                        deviation_max_deg=self.wind_deviation_max_deg, noise_scale_m=self.wind_noise_scale_m,
                        noise_octaves=self.wind_noise_octaves, drift_m=self.wind_drift_m,
                        law="original" if self.wind_original_law else "ease", lerp_speed=self.wind_lerp_speed,
                        frame_steps=self.wind_frame_steps)


@dataclass(frozen=True)
class WindState:
    main: np.ndarray  # (B,) main direction
    target: np.ndarray  # (B,) direction the main one eases toward
    drift: np.ndarray  # (B, 2) displacement of the noise field since reset
    perm: np.ndarray  # (B, 2P) noise permutation per world
    grads: np.ndarray  # (B, P, 2) noise gradients per world
    vector: np.ndarray  # (B, 2) the main wind as the original lerps it (unnormalised); law original only
    fraction: np.ndarray  # (B,) the original's growing lerp fraction since the last retarget
    clock: np.ndarray  # (B,) academy steps since reset (the original moves the wind on frames)


def wrap_angle(angle: np.ndarray) -> np.ndarray:
    """Angles mapped into [-pi, pi)."""
    angle = np.asarray(angle)
    if angle.dtype.type is np.float64:  # 0-d float64 operands: the same result, cheaper (see hivex_dsl.base.numeric)
        return (angle + _PI) % _TWO_PI - _PI
    return (angle + np.pi) % TWO_PI - np.pi


def wind_reset(rng: np.random.Generator, batch: int, spec: WindSpec) -> WindState:
    """Fresh wind for ``batch`` worlds: random main direction, target one shift away."""
    main = rng.uniform(0.0, TWO_PI, batch)
    sign = np.where(rng.random(batch) < 0.5, -1.0, 1.0)
    perm, grads = draw_lattice(rng, batch)
    return WindState(main=main, target=wrap_angle(main + sign * np.radians(spec.target_shift_deg)),
                     drift=np.zeros((batch, 2)), perm=perm, grads=grads,
                     vector=np.stack([np.cos(main), np.sin(main)], axis=1), fraction=np.zeros(batch),
                     clock=np.zeros(batch))


def wind_worlds(state: WindState, index: Any) -> WindState:
    """The wind of the worlds selected by ``index`` (a slice, mask or index array on the batch axis)."""
    return select_worlds(state, index)


def wind_reset_where(state: WindState, mask: np.ndarray, rng: np.random.Generator, spec: WindSpec) -> WindState:
    """Replace the wind of the worlds where ``mask`` (B,) is true by fresh draws."""
    return replace_worlds(state, mask, wind_reset(rng, int(np.count_nonzero(mask)), spec))


def wind_step(state: WindState, rng: np.random.Generator, spec: WindSpec) -> WindState:
    """Advance every world's wind by one step (one uniform draw per world, always)."""
    constants = spec.operands
    draws = rng.random(state.main.shape[0])
    if spec.law == "original":
        main, target, vector, fraction = _original_frame(state, draws, constants)
    else:
        main, target = _ease(state, draws, constants)
        vector, fraction = state.vector, state.fraction
    heading = np.empty(state.drift.shape)
    np.cos(main, out=heading[:, 0])
    np.sin(main, out=heading[:, 1])
    drift = state.drift + constants.drift * heading
    return assemble(WindState, main=main, target=target, drift=drift, perm=state.perm, grads=state.grads,
                    vector=vector, fraction=fraction, clock=state.clock + 1.0)


def _retarget(target: np.ndarray, reached: np.ndarray, draws: np.ndarray, constants: _WindOperands) -> np.ndarray:
    """(B,) targets turned by +/- the shift (sign by ``draws`` (B,)) where ``reached`` (B,)."""
    if not np.count_nonzero(reached):  # a target is reached once every few hundred steps
        return target
    signed_shift = np.where(draws < 0.5, -constants.shift, constants.shift)
    return np.where(reached, wrap_angle(target + signed_shift), target)


def _ease(state: WindState, draws: np.ndarray, constants: _WindOperands) -> tuple[np.ndarray, np.ndarray]:
    """Law ease: the main direction covers a constant share of the remaining angle; retarget once within the
    tolerance. -> main (B,), target (B,)."""
    main = wrap_angle(state.main + constants.ease_rate * wrap_angle(state.target - state.main))
    reached = np.abs(wrap_angle(state.target - main)) < constants.tolerance
    return main, _retarget(state.target, reached, draws, constants)


def frame_ends(clock, frame_steps):
    """Whether the step from academy step ``clock`` (a number or an array) ends a rendered frame, one every
    ``frame_steps`` academy steps: when the release's Update methods run (the wind's CalcMainWind, Aerial Wildfire
    Suppression's terrain cast)."""
    return np.floor((clock + 1.0) / frame_steps) > np.floor(clock / frame_steps)


def _original_frame(state: WindState, draws: np.ndarray, constants: _WindOperands):
    """Law original (Wind.CalcMainWind), on the worlds whose step ends a frame: retarget if the main vector is
    within the tolerance of the target (the fraction restarts at 0), grow the fraction, and lerp the
    unnormalised main vector toward the target's unit vector by it (Unity's Lerp clamps it at 1).
    -> main (B,), target (B,), vector (B, 2), fraction (B,)."""
    frame = frame_ends(state.clock, constants.frame_steps)
    if not np.count_nonzero(frame):
        return state.main, state.target, state.vector, state.fraction
    gap = np.abs(wrap_angle(state.target - state.main))
    reached = frame & (gap < constants.tolerance)
    target = _retarget(state.target, reached, draws, constants)
    fraction = np.where(reached, 0.0, state.fraction) + np.where(frame, constants.lerp_growth, 0.0)
    goal = np.stack([np.cos(target), np.sin(target)], axis=1)
    vector = state.vector + np.where(frame, np.minimum(fraction, 1.0), 0.0)[:, None] * (goal - state.vector)
    return portable.arctan2(vector[:, 1], vector[:, 0]), target, vector, fraction


@dataclass(frozen=True)
class WindProbe:
    """The noise lattice cells around a set of points and their corner gradients.

    The field drifts about a metre per step against lattice cells of hundreds of metres, so points
    stay in their cells for hundreds of steps; a probe lets :func:`probe_wind` skip the gradient
    lookups until one of them moves on. It is only reused for the very lattice arrays it was
    built from (``perm``, by identity), so a world's new wind after a reset cannot meet a stale probe.
    """

    perm: np.ndarray  # the WindState.perm it was built from
    lower: np.ndarray  # (2, B, N, octaves) x and y of the cells' lower-left corners in lattice units
    gx: np.ndarray  # (4, B, N, octaves) gradients at the cells' corners, x component
    gy: np.ndarray  # (4, B, N, octaves)

    def fits(self, perm: np.ndarray, lower: np.ndarray) -> bool:
        return self.perm is perm and self.lower.shape == lower.shape and not np.count_nonzero(self.lower != lower)


def probe_wind(state: WindState, points: np.ndarray, spec: WindSpec,
               probe: WindProbe | None = None) -> tuple[np.ndarray, WindProbe]:
    """Wind direction at ``points`` (B, N, 2) metres -> ((B, N) radians, the probe to pass next time).

    Identical to :func:`local_wind`; ``probe`` (from the previous call for the same points, or None)
    only saves the gradient lookups while every point stays in its lattice cells.
    """
    constants = spec.operands
    moved = (points - state.drift[:, None, :]) / constants.noise_scale
    frequencies = octave_frequencies(spec.noise_octaves, 2.0)[:, 0]
    # (2, B, N, octaves), C-contiguous: a product keeps its operand's transposed layout, which slows every op after
    octave_coords = np.multiply(moved.transpose(2, 0, 1)[..., None], frequencies, order="C")
    lower = np.floor(octave_coords)
    if probe is None or not probe.fits(state.perm, lower):
        probe = WindProbe(state.perm, lower, *corner_gradients(state.perm, state.grads, lower))
    noise = sum_octaves(blend_corners(probe.gx, probe.gy, octave_coords - lower), 0.5)
    return wrap_angle(state.main[:, None] + constants.deviation * noise), probe


def local_wind(state: WindState, points: np.ndarray, spec: WindSpec) -> np.ndarray:
    """Wind direction at ``points`` (B, N, 2) metres -> (B, N) radians."""
    return probe_wind(state, points, spec)[0]


def wind_reader(state: WindState, spec: WindSpec, half_extent_m: float, cell_m: float):
    """The fire engine's winds callback (hivex_dsl.sim.fire.Winds): the :func:`local_wind` (N,) radians at forest
    cells (world, row, col), each (N,) int, whose centres lie at ((col + 0.5) cell_m - half_extent_m,
    (row + 0.5) cell_m - half_extent_m) metres; every world's cells are asked in one padded call."""

    def read(world: np.ndarray, row: np.ndarray, col: np.ndarray) -> np.ndarray:
        if world.size == 0:
            return np.zeros(0)
        order = np.argsort(world, kind="stable")
        owner = world[order]
        slot, width = pad_by_world(owner, len(state.main))
        points = np.zeros((len(state.main), width, 2))
        points[owner, slot, 0] = (col[order] + 0.5) * cell_m - half_extent_m
        points[owner, slot, 1] = (row[order] + 0.5) * cell_m - half_extent_m
        winds = np.empty(len(world))
        winds[order] = local_wind(state, points, spec)[owner, slot]
        return winds

    return read
