"""Committed baselines: a trained run turned into small data (JSON) and a learning curve (PNG) under
``benchmarks/baselines/``, from which `hivex docs` generates docs/baselines.md.

``record_baseline`` evaluates the run's checkpoint on the test seeds, measures the random and the scripted
policy on the same seeds, and writes ``<environment>.json`` and ``<environment>.png``. Every intermediate
checkpoint the run kept is also evaluated on the test seeds (fewer episodes): that test-seed curve says
after how many agent-steps and how much wall time the policy first matched the published return.

``add_seed`` adds a run of the same scenario and hyperparameters but another training seed to a record
(``other_seeds``): its test-seed evaluation on the record's episodes. One seed can mislead where PPO finds a
strategy in some seeds and not in others; the page shows every recorded seed and their spread.

``record_grid`` turns a trained sweep (``hivex train SWEEP --eval-episodes N``) into ``grids/<environment>.json``:
every point's test-seed return and statistics beside the paper's published cell for its task and level, and its
training curve, which the fidelity page measures against the original's; :mod:`.grid_seeds` adds other training
seeds to its points, which re-recording the grid keeps while they trained what its points train.
"""

from __future__ import annotations

import hashlib
import json
from pathlib import Path
from typing import Any

from ..compiler import CompiledScenario, compile, compile_all
from ..evaluation.report import collect_returns
from .checkpoint import RESUMABLE_CHANGES, acting_interface, load_checkpoint, older_defaults
from .config import PPOConfig, TrainError
from .devices import machine
from .evaluate import evaluate, published_result
from .grid import point_dir
from .rundir import dumps, file_digest

# what another seed's run may differ in: its weights' and sampling's seed and its training worlds' (world_seed)
SEED_CHANGES = RESUMABLE_CHANGES | {"seed", "world_seed"}


LEVEL_POLICIES = ("random", "scripted")  # the trivial and the hand-written policy every record sets beside PPO


def level_of(compiled, policy: str, episodes: int) -> dict[str, float]:
    """The per-agent return (mean, std) of ``policy`` (one of :data:`LEVEL_POLICIES`) on the test seeds'
    first ``episodes`` episodes, the ones ``evaluate`` plays."""
    returns, _ = collect_returns(compiled, policy, episodes, "test")
    per_agent = returns.reshape(-1)
    return {"mean": float(per_agent.mean()), "std": float(per_agent.std())}


def test_curve(run_dir: Path, episodes: int) -> list[list[float]]:
    """[agent-steps, wall s, mean, std] of the test-seed return of every checkpoint under run_dir/checkpoints."""
    rows = []
    for path in sorted(Path(run_dir).glob("checkpoints/step_*.pt")):
        report = evaluate(path, split="test", episodes=episodes)
        ret = report["return"]
        rows.append([report["trained_agent_steps"], report["trained_wall_s"], round(ret["mean"], 4), round(ret["std"], 4)])
    return rows


def first_reaching(curve: list[list[float]], final: list[float], published: dict[str, Any] | None) -> dict | None:
    """The first test-curve point (or the final one) whose mean reaches the published mean; None if none does."""
    if not published:
        return None
    target = published["return"]["mean"]
    for steps, wall, mean, _ in [*curve, final]:
        if mean >= target:
            return {"agent_steps": steps, "wall_s": wall, "return": mean}
    return None


def curve_fields(run_dir: Path) -> dict[str, Any]:
    """A run's curve.json as a record keeps it: ``curve`` rows of (agent-steps, wall s, mean training return) and,
    where it has points, the episodes and every other panel beside them (Episode Length, the statistics:
    :func:`~hivex_dsl.evaluation.original.compare.record_panels`), which the fidelity page measures."""
    from ..evaluation.original.compare import from_points, record_panels

    points = read_json(Path(run_dir) / "curve.json", "curve")
    rows = [[point["agent_steps"], point["wall_s"], round(point["return"], 4)] for point in points]
    return {"curve": rows, **(record_panels(from_points(points)) if points else {})}


