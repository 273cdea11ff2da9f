"""Training every point of a sweep: one after another, several at once in local processes (``jobs``), or as Ray
tasks on a local instance or a cluster.

Each point trains in its own run directory ``RUN_DIR/NNN-<name>`` and returns its summary; the
summaries are gathered into one table (``RUN_DIR/results.json``). On a cluster the run directories are
written on the node that ran the point: give RUN_DIR on a shared filesystem to see them all in one place.
Every node of a cluster needs hivex-dsl with its train extra installed (``pip install 'hivex-dsl[train]'``).
"""

from __future__ import annotations

import json
import os
import pickle
import queue
import re
import signal
import sys
import threading
import time
import traceback
from multiprocessing import get_context
from pathlib import Path
from typing import Any, Sequence

from ..compiler import CompiledScenario, compile
from .config import PPOConfig, TrainError
from .rundir import Inventory, RunDir, check_claimable, file_digest, writer_of
from .stopping import StopRequests


def point_dir(run_dir: Path, index: int, compiled: CompiledScenario) -> Path:
    """``RUN_DIR/003-wfc-paper_pattern=1,task=1``: sortable, and safe on every filesystem."""
    slug = re.sub(r"[^A-Za-z0-9_.,=-]+", "_", compiled.name).strip("_")
    return Path(run_dir) / f"{index:03d}-{slug}"


def train_point(scenario: dict[str, Any], config: dict[str, Any], run_dir: str, eval_episodes: int,
                progress: bool, resume: bool = False, overwrite: bool = False, stop_event: Any = None
                ) -> dict[str, Any]:
    """Train one point (given as plain data, so it travels to a Ray worker) and evaluate it on the test seeds;
    ``resume`` goes on from the run directory's checkpoint, ``overwrite`` replaces an earlier run there, and
    setting ``stop_event`` stops its training after the update under way (a point stopped is not evaluated: the
    policy is half-trained, and the command should end now). The evaluation (``evaluation.json``) names the
    checkpoint it played by its digest, so it is reused only while that checkpoint is the run's."""
    from .evaluate import evaluate
    from .ppo import train

    compiled = compile(scenario)
    with RunDir.claim(Path(run_dir), resume, overwrite) as run:
        summary = train(compiled, PPOConfig(**config), run.root, progress=progress, resume=resume,
                        stop_event=stop_event, run=run)
        summary["run_dir"], summary["fingerprint"] = str(run_dir), compiled.fingerprint
        if eval_episodes and not summary["stopped_early"]:
            checkpoint = run.root / "checkpoint.pt"
            report = evaluate(checkpoint, split="test", episodes=eval_episodes, progress=progress)
            report |= {"checkpoint_sha256": file_digest(checkpoint), "fingerprint": compiled.fingerprint}
            summary["test_return"] = report["return"]
            summary["published_return"] = report["published"]["return"] if report["published"] else None
            run.write_json("evaluation.json", report)
    return summary


