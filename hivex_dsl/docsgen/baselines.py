"""The baselines page: every environment's main task, this toolkit's trained PPO on the test seeds beside the
paper's, from the data committed under ``benchmarks/baselines/`` (no torch needed to generate it)."""

from __future__ import annotations

import json
import statistics
from pathlib import Path
from typing import Any

from ..compiler import registry
from ..evaluation.original.compare import seed_words
from .curves import budget_source

BASELINES_DIR = Path("benchmarks") / "baselines"
PAGE = "baselines.md"
# Throughput targets (agent-steps/s, end to end): on one 2-core CPU machine per environment in exact arithmetic
# and in the opt-in approximate precision, and on one GPU (an H100) for every environment.
THROUGHPUT_TARGETS = {"wind_farm_control": 60_000, "ocean_plastic_collection": 450,
                      "drone_based_reforestation": 1_200, "aerial_wildfire_suppression": 3_500}
APPROXIMATE_THROUGHPUT_TARGETS = {"ocean_plastic_collection": 600}
GPU_THROUGHPUT_TARGET = 50_000
THROUGHPUT_FILE = Path("results") / "train_throughput.json"  # beside baselines/, under benchmarks/
COMPUTE_BOUND_FILE = Path("results") / "compute_bound.json"  # benchmarks/compute_bound.py -o
GRIDS = "grids"  # benchmarks/baselines/grids/<environment>.json: a trained sweep (train.baselines.record_grid)


def baselines_dir(docs_dir: Path) -> Path:
    """``benchmarks/baselines`` of the checkout holding ``docs_dir``."""
    return Path(docs_dir).resolve().parent / BASELINES_DIR


def _number(value: float) -> str:
    return f"{value:,.2f}"


def _spread(value: dict[str, float] | None) -> str:
    return "-" if not value else f"{_number(value['mean'])} ± {_number(value['std'])}"


def statistic_cell(value: dict[str, float]) -> str:
    """A recorded statistic as it compares with the published one: a running mean's pooled form first (the
    original's summary point, see hivex_dsl.sim.statistics), its per-episode mean ± std beside it."""
    if "pooled" not in value:
        return _spread(value)
    return f"{_number(value['pooled'])} pooled (per episode {_spread(value)})"


def _row(env_id: str, data: dict[str, Any] | None) -> dict[str, Any]:
    scenario = f"scenarios/{env_id}/main.yaml"
    run = f"runs/{env_id}-main"
    row: dict[str, Any] = {
        "environment": env_id, "scenario": scenario,
        "commands": [f"hivex train {scenario} -o {run}",
                     f"python benchmarks/record_baseline.py {run} {scenario}"],
        "trained": data is not None,
    }
    if data is None:
        return row
    published = data["published"]["return"] if data["published"] else None
    test = data["test"]["return"]
    row |= {
        "ours": _spread(test), "published": _spread(published), "random": _spread(data["random"]),
        "scripted": _spread(data["scripted"]), "steps": f"{data['agent_steps']:,}",
        "paper_steps": f"{data['hyperparameters'].get('max_steps', 0):,}: "
                       + budget_source(env_id, data["hyperparameters"].get("max_steps", 0)),
        "precision": data["hyperparameters"].get("precision", "exact"),
        "wall": f"{data['wall_s'] / 60:.1f} min" + "".join(f" (resumed at {n:,})" for n in data.get("resumed_at", [])),
        "machine": data["machine"], "seed": data["seed"],
        "test_seed": data["test"]["seed"], "episodes": data["test"]["episodes"], "actions": data["test"]["actions"],
        "verdict": record_verdict(data, published),
        "image": f"images/baselines/{env_id}.png", "note": data.get("note", ""), "reached": _reached(data),
        "commands": [data["command"]] if data.get("command") else row["commands"],
        "seeds": _seeds(data),
        "statistics": _episode_length_rows(data["test"]) + [
            {"name": name, "ours": statistic_cell(value),
             "published": _spread(_published_statistic(data["published"], name))}
            for name, value in data["test"]["statistics"].items()],
    }
    return row


def _episode_length_rows(test: dict[str, Any]) -> list[dict[str, str]]:
    """The test Episode Length (decisions less one, as ML-Agents logs it) beside the original's test average, which
    the paper did not publish; none for a record made before `hivex evaluate` reported it."""
    if "episode_length" not in test:
        return []
    original = test.get("original_episode_length")
    theirs = "-" if original is None else f"{_number(original)} (the original's test average, unpublished)"
    return [{"name": "Episode Length", "ours": _spread(test["episode_length"]), "published": theirs}]


