"""A run directory is the run's, as a repository is git's: the run writes only its own files there, it knows
them afterwards by a manifest of their names and SHA-256 digests (``.hivex/manifest.json``), and one process at a
time writes there (``.hivex/lock``, an flock that dies with its process).

A new run never silently replaces an earlier one (as ML-Agents refuses a used run-id without --resume or
--force). ``--force`` removes exactly the files the manifest lists whose digests still match; ``--resume`` goes
on beside them. A file at a name the run writes or reads (``checkpoints/step_*.pt``, ``tb/events.out.tfevents.*``,
``summary.json``, ...) that the manifest does not list, or whose content changed since, is refused either way,
named, and left as it is: kept, it would be read as the run's (TensorBoard reads every event file in ``tb/``, a
baseline record every ``step_*.pt``), and replaced, it would be lost. Nothing is followed through a symbolic link.
"""

from __future__ import annotations

import fnmatch
import hashlib
import json
import math
import os
import socket
import time
from pathlib import Path
from typing import Any, Callable, Iterable

from .config import TrainError

# The names a run (and its grid's evaluation, and a grid's table) writes into its folder, as glob patterns.
RUN_FILES = ("checkpoint.pt", "checkpoints/step_*.pt", "config.json", "curve.json", "summary.json", "evaluation.json",
             "results.json", "tb/events.out.tfevents.*")
RUN_FOLDERS = ("checkpoints", "tb")  # removed by --force once the run's files are gone, if nothing else is left
PARTIAL = ".partial"  # the suffix of a file being written (write_atomically)
META = ".hivex"  # the run's own bookkeeping: the manifest and the lock
MANIFEST, LOCK, OWNER = f"{META}/manifest.json", f"{META}/lock", f"{META}/owner.json"
MANIFEST_FORMAT = "hivex-run/1"
# an earlier hivex's run, written before manifests: its JSON files by the shape and key that say a run wrote them
LEGACY_JSON = {"config.json": (dict, "hyperparameters"), "summary.json": (dict, "agent_steps"),
               "evaluation.json": (dict, "split"), "curve.json": (list, None), "results.json": (list, None)}


def file_digest(path: Path, size: int | None = None) -> str:
    """``sha256:<hex>`` of the file's bytes (its first ``size`` bytes when given), read without following a link."""
    digest, left = hashlib.sha256(), size
    with open(os.open(path, os.O_RDONLY | getattr(os, "O_NOFOLLOW", 0)), "rb") as handle:
        while left is None or left > 0:
            chunk = handle.read(1 << 20 if left is None else min(1 << 20, left))
            if not chunk:
                break
            digest.update(chunk)
            left = None if left is None else left - len(chunk)
    return "sha256:" + digest.hexdigest()


class Inventory:
    """What a run directory holds at the names a run writes, by whose they are: ``ours`` (the manifest lists them
    with their content, or they are half-written saves it announced), ``changed`` (listed, content changed),
    ``foreign`` (not listed, or a link or folder where a run writes a file), ``missing`` (listed, gone).
    ``legacy``: no manifest, so the run files were judged by name and shape (an earlier hivex's run)."""

    def __init__(self, root: Path) -> None:
        self.root = Path(root)
        self.manifest = read_manifest(self.root)
        self.legacy = self.manifest is None
        self.ours: list[str] = []
        self.changed: list[str] = []
        self.foreign: list[str] = []
        listed = {} if self.manifest is None else self.manifest["files"]
        pending = set() if self.manifest is None else set(self.manifest["pending"])
        self.missing = sorted(name for name in listed if not _lexists(self.root / name))
        for name in sorted(set(_candidates(self.root)) | {n for n in [*listed, *pending] if _lexists(self.root / n)}):
            self._sort(name, listed, pending)

    def _sort(self, name: str, listed: dict[str, Any], pending: set[str]) -> None:
        path = self.root / name
        if path.is_symlink() or not path.is_file():
            self.foreign.append(name + (" (a link)" if path.is_symlink() else " (not a file)"))
        elif name in pending:
            self.ours.append(name)
        elif name in listed:
            (self.ours if _matches(path, listed[name]) else self.changed).append(name)
        elif self.legacy and (name.endswith(PARTIAL) or _legacy_run_file(path)):  # a half save at a run's name
            self.ours.append(name)
        else:
            self.foreign.append(name)

    def lost(self, name: str) -> bool:
        """Whether the run wrote ``name`` and it is gone since (a checkpoint deleted by hand)."""
        return name in self.missing