def record_baseline(run_dir: Path, scenario: str, out_dir: Path, episodes: int = 10,
                    command: str | None = None, note: str | None = None, curve_episodes: int = 3) -> dict[str, Any]:
    """Write ``out_dir/<environment>.json`` and ``.png`` for the run in ``run_dir`` trained on ``scenario``
    (the bundled path, e.g. ``scenarios/wind_farm_control/main.yaml``); -> the JSON's content. A ``command`` or
    ``note`` not given (None) is the record's already there of the same scenario, as in :func:`record_grid`."""
    run_dir, out_dir = Path(run_dir), Path(out_dir)
    _check_episodes(episodes)
    summary = read_json(run_dir / "summary.json", "summary")
    compiled = compile(scenario)
    _check_trained(run_dir, compiled, scenario)
    earlier = _earlier_words(out_dir / f"{compiled.environment}.json", scenario)
    command = earlier["command"] if command is None else command
    note = earlier["note"] if note is None else note
    report = evaluate(run_dir / "checkpoint.pt", split="test", episodes=episodes)
    data = {
        "environment": compiled.environment, "scenario": scenario, "task": compiled.task_name,
        "task_index": compiled.task_index, "level": compiled.level, "command": command, "note": note,
        "agent_steps": summary["agent_steps"], "wall_s": summary["wall_s"], "seed": summary["seed"],
        "resumed_at": summary.get("resumed_at", []), "machine": "; ".join(trained_on(summary)),
        "hyperparameters": read_json(run_dir / "config.json", "config")["hyperparameters"],
        "test": {k: report[k] for k in ("seed", "episodes", "agent_episodes", "actions", "return", "episode_length",
                                        "original_episode_length", "statistics")},
        "published": report["published"],
        **{policy: level_of(compiled, policy, episodes) for policy in LEVEL_POLICIES},
        **curve_fields(run_dir),
        "test_curve": test_curve(run_dir, curve_episodes), "test_curve_episodes": curve_episodes,
    }
    final = [summary["agent_steps"], summary["wall_s"], report["return"]["mean"], report["return"]["std"]]
    data["reached_published"] = first_reaching(data["test_curve"], final, report["published"])
    out_dir.mkdir(parents=True, exist_ok=True)
    (out_dir / f"{compiled.environment}.json").write_text(dumps(data, out_dir / f"{compiled.environment}.json", 1))
    from .plots import learning_curve

    learning_curve(data, out_dir / f"{compiled.environment}.png")
    return data


def _earlier_words(record: Path, scenario: str) -> dict[str, str]:
    """The command and note of the baseline record at ``record`` when it records ``scenario``; empty otherwise."""
    data = read_json(record, "baseline record") if record.is_file() else {}
    words = data if data.get("scenario") == scenario else {}
    return {"command": words.get("command", ""), "note": words.get("note", "")}


# what a run's JSON file holds at the top level, by its kind (in messages: "not a run's summary")
RUN_JSON = {"summary": (dict, "agent_steps"), "config": (dict, "hyperparameters"), "curve": (list, None),
            "grid record": (dict, "points"), "baseline record": (dict, "scenario")}


def read_json(path: Path, kind: str) -> Any:
    """The run's (or record's) JSON file ``path`` of ``kind`` (:data:`RUN_JSON`); a TrainError naming it where it is
    missing, unreadable (truncated, say) or not of that kind."""
    shape, key = RUN_JSON[kind]
    try:
        data = json.loads(Path(path).read_text(encoding="utf-8"))
    except FileNotFoundError:
        raise TrainError(f"no {kind} at {path}: is it a finished run's directory?") from None
    except (OSError, UnicodeDecodeError, ValueError) as exc:
        raise TrainError(f"{path} is not a {kind} hivex can read ({type(exc).__name__}: {exc}): a run killed while "
                         "writing it, or edited by hand?") from None
    if not isinstance(data, shape) or (key is not None and key not in data):
        raise TrainError(f"{path} is not a run's {kind}: expected a JSON {shape.__name__}"
                         f"{f' with {key!r}' if key else ''}")
    return data


