"""The physical constants of Bee Foraging; every one bounded, documented and overridable under ``params:``."""

from __future__ import annotations

from pydantic import Field

from hivex_dsl.lang.spec.common import StrictModel


class BeeForagingParams(StrictModel):
    meadow_half_extent_m: float = Field(50.0, ge=10.0, le=1_000.0, description=(
        "[ours] Half the side of the square meadow in metres; the hive is at its centre."))
    flowers: int = Field(12, ge=1, le=64, description="[ours] Flowers in the meadow, placed anew every episode.")
    nectar_per_flower: float = Field(1.0, gt=0.0, le=10.0, description="[ours] Nectar a flower holds at the start.")
    speed_m: float = Field(2.0, gt=0.0, le=20.0, description="[ours] Metres a bee flies per step.")
    reach_m: float = Field(3.0, gt=0.0, le=50.0, description=(
        "[ours] How near a bee must be to a flower to gather from it, or to the hive to unload."))
    gather_rate: float = Field(0.1, gt=0.0, le=10.0, description="[ours] Most nectar a bee gathers in one step.")
    capacity: float = Field(0.5, gt=0.0, le=10.0, description="[ours] Most nectar a bee carries.")
