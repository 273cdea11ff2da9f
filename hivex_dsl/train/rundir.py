"""A run directory's files: a new run never silently replaces an earlier one (as ML-Agents refuses a used run-id
without --resume or --force), and replacing one removes that run's files and nothing else."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any, Callable

from .config import TrainError

# What `hivex train` (and its grid's evaluation) writes into a run directory, as glob patterns: checkpoints and
# TensorBoard event files are recognised by the names the run gives them (step_<N>.pt, events.out.tfevents.*);
# a user's own files beside them (checkpoints/best.pt, tb/other.tfevents) are not the run's.
RUN_FILES = ("checkpoint.pt", "checkpoint.pt.partial", "checkpoints/step_*.pt", "checkpoints/step_*.pt.partial",
             "config.json", "curve.json", "summary.json", "evaluation.json", "*.json.partial",
             "tb/events.out.tfevents.*")
# the run's JSON files, by the top-level shape and key that say a run wrote them (a user's config.json is not)
RUN_JSON = {"config.json": (dict, "hyperparameters"), "summary.json": (dict, "agent_steps"),
            "evaluation.json": (dict, "split"), "curve.json": (list, None)}
RUN_FOLDERS = ("checkpoints", "tb")  # removed by --force once the run's files are gone, if nothing else is left


def earlier_run(run_dir: Path) -> list[str]:
    """The paths (relative to ``run_dir``, sorted) of an earlier run's files there (empty when it holds none)."""
    run_dir = Path(run_dir)
    found = {path for pattern in RUN_FILES for path in run_dir.glob(pattern) if path.is_file()}
    return sorted(str(path.relative_to(run_dir)) for path in found if _written_by_a_run(path))


def foreign_files(run_dir: Path) -> list[str]:
    """Files at the names a run writes that a run did not write (a run would overwrite them): JSON files of
    another shape, and folders or links where a run writes a file."""
    run_dir = Path(run_dir)
    names = [name for name in RUN_FILES if "*" not in name]
    return [name for name in names if (run_dir / name).exists() and
            ((run_dir / name).is_symlink() or not (run_dir / name).is_file() or not _written_by_a_run(run_dir / name))]


def _written_by_a_run(path: Path) -> bool:
    """A JSON file of :data:`RUN_JSON` is a run's when its shape says so; the other names are a run's by name."""
    if path.is_symlink():
        return False
    if path.name not in RUN_JSON or path.parent.name in RUN_FOLDERS:
        return True
    kind, key = RUN_JSON[path.name]
    try:
        data = json.loads(path.read_text(encoding="utf-8"))
    except (OSError, UnicodeDecodeError, ValueError):
        return False
    return isinstance(data, kind) and (key is None or key in data)


def refusal(run_dir: Path, found: list[str]) -> str:
    return (f"{run_dir} holds an earlier run ({', '.join(_summarised(found))}): add --resume to go on from it, "
            "--force to replace it, or give another run directory")


def _summarised(found: list[str]) -> list[str]:
    """``checkpoints/step_1.pt, checkpoints/step_2.pt, tb/events...`` -> ``checkpoints/ (2 files)``, ``tb/ (1 file)``."""
    names: dict[str, int] = {}
    for path in found:
        folder, sep, _ = path.partition("/")
        names[folder + sep] = names.get(folder + sep, 0) + 1
    return [name if not name.endswith("/") else f"{name} ({count} file{'s' * (count != 1)})"
            for name, count in names.items()]


def claim(run_dir: Path, resume: bool, overwrite: bool) -> None:
    """Make ``run_dir`` ready for a run (creating it). ``resume`` goes on from the run there (checked by
    :func:`.checkpoint.resume_state`), removing the ``.partial`` saves an interrupted run left; otherwise one that holds an earlier run's files is refused unless
    ``overwrite``, which removes exactly those files (:func:`earlier_run`) and then the run's folders if that
    left them empty: anything else in the directory stays. A file of the user's at a name the run writes
    (a config.json of another tool's, say) is refused either way: the run would overwrite it."""
    if resume and overwrite:
        raise TrainError("resume goes on from the run directory's run and overwrite replaces it: give one")
    run_dir = Path(run_dir)
    if run_dir.exists() and not run_dir.is_dir():
        raise TrainError(f"{run_dir} is a file, not a run directory: give a directory's path (it is made if new)")
    foreign = foreign_files(run_dir)
    if foreign:
        raise TrainError(f"{run_dir} holds {', '.join(foreign)}, which a run did not write and would overwrite: "
                         "move it, or give another run directory")
    found = earlier_run(run_dir)
    if resume:  # go on with the run's files, less the half-written saves an interruption left
        found = [name for name in found if name.endswith(".partial")]
    elif found and not overwrite:
        raise TrainError(refusal(run_dir, found))
    for name in found:
        (run_dir / name).unlink()
    for folder in RUN_FOLDERS:
        if found and (run_dir / folder).is_dir() and not any((run_dir / folder).iterdir()):
            (run_dir / folder).rmdir()
    run_dir.mkdir(parents=True, exist_ok=True)


def write_atomically(path: Path, write: Callable[[Path], None]) -> None:
    """``write(partial)`` a file beside ``path``, then rename it over ``path``: a run killed mid-write leaves
    the old file or the new one, never half of one (a stale ``.partial`` is removed by the next claim)."""
    partial = Path(path).with_name(Path(path).name + ".partial")
    write(partial)
    partial.replace(path)


def write_json(path: Path, data: Any, indent: int = 2) -> None:
    """``data`` as indented JSON at ``path``, atomically (:func:`write_atomically`)."""
    write_atomically(path, lambda partial: partial.write_text(json.dumps(data, indent=indent) + "\n"))