def _check_episodes(episodes: int) -> None:
    if isinstance(episodes, bool) or not isinstance(episodes, int) or episodes < 1:
        raise TrainError(f"--episodes must be a positive number of test episodes, got {episodes!r}: a record of none "
                         "would hold no return")


def _check_trained(run_dir: Path, compiled: CompiledScenario, scenario: str) -> None:
    """The run in ``run_dir`` trained ``compiled`` (by its content, its fingerprint, not by its name)."""
    trained = load_checkpoint(run_dir / "checkpoint.pt")
    if trained["fingerprint"] != compiled.fingerprint:
        raise TrainError(f"{run_dir} trained scenario {trained['compiled'].name!r} (fingerprint {trained['fingerprint']}),"
                         f" not {scenario} (fingerprint {compiled.fingerprint}), whatever their names")


def add_seed(record: Path, run_dir: Path) -> dict[str, Any]:
    """Add (or replace) ``run_dir``'s test-seed evaluation in the baseline ``record`` (a ``<environment>.json``)
    as one of its ``other_seeds``; -> the record's new content, also written back, and its PNG redrawn.

    The run must have trained the record's scenario with the record's hyperparameters but for
    :data:`SEED_CHANGES`, on a training seed other than the record's own."""
    record, run_dir = Path(record), Path(run_dir)
    data = read_json(record, "baseline record")
    trained = load_checkpoint(run_dir / "checkpoint.pt")
    if trained["fingerprint"] != compile(data["scenario"]).fingerprint:
        raise TrainError(f"{run_dir} trained scenario {trained['compiled'].name!r}, which differs from the "
                         f"record's {data['scenario']}")
    check_other_seed(run_dir, trained["compiled"], data["hyperparameters"], data["seed"], record.name)
    report = evaluate(run_dir / "checkpoint.pt", split="test", episodes=data["test"]["episodes"])
    data["other_seeds"] = with_seed(data.get("other_seeds", []), seed_entry(run_dir, report))
    record.write_text(dumps(data, record, 1))
    from .plots import learning_curve

    learning_curve(data, record.with_suffix(".png"))
    return data


def check_other_seed(run_dir: Path, compiled: CompiledScenario, hyperparameters: dict[str, Any], seed: int,
                     of: str) -> None:
    """Refuse ``run_dir`` as another training seed of ``of`` (a record, or a grid record's point), which trained
    ``compiled`` with ``hyperparameters`` on ``seed``, unless its hyperparameters differ from those only in
    :data:`SEED_CHANGES` and its seed from ``seed``."""
    ran = read_json(run_dir / "config.json", "config")["hyperparameters"]
    # through the config model: a record made before a key existed holds what the key meant then
    recorded = PPOConfig(**older_defaults(hyperparameters, *acting_interface(compiled))).model_dump(mode="json")
    changed = sorted(k for k, v in ran.items() if k not in SEED_CHANGES and recorded.get(k) != v)
    if changed:
        listing = ", ".join(f"{k}: {recorded.get(k)!r} -> {ran[k]!r}" for k in changed)
        raise TrainError(f"{run_dir} is not another seed of {of}: its hyperparameters differ ({listing})")
    ran_seed = read_json(run_dir / "summary.json", "summary")["seed"]
    if ran_seed == seed:
        raise TrainError(f"{run_dir} trained on seed {ran_seed}, the record's own; give another seed's run")


def seed_entry(run_dir: Path, report: dict[str, Any]) -> dict[str, Any]:
    """One of a record's ``other_seeds``: the run in ``run_dir`` (its seeds, budget, machines and training curve)
    and its test-seed evaluation ``report``."""
    summary = read_json(run_dir / "summary.json", "summary")
    hyperparameters = read_json(run_dir / "config.json", "config")["hyperparameters"]
    return {"seed": summary["seed"], "world_seed": hyperparameters.get("world_seed"),
            "agent_steps": summary["agent_steps"], "wall_s": summary["wall_s"],
            "resumed_at": summary.get("resumed_at", []), "threads": hyperparameters["torch_threads"],
            "machines": trained_on(summary), "return": report["return"], "episode_length": report["episode_length"],
            "statistics": report["statistics"], **curve_fields(run_dir)}


