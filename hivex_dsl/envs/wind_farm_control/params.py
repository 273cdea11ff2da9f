"""Physical constants of Wind Farm Control; every one bounded, documented and overridable.

[paper] values come from the paper's reward equations, [orig] from the original release's shared
Wind component, [records] from the original's own logged training and test runs (the notes of
rewards/wind_farm_control.yaml give the reading), [ours] are this project's defaults where none says
(ENVIRONMENTS.md).
"""

from __future__ import annotations

from pydantic import Field

from ...sim.procgen.wind import WindParams


class WindFarmControlParams(WindParams):
    farm_half_extent_m: float = Field(600.0, ge=50.0, le=10_000.0, description=(
        "[ours] Half the side of the square farm area in metres; turbine positions are normalised by it."))
    turbine_spacing_m: float = Field(70.0, ge=5.0, le=2_000.0, description=(
        "[ours] Minimum distance between turbines; the layout patterns are built from it."))
    rotation_speed_deg: float = Field(0.1, gt=0.0, le=45.0, description=(
        "[records] Degrees a turbine turns per rotate action. Random play moves a heading by r sqrt(2n/3) over n "
        "steps, 22 degrees over the original's first 15 episodes at 0.1, which keeps a farm's turbines as alike "
        "as the original's logged runs show; a tracking policy still turns 500 degrees an episode."))
    wind_ease_rate: float = Field(0.0005, gt=0.0, le=1.0, description=(
        "[records] Fraction of the remaining angle to the target that the main wind covers per step: a 60 degree "
        "shift takes about 5,000 steps, one an episode, as the original's near-random returns, correlated from "
        "one episode to the next, show."))
    wind_drift_m: float = Field(0.25, ge=0.0, le=100.0, description=(
        "[records] Metres the wind noise field moves with the main wind per step: slow enough for a turbine "
        "turning 0.1 degrees a step to follow its local wind within the original's plateau (about 4,600). The "
        "release's Wind holds its field still while training (0 here; the reward table's notes)."))
    motor_acceleration: float = Field(0.1, ge=0.0, le=1.0, description="[paper] a_turbine: performance gain per step at full wind force W = 1.")
    drag: float = Field(0.1, ge=0.0, le=1.0, description="[paper] Drag: fraction of the performance P lost per step (d = -drag * P).")
    initial_heading_spread_deg: float = Field(0.0, ge=0.0, le=360.0, description=(
        "[records] The turbines of a farm start an episode within this spread of one heading drawn per world "
        "(0: all face the same way; 360: each draws its own). The original's near-random runs earn farm means "
        "that swing by about 750 from episode to episode while one turbine stays within about 215 of its farm: "
        "the turbines of a farm start alike (rewards/wind_farm_control.yaml)."))
    episodes_continue: int = Field(1, ge=0, le=1, description=(
        "[records] 1: a new episode continues the world, the turbines keep their headings and the wind its "
        "course, and only the performance P restarts at 0; 0: both are drawn afresh. The original's test "
        "episodes vary by only about 40 around 4,600 although a turbine turns too slowly to face a fresh "
        "random wind within a few steps (rewards/wind_farm_control.yaml)."))
    alignment_threshold: float = Field(0.5, ge=0.0, lt=1.0, description=(
        "[paper] Alignment below which the wind force W is 0; W rises linearly to 1 at perfect alignment."))
