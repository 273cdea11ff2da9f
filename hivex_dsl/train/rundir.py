"""A run directory's files: a new run never silently replaces an earlier one (as ML-Agents refuses a used run-id
without --resume or --force)."""

from __future__ import annotations

import shutil
from pathlib import Path

from .config import TrainError

# everything `hivex train` (and its grid's evaluation) writes into a run directory
RUN_FILES = ("checkpoint.pt", "checkpoint.pt.partial", "checkpoints", "config.json", "curve.json", "summary.json",
             "evaluation.json", "tb")


def earlier_run(run_dir: Path) -> list[str]:
    """The names of an earlier run's files in ``run_dir`` (empty when it holds none)."""
    return [name for name in RUN_FILES if (Path(run_dir) / name).exists()]


def refusal(run_dir: Path, found: list[str]) -> str:
    return (f"{run_dir} holds an earlier run ({', '.join(found)}): add --resume to go on from it, --force to "
            "replace it, or give another run directory")


def claim(run_dir: Path, resume: bool, overwrite: bool) -> None:
    """Make ``run_dir`` ready for a run (creating it). ``resume`` goes on from the run there (checked by
    :func:`.checkpoint.resume_state`); otherwise one that holds an earlier run's files is refused unless
    ``overwrite``, which removes exactly those files (anything else in the directory stays)."""
    if resume and overwrite:
        raise TrainError("resume goes on from the run directory's run and overwrite replaces it: give one")
    if Path(run_dir).exists() and not Path(run_dir).is_dir():
        raise TrainError(f"{run_dir} is a file, not a run directory: give a directory's path (it is made if new)")
    found = [] if resume else earlier_run(run_dir)
    if found and not overwrite:
        raise TrainError(refusal(run_dir, found))
    for name in found:
        path = Path(run_dir) / name
        if path.is_dir() and not path.is_symlink():
            shutil.rmtree(path)
        else:
            path.unlink()
    Path(run_dir).mkdir(parents=True, exist_ok=True)