def with_seed(entries: list[dict[str, Any]], entry: dict[str, Any]) -> list[dict[str, Any]]:
    """``entries`` (a record's ``other_seeds``) with ``entry`` added, replacing one of its seed, in seed order."""
    return sorted([*(e for e in entries if e["seed"] != entry["seed"]), entry], key=lambda e: e["seed"])


GRIDS = "grids"  # under the baselines folder: grids/<environment>.json


def record_grid(grid_dir: Path, sweep: str, out_dir: Path, episodes: int = 10, command: str | None = None,
                note: str | None = None, partial: bool = False, replace: bool = False) -> dict[str, Any]:
    """Write ``out_dir/grids/<environment>.json`` for the grid trained in ``grid_dir`` on ``sweep`` (the bundled
    path, e.g. ``scenarios/wind_farm_control/paper_suite.yaml``); -> the JSON's content.

    Every point must have finished training that sweep's point of the same index, all with one set of
    hyperparameters. Its test-seed evaluation is the ``evaluation.json`` the grid wrote when that holds
    ``episodes`` test episodes, and a fresh one otherwise; the random and the scripted policy play the same
    episodes of every point. A point not trained to its end in ``grid_dir`` keeps its row of the record already
    there (a grid trained a few points at a time, on machines that do not keep their runs), which must be of the
    same scenario (its fingerprint), hyperparameters and test episodes. With ``partial`` (a grid still training)
    the points in neither are listed by name under ``untrained`` instead of refused; at least one must be recorded.

    The record already there is of the same sweep when it is of the same content (:func:`sweep_fingerprint`), however
    the sweep's path is written; one of another sweep is refused, and replaced only with ``replace``. Each row names
    the machines its point trained on (:func:`trained_on`) and the record every one of them, since a run reproduces
    only on alike processors. A ``command`` or ``note`` not given (None) is the record's already there of the same
    sweep (someone wrote it by hand; re-recording must not drop it), and empty where there is none or with
    ``replace``."""
    grid_dir, out_dir = Path(grid_dir), Path(out_dir)
    _check_episodes(episodes)
    points = compile_all(sweep)
    run_dirs = [point_dir(grid_dir, index, point) for index, point in enumerate(points)]
    earlier = _recorded_rows(out_dir / GRIDS / f"{points[0].environment}.json", sweep, points, replace)
    fresh = [index for index, run_dir in enumerate(run_dirs)
             if trained_to_end(run_dir) or not (partial or points[index].name in earlier["rows"])]
    kept = [index for index in range(len(points)) if index not in fresh and points[index].name in earlier["rows"]]
    if not fresh and not kept:
        raise TrainError(f"{grid_dir} has no point of {sweep} trained to its end yet: nothing to record")
    untrained = [points[index].name for index in range(len(points)) if index not in fresh + kept]
    summaries = {index: finished_point(run_dirs[index], index, points[index], sweep) for index in fresh}
    configs = [read_json(run_dirs[index] / "config.json", "config")["hyperparameters"] for index in fresh]
    configs += [earlier["hyperparameters"]] if kept else []
    differing = sorted({k for c in configs for k in c if any(other.get(k) != c[k] for other in configs)})
    if differing:
        raise TrainError(f"the points of {grid_dir}{' and its earlier record' if kept else ''} trained with different "
                         f"hyperparameters ({', '.join(differing)}): a grid record holds one set")
    rows, test = {}, earlier["test"] if kept else None
    for index in kept:
        rows[index] = _kept_row(earlier, points[index], index, episodes)
    for index in fresh:
        point = points[index]
        report = evaluation_of_point(run_dirs[index], point, episodes)
        summary, test = summaries[index], {"seed": report["seed"], "episodes": episodes, "actions": "sampled"}
        rows[index] = {"name": point.name, "task": point.task_name, "task_index": point.task_index,
                       "level": point.level, "fingerprint": point.fingerprint,
                       "agent_steps": summary["agent_steps"], "wall_s": summary["wall_s"], "seed": summary["seed"],
                       "resumed_at": summary.get("resumed_at", []), "machines": trained_on(summary),
                       "return": report["return"], "statistics": report["statistics"], "published": report["published"],
                       **{policy: level_of(point, policy, episodes) for policy in LEVEL_POLICIES},
                       **curve_fields(run_dirs[index])}
        rows[index] |= _kept_seeds(earlier, point, configs[0], summary["seed"])
    data = {"environment": points[0].environment, "sweep": sweep, "sweep_fingerprint": sweep_fingerprint(points),
            "command": earlier["command"] if command is None else command,
            "note": earlier["note"] if note is None else note, "machine": "; ".join(_grid_machines(rows)),
            "hyperparameters": configs[0], "test": test,
            "points": [rows[index] for index in sorted(rows)], "untrained": untrained}
    record = out_dir / GRIDS / f"{data['environment']}.json"
    text = dumps(data, record, 1)
    record.parent.mkdir(parents=True, exist_ok=True)
    record.write_text(text)
    return data