def _lexists(path: Path) -> bool:
    return path.is_symlink() or path.exists()


def _candidates(root: Path) -> Iterable[str]:
    """The relative names under ``root`` at the run's patterns (and their ``.partial``s), not through links: a
    run folder that is a link is itself a candidate (and foreign)."""
    for folder in RUN_FOLDERS:
        if (root / folder).is_symlink() or ((root / folder).exists() and not (root / folder).is_dir()):
            yield folder
    for pattern in RUN_FILES:
        folder = pattern.partition("/")[0] if "/" in pattern else None
        if folder is not None and ((root / folder).is_symlink() or not (root / folder).is_dir()):
            continue
        for found in [*root.glob(pattern), *root.glob(pattern + PARTIAL)]:
            yield str(found.relative_to(root))


def _matches(path: Path, entry: dict[str, Any]) -> bool:
    """Whether ``path`` holds what the manifest's ``entry`` says: one of its digests, or (a file the run appends
    to, TensorBoard's events) at least its recorded size with that prefix's digest."""
    try:
        if "prefix" in entry:
            size = entry["prefix"]["size"]
            return path.stat().st_size >= size and file_digest(path, size) == entry["prefix"]["sha256"]
        return file_digest(path) in entry["sha256"]
    except OSError:
        return False


def _legacy_run_file(path: Path) -> bool:
    """A file of an earlier hivex's run, without a manifest: its JSON files by shape, the others by name."""
    if path.name not in LEGACY_JSON or path.parent.name in RUN_FOLDERS:
        return True
    kind, key = LEGACY_JSON[path.name]
    try:
        data = json.loads(path.read_text(encoding="utf-8"))
    except (OSError, UnicodeDecodeError, ValueError):
        return False
    if path.name == "results.json":
        return isinstance(data, list) and all(isinstance(row, dict) and "agent_steps" in row for row in data)
    return isinstance(data, kind) and (key is None or key in data)


def read_manifest(root: Path) -> dict[str, Any] | None:
    """``root``'s manifest (``{"files": {name: entry}, "pending": [name]}``), None where it has none."""
    path = Path(root) / MANIFEST
    if (Path(root) / META).is_symlink() or path.is_symlink():
        raise TrainError(f"{Path(root) / META} is a link: a run keeps its bookkeeping inside its own directory")
    if not path.exists():
        return None
    try:
        data = json.loads(path.read_text(encoding="utf-8"))
        if data.get("format") != MANIFEST_FORMAT or not isinstance(data["files"], dict) or \
                not isinstance(data["pending"], list):
            raise ValueError
    except (OSError, UnicodeDecodeError, ValueError, KeyError, AttributeError, TypeError):
        raise TrainError(f"{path} is not a hivex run manifest ({MANIFEST_FORMAT}): restore it, or give another run "
                         "directory") from None
    strange = [name for name in [*data["files"], *data["pending"]] if not _a_run_name(name)]
    if strange:  # a manifest edited to list another file would have --force remove it
        raise TrainError(f"{path} lists {', '.join(map(repr, strange))}, not names a run writes in its directory: "
                         "restore it, or give another run directory")
    return data


def _a_run_name(name: Any) -> bool:
    """Whether ``name`` is one of :data:`RUN_FILES` (or its ``.partial``), relative and inside the directory."""
    if not isinstance(name, str) or name.startswith("/") or ".." in name.split("/"):
        return False
    return any(fnmatch.fnmatchcase(name.removesuffix(PARTIAL), pattern) for pattern in RUN_FILES)


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