def run_grid(points: Sequence[CompiledScenario], configs: Sequence[PPOConfig], run_dir: Path,
             eval_episodes: int = 0, ray_address: str | None = None, ray_init: dict[str, Any] | None = None,
             progress: bool = True, resume: bool = False, overwrite: bool = False, jobs: int = 1,
             indices: Sequence[int] | None = None) -> list[dict[str, Any]]:
    """Train every point (``configs[i]`` for ``points[i]``); ``ray_address`` ``"local"`` starts a local Ray
    instance, any other value joins that cluster, ``None`` runs the points in turn, or ``jobs`` of them at once
    in processes of their own (a point's ``auto`` torch threads are then this machine's cores / ``jobs``, so
    the points share the cores instead of fighting over them). ``resume`` lets each
    point with a checkpoint go on from it (one that finished only re-evaluates); the others start afresh, over
    what a point killed before its first checkpoint left. Without ``resume`` or ``overwrite`` a grid whose
    points hold earlier runs is refused before any point trains. Ctrl-C (or SIGTERM) stops the point under
    way after its update and trains no later point. ``indices`` are the points' indices in their sweep when
    ``points`` are some of its points (`hivex train --points`), so each trains in the folder its index names.
    -> the results table of the points trained; ``RUN_DIR/results.json`` keeps earlier runs' rows of other points."""
    run_dir = Path(run_dir)
    indices = range(len(points)) if indices is None else indices
    folders = [point_dir(run_dir, i, p).resolve() for i, p in zip(indices, points, strict=True)]
    going_on = [resume and (folder / "checkpoint.pt").is_file() for folder in folders]
    modes = [(again, not again and (resume or overwrite)) for again in going_on]
    _check_points(run_dir, folders, indices, modes, resume, overwrite)
    if jobs > 1 and ray_address is None:
        configs = [shared_cores(c, jobs) for c in configs]
    work = [(p.resolved(), c.model_dump(mode="json"), str(folder), eval_episodes)
            for p, c, folder in zip(points, configs, folders)]
    if ray_address is not None:
        results = _on_ray(work, modes, ray_address, ray_init or {})
    elif jobs > 1:
        results = _in_processes(work, modes, jobs)
    else:
        results = []
        for job, (again, replace) in zip(work, modes):
            results.append(train_point(*job, progress=progress, resume=again, overwrite=replace))
            if results[-1]["stopped_early"]:  # Ctrl-C or SIGTERM stops the grid with its point
                break
    for row in results:  # a point's folder by its name in the grid's: the table holds after the grid is moved
        row["run_dir"] = Path(row["run_dir"]).name
    with RunDir.claim(run_dir, resume=True, wait=60) as grid:
        grid.write_json("results.json", _with_earlier_rows(run_dir / "results.json", results))
    return results


def _check_points(run_dir: Path, folders: list[Path], indices: Sequence[int], modes: list[tuple[bool, bool]],
                  resume: bool, overwrite: bool) -> None:
    """Refuse, before any point trains, what a point or the grid's table would refuse: a folder in use by another
    process or holding files hivex did not write, earlier runs without ``resume`` or ``overwrite``, and (with
    ``resume``) a point whose run saved a checkpoint that is gone: it is not started afresh over its files."""
    check_claimable(run_dir, resume=True, overwrite=False)
    problems = []
    for index, folder, (again, replace) in zip(indices, folders, modes):
        try:
            if resume and not again and _lost_checkpoint(folder):
                raise TrainError(f"cannot resume point {index}: {folder} holds a run that saved a checkpoint, and its "
                                 "checkpoint.pt is gone: restore it, or train the point afresh with --force --points "
                                 f"{index}")
            check_claimable(folder, again, replace)
            writer = writer_of(folder)
            if writer:
                raise TrainError(f"another hivex is writing to {folder}{writer}: wait for it to end")
        except TrainError as exc:
            problems.append(str(exc))
    if problems:
        raise TrainError("\n".join(problems))


def _lost_checkpoint(folder: Path) -> bool:
    """Whether ``folder``'s run saved a checkpoint that is not there now (deleted, moved): its manifest lists
    ``checkpoint.pt`` as gone, or it holds numbered checkpoints or a summary, which a run writes after its first."""
    if not folder.is_dir() or (folder / "checkpoint.pt").exists():
        return False
    found = Inventory(folder)
    return found.lost("checkpoint.pt") or any(name == "summary.json" or name.startswith("checkpoints/")
                                              for name in found.ours)