def trained_on(summary: dict[str, Any]) -> list[str]:
    """The machines a run trained on (its summary's, in words), or this one for a run from before summaries named
    them, which is taken to be recorded where it trained."""
    return summary.get("machines") or [machine()]


def _grid_machines(rows: dict[int, dict[str, Any]]) -> list[str]:
    """Every machine the grid's points trained on, each once in the points' order."""
    return list(dict.fromkeys(word for index in sorted(rows) for word in rows[index]["machines"]))


def sweep_fingerprint(points: list[CompiledScenario]) -> str:
    """``sha256:<hex>`` of a sweep's points' fingerprints in their order: what the sweep trains, whatever its path
    or its points' names."""
    return "sha256:" + hashlib.sha256("\n".join(point.fingerprint for point in points).encode()).hexdigest()


def _recorded_rows(record: Path, sweep: str, points: list[CompiledScenario], replace: bool) -> dict[str, Any]:
    """The grid record already at ``record``, of ``points`` (the sweep ``sweep``): its rows by point name,
    hyperparameters, test, command and note; no rows (and no words) where there is none yet, or with ``replace``.
    A record of another sweep is refused (it is replaced only with ``replace``)."""
    if not record.is_file() or replace:
        return {"rows": {}, "command": "", "note": ""}
    data = read_json(record, "grid record")
    if not of_sweep(data, points):
        raise TrainError(f"{record} records another sweep ({data.get('sweep')!r}, {len(data['points'])} points "
                         f"recorded) than {sweep} ({len(points)} points): give --replace to replace it, or record "
                         "into another folder")
    # a row from before rows named their machines trained on its record's
    rows = {row["name"]: {"machines": [data["machine"]]} | row for row in data["points"]}
    return {"rows": rows, "hyperparameters": data["hyperparameters"], "test": data["test"], "path": record,
            "command": data.get("command", ""), "note": data.get("note", "")}


def of_sweep(data: dict[str, Any], points: list[CompiledScenario]) -> bool:
    """Whether the grid record ``data`` records the sweep of ``points``: by its sweep's fingerprint, or (a record
    written before records carried one) every row's point among them by name and fingerprint."""
    if "sweep_fingerprint" in data:
        return data["sweep_fingerprint"] == sweep_fingerprint(points)
    ours = {(point.name, point.fingerprint) for point in points}
    return all(isinstance(row, dict) and (row.get("name"), row.get("fingerprint")) in ours for row in data["points"])


