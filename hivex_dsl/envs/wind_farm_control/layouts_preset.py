"""The layout pattern preset (generators/wind_farm_control_layouts.yaml), checked against the code."""

from __future__ import annotations

from typing import Literal

from pydantic import Field

from ...lang.spec.common import SCHEMA_VERSION, StrictModel
from ...sim.procgen.layouts import PATTERN_NAMES
from ...sim.procgen.presets import load_preset


PRESET_FILE = "wind_farm_control_layouts.yaml"


class Pattern(StrictModel):
    index: int = Field(ge=0, le=8, description="The paper's pattern index.")
    name: str = Field(max_length=40, description="Name accepted by `pattern:` in scenarios.")
    title: str = Field(max_length=40, description="The paper's name.")
    description: str = Field(max_length=200, description="The geometry in one line.")


class LayoutPreset(StrictModel):
    hivex: Literal[SCHEMA_VERSION]
    generator: Literal["wind_farm_control_layouts"]
    patterns: list[Pattern] = Field(min_length=9, max_length=9)


def load_layout_preset() -> LayoutPreset:
    preset = load_preset(PRESET_FILE, LayoutPreset)
    names = tuple(p.name for p in preset.patterns)
    if names != PATTERN_NAMES or [p.index for p in preset.patterns] != list(range(9)):
        raise ValueError(f"generators/{PRESET_FILE}: patterns must be {PATTERN_NAMES} in index order, found {names}")
    return preset