def pooled_return(data: dict[str, Any]) -> dict[str, float]:
    """Mean and std of the per-agent test return over every recorded seed's test episodes taken together.

    Every seed is tested on the same episodes, so each seed weighs the same: the pooled variance is the mean of
    the seeds' variances plus the variance of their means.
    """
    returns = [data["test"]["return"]] + [seed["return"] for seed in data.get("other_seeds", [])]
    mean = statistics.fmean(r["mean"] for r in returns)
    variance = statistics.fmean(r["std"] ** 2 + (r["mean"] - mean) ** 2 for r in returns)
    return {"mean": mean, "std": variance ** 0.5}


def verdict(ours: dict[str, float], published: dict[str, float] | None) -> str:
    """"matches" when our mean return lies within one standard deviation of the published mean, else "above" or
    "below". The published standard deviation is taken over TensorBoard summary points, each a mean of whole
    episodes of all agents, so it is a spread of means: the verdict compares our mean (over many agent-episodes)
    with that band, a mean with means; our own ± is over single agent-episodes and never enters it."""
    if published is None:
        return "-"
    if abs(ours["mean"] - published["mean"]) <= published["std"]:
        return "matches (within the summary points' spread)"
    return "above" if ours["mean"] > published["mean"] else "below"


def record_verdict(data: dict[str, Any], published: dict[str, float] | None) -> str:
    """The verdict of a record's headline row: of its own return, the one the row shows beside it; where more seeds
    were recorded, then that of every seed's test episodes pooled, named with its mean, so a verdict never sits
    beside a number it is not about (DBR's seed 0 at 7.02 "above" a published 8.96: the three seeds pooled were)."""
    own = verdict(data["test"]["return"], published)
    seeds = 1 + len(data.get("other_seeds", []))
    if published is None or seeds == 1:
        return own
    pooled = pooled_return(data)
    return f"{own}; {seeds} seeds pooled ({pooled['mean']:,.2f}): {verdict(pooled, published)}"


def _seeds(data: dict[str, Any]) -> dict[str, Any] | None:
    """The record's seed and its ``other_seeds`` as rows, and the spread of their test means; None with one seed."""
    others = data.get("other_seeds", [])
    if not others:
        return None
    runs = [{"seed": data["seed"], "world_seed": data["hyperparameters"].get("world_seed"),
             "return": data["test"]["return"], "agent_steps": data["agent_steps"],
             "wall_s": data["wall_s"], "recorded": True}] + [{**e, "recorded": False} for e in others]
    means = [run["return"]["mean"] for run in runs]
    across = _spread({"mean": statistics.fmean(means), "std": statistics.pstdev(means)})
    return {"rows": [{"seed": seed_words(run).removeprefix("seed ") + (" (the record above)" if run["recorded"] else ""),
                      "ours": _spread(run["return"]), "steps": f"{run['agent_steps']:,}",
                      "wall": f"{run['wall_s'] / 60:.1f} min"} for run in runs],
            "count": len(runs), "across": across, "cell": f"{across} ({len(runs)} seeds)"}


def _reached(data: dict[str, Any]) -> str:
    """When the test-seed return first reached the published mean, in words ("-" without a published cell)."""
    if not data["published"]:
        return "-"
    hit = data.get("reached_published")
    if "reached_published" not in data:
        return "not measured"
    if hit is None:
        return "not within the run"
    wall = "" if hit["wall_s"] is None else f", {hit['wall_s'] / 60:.1f} min"
    return f"{hit['agent_steps']:,} agent-steps{wall}"


def _published_statistic(published: dict[str, Any] | None, name: str) -> dict[str, float] | None:
    if not published:
        return None
    return next((v for k, v in published["statistics"].items() if k.split("/", 1)[-1] == name), None)


def _load(directory: Path) -> dict[str, dict[str, Any]]:
    found = {}
    for path in sorted(Path(directory).glob("*.json")):
        found[path.stem] = json.loads(path.read_text(encoding="utf-8"))
    return found


def baselines_context(directory: Path, comparisons: list[dict[str, Any]] = ()) -> dict[str, Any]:
    """Rows of the baselines page, one per environment (trained or not); ``comparisons``
    (:func:`.curves.curve_comparisons`) set each record's curve beside the original's."""
    data = _load(directory)
    beside = {c["environment"]: c for c in comparisons}
    rows = [_row(env_id, data.get(env_id)) | {"curves": beside.get(env_id)} for env_id in registry.environments()]
    return {"rows": rows, "trained": [r for r in rows if r["trained"]], "left": [r for r in rows if not r["trained"]],
            **grid_context(Path(directory) / GRIDS), **hyperparameter_table(), **earlier_choices(data),
            **throughput_table(Path(directory).parent / THROUGHPUT_FILE)}