def check_claimable(run_dir: Path, resume: bool, overwrite: bool) -> Inventory | None:
    """Refuse (a TrainError) what a run may not do in ``run_dir``; -> its inventory (None where it is new)."""
    if resume and overwrite:
        raise TrainError("resume goes on from the run directory's run and overwrite replaces it: give one")
    run_dir = Path(run_dir)
    if run_dir.exists() and not run_dir.is_dir():
        raise TrainError(f"{run_dir} is a file, not a run directory: give a directory's path (it is made if new)")
    if not run_dir.exists():
        return None
    found = Inventory(run_dir)
    if found.foreign:
        raise TrainError(f"{run_dir} holds {', '.join(found.foreign)}, which hivex did not write, at names a run writes "
                         "or reads: move them, or give another run directory")
    if found.changed:
        raise TrainError(f"{run_dir} holds {', '.join(found.changed)}, changed since the run wrote "
                         f"{'them' if len(found.changed) > 1 else 'it'}: a run neither trusts nor removes what it did not "
                         "write; restore or move them, or give another run directory")
    if overwrite and found.legacy and found.ours:
        raise TrainError(f"{run_dir} holds {', '.join(found.ours)} at names a run writes, and no run manifest "
                         f"({MANIFEST}): an earlier hivex's run, or files of your own; which are a run's cannot be "
                         "told, so --force removes nothing: remove them yourself, go on with --resume, or give another "
                         "run directory")
    if not (resume or overwrite) and [name for name in found.ours if not name.endswith(PARTIAL)]:
        raise TrainError(refusal(run_dir, found.ours))
    return found


class RunDir:
    """A run directory claimed by this process (:meth:`claim`): locked until :meth:`close`, and every file written
    through it recorded in its manifest with its digest."""

    def __init__(self, root: Path, lock: Any, manifest: dict[str, Any]) -> None:
        self.root, self._lock, self.manifest = Path(root), lock, manifest
        self._plan: tuple[Inventory | None, bool] | None = None

    @classmethod
    def claim(cls, run_dir: Path, resume: bool = False, overwrite: bool = False, wait: float = 0) -> "RunDir":
        """``run_dir`` ready for a run (made if new): ``resume`` keeps the run's files there (less the half-written
        saves an interruption left), ``overwrite`` removes them, neither refuses a directory that holds any
        (:func:`check_claimable`). Another process writing there is refused at once, or after ``wait`` seconds."""
        run_dir = Path(run_dir)
        lock = _try_lock(run_dir, wait) if (run_dir / LOCK).exists() else None
        try:
            check_claimable(run_dir, resume, overwrite)
            lock = lock or _try_lock(run_dir, wait)
            found = check_claimable(run_dir, resume, overwrite)  # again, now that no other process can write
        except BaseException:
            if lock is not None:
                lock.release()
            raise
        _sign(run_dir)
        listed = {} if found is None or found.manifest is None else found.manifest["files"]
        kept = {name: entry for name, entry in listed.items() if not (overwrite and found.lost(name))}
        run = cls(run_dir, lock, {"format": MANIFEST_FORMAT, "files": kept, "pending": []})
        run._plan = (found, overwrite)
        return run

    def _prepare(self) -> None:
        """Before the run's first write (so that a run refused after its claim, by its checkpoint say, has changed
        nothing): remove the earlier run's files (``overwrite``) or the half-written saves an interruption left,
        and adopt an earlier hivex's files into the manifest."""
        if self._plan is None:
            return
        found, overwrite = self._plan
        self._plan = None
        ours = [] if found is None else found.ours
        removed = [name for name in ours if overwrite or name.endswith(PARTIAL)]
        for name in ours:
            if name not in removed and name not in self.manifest["files"]:  # an earlier hivex's file, adopted
                self.manifest["files"][name] = {"sha256": [file_digest(self.root / name)]}
        for name in removed:
            (self.root / name).unlink()
            self.manifest["files"].pop(name, None)
        for folder in RUN_FOLDERS:
            if removed and (self.root / folder).is_dir() and not any((self.root / folder).iterdir()):
                (self.root / folder).rmdir()
        self._save_manifest()

    def __enter__(self) -> "RunDir":
        return self

    def __exit__(self, *exc: Any) -> None:
        self.close()

    def close(self) -> None:
        if self._lock is not None:
            self._lock.release()
            self._lock = None

    def name_of(self, path: Path) -> str:
        """``path`` (under the run directory, as the run builds its paths) relative to it."""
        return Path(path).relative_to(self.root).as_posix()

    def write(self, path: Path, write: Callable[[Path], None]) -> None:
        """:func:`write_atomically`, with the manifest announcing the ``.partial`` before it is written and
        accepting either content while the rename is under way, so a run killed at any instant leaves files its
        manifest recognises."""
        self._prepare()
        name = self.name_of(path)
        partial = Path(path).with_name(Path(path).name + PARTIAL)
        self.manifest["pending"].append(name + PARTIAL)
        self._save_manifest()
        write(partial)
        before = self.manifest["files"].get(name, {}).get("sha256", [])
        self.manifest["files"][name] = {"sha256": [*before, file_digest(partial)]}
        self._save_manifest()
        partial.replace(path)
        self.manifest["files"][name]["sha256"] = self.manifest["files"][name]["sha256"][-1:]
        self.manifest["pending"].remove(name + PARTIAL)
        self._save_manifest()

    def write_json(self, name: str, data: Any, indent: int = 2) -> None:
        self.write(self.root / name, lambda partial: partial.write_text(dumps(data, self.root / name, indent)))

    def appended(self, path: Path) -> None:
        """Record ``path``, a file the run appends to (TensorBoard's events), as it is now: it stays the run's
        while it begins with these bytes."""
        self._prepare()
        size = Path(path).stat().st_size
        self.manifest["files"][self.name_of(path)] = {"prefix": {"size": size, "sha256": file_digest(path, size)}}
        self._save_manifest()

    def remove(self, path: Path) -> None:
        """Remove ``path`` if it is the run's (the manifest lists it with this content); leave anything else."""
        self._prepare()
        name = self.name_of(path)
        entry = self.manifest["files"].get(name)
        if entry is not None and not Path(path).is_symlink() and Path(path).is_file() and _matches(Path(path), entry):
            Path(path).unlink()
            del self.manifest["files"][name]
            self._save_manifest()

    def _save_manifest(self) -> None:
        write_atomically(self.root / MANIFEST, lambda partial: partial.write_text(json.dumps(self.manifest, indent=1)))