def _kept_row(earlier: dict[str, Any], point: CompiledScenario, index: int, episodes: int) -> dict[str, Any]:
    """The earlier record's row of ``point`` (index ``index``), refused where it is not of this scenario or of
    ``episodes`` test episodes."""
    row, where = earlier["rows"][point.name], f"{earlier['path']} records point {index} ({point.name!r})"
    if row.get("fingerprint") != point.fingerprint:
        raise TrainError(f"{where} of another scenario (fingerprint {row.get('fingerprint')}, the sweep's point now "
                         f"{point.fingerprint}): train it again, or move the record aside")
    if earlier["test"]["episodes"] != episodes:
        raise TrainError(f"{where} on {earlier['test']['episodes']} test episodes, not {episodes}: record with "
                         f"--episodes {earlier['test']['episodes']}, or train it again")
    return row


def _kept_seeds(earlier: dict[str, Any], point: CompiledScenario, hyperparameters: dict[str, Any],
                seed: int) -> dict[str, Any]:
    """The ``other_seeds`` of the earlier record's row of ``point`` (:mod:`.grid_seeds`), kept for its fresh row
    where they trained the same scenario with the same ``hyperparameters`` (but the one on ``seed``, which the fresh
    row now is); none otherwise."""
    row = earlier["rows"].get(point.name, {})
    if row.get("fingerprint") != point.fingerprint or earlier.get("hyperparameters") != hyperparameters:
        return {}
    others = [entry for entry in row.get("other_seeds", []) if entry["seed"] != seed]
    return {"other_seeds": others} if others else {}


def trained_to_end(run_dir: Path) -> bool:
    """Whether the run in ``run_dir`` trained to its end (which scenario it trained, :func:`finished_point` checks)."""
    return (run_dir / "checkpoint.pt").is_file() and not _summary(run_dir)["stopped_early"]


def _summary(run_dir: Path) -> dict[str, Any]:
    """The run's summary.json, or ``{"stopped_early": True}`` where it has none yet (a run under way)."""
    path = run_dir / "summary.json"
    return read_json(path, "summary") if path.is_file() else {"stopped_early": True}


def finished_point(run_dir: Path, index: int, point: CompiledScenario, sweep: str) -> dict[str, Any]:
    """The summary of ``run_dir``'s run, which must have trained ``point`` (of ``sweep``) to its end."""
    if not (run_dir / "checkpoint.pt").is_file():
        raise TrainError(f"{run_dir.parent} has no trained point {index} of {sweep} (no {run_dir / 'checkpoint.pt'})")
    if load_checkpoint(run_dir / "checkpoint.pt")["fingerprint"] != point.fingerprint:
        raise TrainError(f"{run_dir} trained another scenario than {point.name!r}, point {index} of {sweep}")
    summary = _summary(run_dir)
    if summary["stopped_early"]:
        raise TrainError(f"point {index} of {sweep} ({run_dir}) did not train to its end: run the grid's "
                         "`hivex train` command again with --resume")
    return summary


def evaluation_of_point(run_dir: Path, point: CompiledScenario, episodes: int) -> dict[str, Any]:
    """The point's test-seed evaluation of ``episodes`` episodes: the grid's own where it played the checkpoint as
    it is now (its digest; a point resumed and trained on since has another), or a fresh one. Its published cell is
    read now: whether a scenario is the paper's setting depends on the defaults as they are, and a point trained from
    a copy that wrote out params that became the defaults later is the paper's cell now, the same by its fingerprint."""
    written = run_dir / "evaluation.json"
    if written.is_file():
        try:
            report = json.loads(written.read_text())
        except (OSError, UnicodeDecodeError, ValueError):
            report = {}
        same = {"split": "test", "episodes": episodes, "actions": "sampled", "fingerprint": point.fingerprint,
                "checkpoint_sha256": file_digest(run_dir / "checkpoint.pt")}
        if isinstance(report, dict) and all(report.get(key) == value for key, value in same.items()):
            return report | {"published": published_result(point)}
    return evaluate(run_dir / "checkpoint.pt", split="test", episodes=episodes)