def grid_context(directory: Path) -> dict[str, Any]:
    """``grids`` (see :func:`grid_tables`) and ``grid_names``, their environments in words."""
    grids = grid_tables(directory)
    return {"grids": grids, "grid_names": ", ".join(f"`{g['environment']}`" for g in grids)}


def grid_tables(directory: Path) -> list[dict[str, Any]]:
    """One table per recorded grid: a row per point (task, level, ours, published, verdict) and the verdicts' counts."""
    tables = []
    for env_id, data in _load(directory).items():
        names = registry.get(env_id).level_names
        rows = []
        for point in data["points"]:
            published = point["published"]["return"] if point["published"] else None
            rows.append({"task": f"{point['task_index']} `{point['task']}`", "level": _level_label(point["level"], names),
                         "ours": _spread(point["return"]), "published": _spread(published),
                         "verdict": verdict(point["return"], published), "steps": f"{point['agent_steps']:,}",
                         "random": _spread(point["random"]), "scripted": _spread(point["scripted"]),
                         "wall": f"{point['wall_s'] / 60:.1f} min"})
        counts = {word: sum(r["verdict"].startswith(word) for r in rows) for word in ("matches", "above", "below")}
        tables.append({"environment": env_id, "sweep": data["sweep"], "rows": rows, "counts": counts,
                       "seed": data["points"][0]["seed"], "test_seed": data["test"]["seed"],
                       "episodes": data["test"]["episodes"], "actions": data["test"]["actions"],
                       "machine": data["machine"], "note": data.get("note", ""),
                       "steps": f"{data['hyperparameters']['max_steps']:,}", "untrained": data.get("untrained", []),
                       "budget": budget_source(env_id, data["hyperparameters"]["max_steps"]),
                       "commands": [data["command"]] if data.get("command") else []})
    return tables


def _level_label(level: int | None, names: tuple[str, ...]) -> str:
    """``3 circle`` for a named level (WFC's patterns), ``3`` for a numbered one, ``-`` where there are none (OPC)."""
    if level is None:
        return "-"
    return f"{level} {names[level]}" if names else str(level)


# The PPO choices where this toolkit first did otherwise than ML-Agents, each now ML-Agents' by default.
ML_AGENTS_CHOICES = ("max_grad_norm", "weight_init", "policy_loss", "continuous_actions", "curiosity_module",
                     "action_masks", "value_loss")


def earlier_choices(records: dict[str, dict[str, Any]]) -> dict[str, Any]:
    """Which committed records trained with an earlier choice than today's default, read from their hyperparameters.

    ``at_defaults`` and ``earlier_records``: abbreviations of the records that set none and of those that set
    some; ``earlier``: per choice key, the abbreviations of the records that set another value (a key a record
    lacks counts as what it meant for every policy then, ``checkpoint.ALWAYS_THEN``; one whose meaning depended on
    the policy, such as ``continuous_actions`` where every action is discrete, does not count).
    """
    from ..train.checkpoint import ALWAYS_THEN
    from ..train.config import PPOConfig

    defaults = {key: PPOConfig.model_fields[key].default for key in ML_AGENTS_CHOICES}
    earlier: dict[str, list[str]] = {key: [] for key in ML_AGENTS_CHOICES}
    at_defaults, earlier_records = [], []
    for env_id in [env_id for env_id in registry.environments() if env_id in records]:
        trained_with = ALWAYS_THEN | records[env_id]["hyperparameters"]
        name = registry.get(env_id).info.abbreviation
        differs = [key for key in ML_AGENTS_CHOICES if key in trained_with and trained_with[key] != defaults[key]]
        for key in differs:
            earlier[key].append(name)
        (earlier_records if differs else at_defaults).append(name)
    return {"at_defaults": at_defaults, "earlier": earlier, "earlier_records": earlier_records}