def _with_earlier_rows(table: Path, results: list[dict[str, Any]]) -> list[dict[str, Any]]:
    """``results`` with the rows of ``table`` (an earlier results.json) of points they do not hold, in the
    order of the points' folders: a grid trained a few points at a time keeps one table of all of them. A row is
    its point's by the point's folder, named relative to the grid's (an earlier hivex wrote it whole: its last
    part is the folder's name), so a moved grid keeps one row per point."""
    earlier = json.loads(table.read_text()) if table.is_file() else []
    ours = {row["run_dir"] for row in results}
    kept = [row | {"run_dir": Path(row["run_dir"]).name} for row in earlier
            if isinstance(row.get("run_dir"), str) and Path(row["run_dir"]).name not in ours]
    return sorted([*kept, *results], key=lambda row: row["run_dir"])


def shared_cores(cfg: PPOConfig, jobs: int) -> PPOConfig:
    """``cfg`` for one of ``jobs`` points training at once: ``auto`` torch threads become its share of the
    cores (at least one); a number written down stays."""
    if cfg.torch_threads != "auto":
        return cfg
    return cfg.model_copy(update={"torch_threads": max(1, cfg.threads() // jobs)})


def _in_processes(work: list[tuple], modes: list[tuple[bool, bool]], jobs: int) -> list[dict[str, Any]]:
    """Train the points ``jobs`` at a time, each in a fresh (spawned) process, in their order; -> the summaries
    of the points trained, in grid order. Ctrl-C or SIGTERM stops the points under way after their update (each
    keeps its checkpoint) and starts no other; a point that fails stops the grid the same way, then raises."""
    context = get_context("spawn")
    finished, stop_points = context.Queue(), context.Event()
    waiting, running, results = list(range(len(work))), {}, {}
    failure: BaseException | None = None
    with StopRequests() as stop:
        while waiting or running:
            if stop.requested or failure is not None:
                waiting.clear()
                stop_points.set()  # the points under way finish their update and save; no signal cuts a write
            while waiting and len(running) < jobs:
                index = waiting.pop(0)
                running[index] = context.Process(target=_point_in_process, args=(finished, stop_points, index,
                                                                                 work[index], *modes[index],
                                                                                 os.getpid()))
                running[index].start()
            try:
                index, outcome, value = finished.get(timeout=0.5)
            except queue.Empty:
                failure = failure or _died(running)
                continue
            running.pop(index).join()
            if outcome == "error":
                failure = failure or value
            else:
                results[index] = value
                stop.requested = stop.requested or value["stopped_early"]
    if failure is not None:
        raise failure
    return [results[i] for i in sorted(results)]


def _died(running: dict[int, Any]) -> BaseException | None:
    """A point's process that ended without reporting (killed, out of memory), as an error naming it."""
    for index, process in list(running.items()):
        if not process.is_alive() and process.exitcode not in (0, None):
            running.pop(index)
            return TrainError(f"grid point {index} stopped without a result (its process exited with "
                              f"{process.exitcode}); its run directory keeps its last checkpoint")
    return None


def _point_in_process(finished: Any, stop_points: Any, index: int, job: tuple, resume: bool,
                      overwrite: bool, parent: int) -> None:
    """A spawned process's work: one point, its summary (or its error) put on ``finished``. Ctrl-C reaches
    the whole process group: the parent asks the point to stop through ``stop_points``, so here it is ignored
    outside training (inside, training's own handler stops after the update, as the parent's request does).
    It ends with its ``parent`` however that ends (:func:`end_with_parent`)."""
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    end_with_parent(parent)
    try:
        summary = train_point(*job, progress=False, resume=resume, overwrite=overwrite, stop_event=stop_points)
        finished.put((index, "result", summary))
    except BaseException as error:  # noqa: BLE001 - reported to the parent, which raises it
        try:
            pickle.loads(pickle.dumps(error))
        except Exception:  # an error that does not travel goes as its text
            error = TrainError(f"grid point {index} failed:\n{traceback.format_exc()}")
        finished.put((index, "error", error))


def end_with_parent(parent: int, poll_s: float = 0.5) -> None:
    """SIGTERM this process once when ``parent`` (its pid) ends, even by SIGKILL, which no handler of the parent's
    sees: a point's training then stops after its update and keeps its checkpoint, as on Ctrl-C, instead of training
    on for hours orphaned. Call it from the main thread.

    On Linux the kernel signals the parent's death (prctl PR_SET_PDEATHSIG), but again each time a thread of the
    process that adopted the orphan ends (PID 1 here is multi-threaded), and a second SIGTERM after training's
    handler is gone cuts the final save: so the kernel sends SIGUSR2, whose handler disarms it and sends the one
    SIGTERM. Elsewhere a daemon thread watches for the process to be handed to another parent."""
    if _kernel_signals_parent_death():
        if os.getppid() != parent:  # it ended before the request was made
            _parent_died()
        return
    threading.Thread(target=_signal_when_orphaned, args=(parent, poll_s), daemon=True, name="end-with-parent").start()


def _kernel_signals_parent_death() -> bool:
    """Ask Linux to send SIGUSR2 when the parent ends (handled by :func:`_parent_died`); -> whether it will."""
    if not sys.platform.startswith("linux"):
        return False
    import ctypes

    signal.signal(signal.SIGUSR2, _parent_died)
    try:
        return ctypes.CDLL(None, use_errno=True).prctl(PR_SET_PDEATHSIG, signal.SIGUSR2, 0, 0, 0) == 0
    except (OSError, AttributeError):
        signal.signal(signal.SIGUSR2, signal.SIG_DFL)
        return False


PR_SET_PDEATHSIG = 1


def _parent_died(*_: Any) -> None:
    """The parent is gone: no more death signals, and one SIGTERM (training stops after its update)."""
    import ctypes

    ctypes.CDLL(None, use_errno=True).prctl(PR_SET_PDEATHSIG, 0, 0, 0, 0)
    os.kill(os.getpid(), signal.SIGTERM)


def _signal_when_orphaned(parent: int, poll_s: float) -> None:
    while os.getppid() == parent:
        time.sleep(poll_s)
    os.kill(os.getpid(), signal.SIGTERM)


def _on_ray(jobs: list[tuple], modes: list[tuple[bool, bool]], address: str,
            init: dict[str, Any]) -> list[dict[str, Any]]:
    try:
        import ray
    except ImportError:
        raise TrainError("--ray needs the ray package: pip install 'hivex-dsl[ray]'") from None
    started = not ray.is_initialized()
    handlers = {sig: signal.getsignal(sig) for sig in (signal.SIGINT, signal.SIGTERM)}
    if started:
        ray.init(address=None if address == "local" else address, include_dashboard=False,
                 log_to_driver=False, **init)
    try:
        remote = ray.remote(num_cpus=1)(train_point)
        return ray.get([remote.remote(*job, progress=False, resume=again, overwrite=replace)
                        for job, (again, replace) in zip(jobs, modes)])
    finally:
        if started:
            ray.shutdown()
            _restore(handlers)  # ray.init ignores SIGINT and takes SIGTERM in the driver, and shutdown leaves them so


def _restore(handlers: dict[int, Any]) -> None:
    """Put back the signal handlers a library replaced (only the main thread may set them)."""
    if threading.current_thread() is threading.main_thread():
        for sig, handler in handlers.items():
            if handler is not None:
                signal.signal(sig, handler)


def format_table(results: Sequence[dict[str, Any]]) -> str:
    """One line per point: name, agent-steps, wall time, last training return, test return (if evaluated)."""
    lines = [f"{'point':44} {'agent-steps':>12} {'wall s':>8} {'train return':>13} {'test return':>20}"]
    for r in results:
        train_return = "-" if r.get("final_return") is None else f"{r['final_return']:.2f}"
        test = r.get("test_return")
        test_text = "-" if not test else f"{test['mean']:.2f} ± {test['std']:.2f}"
        lines.append(f"{r['scenario'][:44]:44} {r['agent_steps']:>12} {r['wall_s']:>8.1f} {train_return:>13} "
                     f"{test_text:>20}")
    return "\n".join(lines)
