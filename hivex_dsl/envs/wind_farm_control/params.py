"""Physical constants of Wind Farm Control; every one bounded, documented and overridable.

[paper] values come from the paper's reward equations, [orig] from the original release's shared
Wind component, [ours] are this project's defaults where neither says (ENVIRONMENTS.md).
"""

from __future__ import annotations

from pydantic import Field

from ...sim.procgen.wind import WindParams


class WindFarmControlParams(WindParams):
    farm_half_extent_m: float = Field(600.0, ge=50.0, le=10_000.0, description=(
        "[ours] Half the side of the square farm area in metres; turbine positions are normalised by it."))
    turbine_spacing_m: float = Field(70.0, ge=5.0, le=2_000.0, description=(
        "[ours] Minimum distance between turbines; the layout patterns are built from it."))
    rotation_speed_deg: float = Field(2.0, gt=0.0, le=45.0, description=(
        "[ours] Degrees a turbine turns per rotate action; faster than the wind's worst drift so tracking is possible."))
    motor_acceleration: float = Field(0.1, ge=0.0, le=1.0, description="[paper] a_turbine: performance gain per step at full wind force W = 1.")
    drag: float = Field(0.1, ge=0.0, le=1.0, description="[paper] Drag: fraction of the performance P lost per step (d = -drag * P).")
    alignment_threshold: float = Field(0.5, ge=0.0, lt=1.0, description=(
        "[paper] Alignment below which the wind force W is 0; W rises linearly to 1 at perfect alignment."))
