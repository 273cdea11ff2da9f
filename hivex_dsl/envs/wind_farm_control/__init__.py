"""Wind Farm Control: turbines turn into (or across) a shifting, spatially varying wind."""

from __future__ import annotations

from ...compiler.registry import EnvironmentEntry, register
from ...lang.spec.catalogue import PAPER_ENVIRONMENTS
from ...sim.procgen.layouts import layout_problem
from .global_state import state_facts
from .layouts_preset import load_layout_preset
from .params import WindFarmControlParams
from .scripted import scripted_policy
from .simulator import WindFarmSimulator
from .statistics import STATISTICS
from .terms import TERMS

PRESET = load_layout_preset()


def layout_fits(compiled) -> list[tuple[tuple, str]]:
    """Every pattern must place the scenario's turbines inside the farm at the configured spacing."""
    p = compiled.params
    problem = layout_problem(compiled.level, compiled.agents, p.turbine_spacing_m, p.farm_half_extent_m)
    return [(("agents",), problem)] if problem else []


ENTRY = register(EnvironmentEntry(
    info=PAPER_ENVIRONMENTS["wind_farm_control"],
    params_model=WindFarmControlParams,
    terms=TERMS,
    statistics=STATISTICS,
    state_facts=state_facts,
    make_simulator=WindFarmSimulator,
    scripted_policy=scripted_policy,
    level_names=tuple(p.name for p in PRESET.patterns),
    level_titles=tuple(p.title for p in PRESET.patterns),
    checks=(layout_fits,),
    notes=(
        "The paper's reward equation names the angle theta but thresholds it at 0.5: we read theta as the "
        "alignment of the rotor with the upwind direction, 1 - angle/180 degrees, as ENVIRONMENTS.md states.",
        "Generate Energy clamps the performance P for the reward; P itself evolves unclamped, as the paper's "
        "update equation is written (with the paper's constants it stays in [0, 1] anyway).",
        "The rotation speed, the main wind's ease rate, the noise field's drift, that a farm's turbines start "
        "facing one way and that an episode continues the world are read from the original's logged runs "
        "([records]; the reward table's notes give the evidence); the layout geometries are this project's own. "
        "Each is a bounded parameter.",
        "Task indices are the configs' 0-based `task:` values (0 Generate Energy, 1 Avoid Damage); the paper's "
        "reward-scale table numbers the same columns 1 and 2.",
    ),
))