def throughput_table(path: Path) -> dict[str, Any]:
    """``throughput``: one table per machine (its words and its rows) from `benchmarks/train_throughput.py -o`
    (none if absent). Each row gains its rate and env share in words, the paper's budget in the wall time that
    each of the row's processes takes for it at that rate, and its target: the CPU one of its precision where the
    machine has 2 cores, the GPU one on a GPU."""
    if not path.is_file():
        return {"throughput": []}
    from ..train.config import PPOConfig, paper_defaults

    report = json.loads(path.read_text(encoding="utf-8"))
    bounds = _compute_bounds(path.parent.parent / COMPUTE_BOUND_FILE)
    tables: dict[str, list[dict[str, Any]]] = {}
    for row in report["rows"]:
        words = row.get("machine", report.get("machine", "an unnamed machine"))
        rate = row["agent_steps_per_s"]
        budget = paper_defaults(row["environment"]).get("max_steps", PPOConfig.model_fields["max_steps"].default)
        target = _throughput_target(row, words)
        bound = bounds.get((words, row["environment"], row["torch_threads"])) if row.get("device", "cpu") == "cpu" \
            and row.get("processes", 1) == 1 else None
        tables.setdefault(words, []).append({
            "bound": "-" if bound is None else f"{bound:,.0f} ({100 * rate / bound:.0f}%)",
            **row, "device": row.get("device", "cpu"), "processes": row.get("processes", 1),
            "precision": row.get("precision", "exact"),
            "rate": f"{rate:,.0f}", "env_share": f"{100 * row['env_share']:.0f}%",
            "budget": f"{budget / 1e6:g}M in {_duration(budget * row.get('processes', 1) / rate)}",
            "target": "-" if target is None else f"{target:,}",
            "met": "-" if target is None else ("yes" if rate >= target else "no"), "when": _measured(row)})
    return {"throughput": [{"machine": words, "rows": rows} for words, rows in tables.items()]}


def _measured(row: dict[str, Any]) -> str:
    """A row's day and the commit it measured (`2026-11-27, 8f2b241`), or "-" for rows from before both were kept."""
    if "measured" not in row:
        return "-"
    return row["measured"] + (f", `{row['commit']}`" if row.get("commit") else "")


def _compute_bounds(path: Path) -> dict[tuple[str, str, int], float]:
    """(machine, environment, threads) -> agent-steps/s at the attained FLOP rate (benchmarks/compute_bound.py)."""
    if not path.is_file():
        return {}
    rows = json.loads(path.read_text(encoding="utf-8"))["rows"]
    return {(row["machine"], row["environment"], row["threads"]): row["compute_bound_agent_steps_per_s"] for row in rows}


def _throughput_target(row: dict[str, Any], machine_words: str) -> int | None:
    if row.get("device", "cpu") != "cpu":
        return GPU_THROUGHPUT_TARGET
    targets = THROUGHPUT_TARGETS if row.get("precision", "exact") == "exact" else APPROXIMATE_THROUGHPUT_TARGETS
    return targets.get(row["environment"]) if ", 2 cores," in machine_words else None


def _duration(seconds: float) -> str:
    """``95`` -> ``2 min``, ``7300`` -> ``2.0 h``."""
    return f"{seconds / 3600:.1f} h" if seconds >= 5400 else f"{max(1, round(seconds / 60))} min"


def hyperparameter_table() -> dict[str, Any]:
    """The shipped hyperparameters (the configs that ran): ``keys`` (the union, in file order) and one row per
    environment that has them, each value followed by the paper appendix's where it differs (``8192 (appendix:
    10240)``); ``hp_defaulted``, the environments without, which train on PPOConfig's defaults."""
    from ..train.config import appendix, has_paper_hyperparameters, paper_defaults

    defaults = {env_id: paper_defaults(env_id) for env_id in registry.environments()
                if has_paper_hyperparameters(env_id)}
    appendices = {env_id: appendix(env_id) for env_id in defaults}
    keys = list(dict.fromkeys(key for values in defaults.values() for key in values))

    def shown(env_id: str, key: str) -> str:
        value = defaults[env_id].get(key, "-")
        return f"{value} (appendix: {appendices[env_id][key]})" if key in appendices[env_id] else str(value)

    return {"hp_keys": keys, "hp_rows": [{"environment": env_id, "values": [shown(env_id, k) for k in keys]}
                                         for env_id in defaults],
            "hp_defaulted": [env_id for env_id in registry.environments() if not has_paper_hyperparameters(env_id)],
            "appendix_differs": [{"environment": env_id, "names": sorted(values)}
                                 for env_id, values in appendices.items() if values]}


def baseline_images(directory: Path) -> dict[str, bytes]:
    """``images/baselines/<env>.png`` -> the committed learning-curve PNG's bytes."""
    return {f"images/baselines/{path.name}": path.read_bytes() for path in sorted(Path(directory).glob("*.png"))}