def writer_of(run_dir: Path) -> str:
    """`` (process 123 on host, since ...)`` where another process holds ``run_dir``'s lock now; else empty."""
    if not (Path(run_dir) / LOCK).is_file():
        return ""
    try:
        _try_lock(Path(run_dir)).release()
    except TrainError:
        return _owner(Path(run_dir)) or " (a process that did not say which)"
    return ""


def _try_lock(run_dir: Path, wait: float = 0) -> Any:
    """The run directory's lock, held by this process; a TrainError where another process holds it still after
    ``wait`` seconds."""
    from filelock import FileLock, Timeout

    if (run_dir / META).is_symlink() or ((run_dir / META).exists() and not (run_dir / META).is_dir()):
        raise TrainError(f"{run_dir / META} is not a folder of hivex's: move it, or give another run directory")
    (run_dir / META).mkdir(parents=True, exist_ok=True)
    lock = FileLock(str(run_dir / LOCK), timeout=wait)
    try:
        lock.acquire()
    except Timeout:
        raise TrainError(f"another hivex is writing to {run_dir}{_owner(run_dir)}: wait for it to end, or give "
                         "another run directory") from None
    return lock


def _sign(run_dir: Path) -> None:
    """Write down who holds the lock, for the message of a process refused it (the lock itself is the flock)."""
    (run_dir / OWNER).write_text(json.dumps({"pid": os.getpid(), "host": socket.gethostname(),
                                             "since": time.strftime("%Y-%m-%d %H:%M:%S")}))


def _owner(run_dir: Path) -> str:
    """`` (process 123 on host, since ...)``: who holds the lock, as it wrote down; empty where unreadable."""
    try:
        owner = json.loads((run_dir / OWNER).read_text())
        return f" (process {owner['pid']} on {owner['host']}, since {owner['since']})"
    except (OSError, ValueError, KeyError, TypeError):
        return ""


def write_atomically(path: Path, write: Callable[[Path], None]) -> None:
    """``write(partial)`` a file beside ``path``, then rename it over ``path``: a run killed mid-write leaves
    the old file or the new one, never half of one."""
    partial = Path(path).with_name(Path(path).name + PARTIAL)
    write(partial)
    partial.replace(path)


def dumps(data: Any, path: Path, indent: int = 2) -> str:
    """``data`` as JSON text; a non-finite number (which JSON cannot hold) is a TrainError naming ``path``."""
    try:
        return json.dumps(data, indent=indent, allow_nan=False) + "\n"
    except ValueError:
        raise TrainError(f"{path} would hold a number that is not finite, which JSON cannot hold: "
                         f"{_first_non_finite(data)}") from None


def _first_non_finite(data: Any, place: str = "") -> str:
    if isinstance(data, float) and not math.isfinite(data):
        return f"{place or 'the value'} is {data}"
    items = data.items() if isinstance(data, dict) else enumerate(data) if isinstance(data, list) else ()
    for key, value in items:
        found = _first_non_finite(value, f"{place}.{key}" if place else str(key))
        if found:
            return found
    return ""
