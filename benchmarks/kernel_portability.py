"""Which math-kernel settings make a training run the same on every processor: a main record's first points.

    python benchmarks/kernel_portability.py [--env ID] [--points 8] [--setting NAME ...] [-o RESULTS]
    python benchmarks/kernel_portability.py --report [RESULTS]   # a results file's machines, setting by setting

RESULTS: benchmarks/results/kernel_portability.json for Wind Farm Control (the default, an MLP), and
kernel_portability_<ID>.json for another environment's main scenario (Aerial Wildfire Suppression's: convolutions).

A run of `hivex train` reproduces to the digit on an alike processor only: float32 matrix products take the
kernels MKL picks for the processor, and their rounding parts two runs' learning within a few hundred thousand
agent-steps (Wind Farm Control's seed 0 leaves its record's curve at 240,040 agent-steps on an Intel Xeon of
family 6 model 167, and follows it to the digit on the AMD EPYC of family 26 model 2). MKL's Conditional
Numerical Reproducibility (MKL_CBWR) pins one code path; ATen (ATEN_CPU_CAPABILITY) and NumPy choose their own
vector kernels. This script trains a main record's command (seed 0, one torch thread) under each setting in
a fresh process, stops it after --points summary points, and writes each point's return. With -o the rows are
merged into the file, one per machine (``hivex_dsl.train.devices.machine``), so that sessions on other processors
add theirs; --report says, per setting, which machines agree to the last digit. A setting every machine agrees
under is a portable way to train a record. ``portable`` sets no variable: it is `hivex train --set
cpu_kernels=portable`, which pins the paths in the training process itself (hivex_dsl.train.kernels).
``numpy-avx2`` and ``portable-numpy-avx2`` add NumPy's kernels as a processor with AVX2 alone takes them (an AVX-512
processor imitating one by NPY_DISABLE_CPU_FEATURES).

A file names the scenario's fingerprint its rows trained: once a default changes, main.yaml trains something else
under the same path, and a row of it is refused from that file (its rows stay the record of what they trained; a
file whose record was replaced since keeps that record's curve, ``record_curve``).
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import hivex_dsl
from hivex_dsl.base.portable import AVX512_GROUPS
from hivex_dsl.train.devices import machine
from hivex_dsl.train.rundir import dumps

ROOT = Path(__file__).resolve().parents[1]
DEFAULT_ENVIRONMENT = "wind_farm_control"
SETTINGS: dict[str, dict[str, str]] = {
    "default": {},
    "mkl-compatible": {"MKL_CBWR": "COMPATIBLE,STRICT"},
    "mkl-avx2": {"MKL_CBWR": "AVX2,STRICT"},
    "mkl-compatible-aten-default": {"MKL_CBWR": "COMPATIBLE,STRICT", "ATEN_CPU_CAPABILITY": "default"},
    "portable": {},  # no variable: `hivex train` pins the paths itself (cpu_kernels portable, hivex_dsl.train.kernels)
    # NumPy as on a processor with AVX2 alone (its AVX-512 groups off): what such a processor computes where MKL and
    # ATen take one code path on every processor, as under portable (tests/test_portable_math.py)
    "numpy-avx2": {"NPY_DISABLE_CPU_FEATURES": " ".join(AVX512_GROUPS)},
    "portable-numpy-avx2": {"NPY_DISABLE_CPU_FEATURES": " ".join(AVX512_GROUPS)},
}
PORTABLE = ["--set", "cpu_kernels=portable"]
SETTING_ARGUMENTS = {"portable": PORTABLE, "portable-numpy-avx2": PORTABLE}  # beside the record's command
# curve.json is written with each checkpoint: often, so that the first points are read soon (saving draws no random
# number and changes nothing a run learns: WFC's rows are the same with it and without)
SOON = ["--set", "checkpoint_every=10000"]
KERNEL_VARIABLES = ("MKL_CBWR", "ATEN_CPU_CAPABILITY", "MKL_ENABLE_INSTRUCTIONS", "NPY_DISABLE_CPU_FEATURES")


def scenario_of(environment: str) -> str:
    return f"scenarios/{environment}/main.yaml"


def fingerprint_of(environment: str) -> str:
    """What ``environment``'s main scenario trains now, by content: a default changed since a file's rows were measured
    changes it, though the scenario's path stays."""
    return hivex_dsl.compile(scenario_of(environment)).fingerprint


def command_of(environment: str) -> list[str]:
    """The record's command: the main scenario, seed 0, one torch thread (what the records pin)."""
    return ["hivex", "train", scenario_of(environment), "--seed", "0", "--set", "torch_threads=1", "--no-progress"]


def results_file(environment: str) -> Path:
    suffix = "" if environment == DEFAULT_ENVIRONMENT else f"_{environment}"
    return ROOT / "benchmarks" / "results" / f"kernel_portability{suffix}.json"


def first_points(name: str, points: int, environment: str = DEFAULT_ENVIRONMENT, timeout_s: float = 1_800.0
                 ) -> list[float]:
    """The returns of the first ``points`` summary points of ``environment``'s :func:`command_of` trained under the
    setting ``name`` (its environment variables set before torch loads, any of :data:`KERNEL_VARIABLES` the
    caller's shell set cleared; its :data:`SETTING_ARGUMENTS` added to the command)."""
    env = {k: v for k, v in os.environ.items() if k not in KERNEL_VARIABLES} | SETTINGS[name]
    with tempfile.TemporaryDirectory() as scratch:
        curve = Path(scratch) / "run" / "curve.json"
        command = [*command_of(environment), *SETTING_ARGUMENTS.get(name, []), *SOON, "-o", str(Path(scratch) / "run")]
        process = subprocess.Popen(command, cwd=ROOT, env=env,
                                   stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
        start = time.monotonic()
        try:
            while len(read := _curve(curve)) < points:
                if process.poll() is not None:
                    raise RuntimeError(f"training under {name} ended early: {process.stderr.read()[-2000:]}")
                if time.monotonic() - start > timeout_s:
                    raise RuntimeError(f"training under {name} logged {len(read)} points in {timeout_s:.0f} s")
                time.sleep(0.5)
        finally:
            process.kill()
            process.wait()
    return [round(point["return"], 4) for point in read[:points]]


def _curve(path: Path) -> list[dict]:
    try:
        return json.loads(path.read_text(encoding="utf-8"))
    except (FileNotFoundError, json.JSONDecodeError):  # not written yet, or caught mid-write
        return []


def merge(recorded: dict, this_machine: str, measured: dict[str, list[float]], points: int,
          environment: str = DEFAULT_ENVIRONMENT, fingerprint: str | None = None) -> dict:
    """``recorded`` (the results file's content, or {}) with ``this_machine``'s row set to ``measured``'s settings
    (its other settings kept); rows of other machines and the file's notes unchanged. Rows must read the same
    number of points of the same scenario, by path and by content (``fingerprint``, by default what the scenario
    resolves to now)."""
    fingerprint = fingerprint or fingerprint_of(environment)
    if recorded and recorded["points"] != points:
        raise ValueError(f"the file holds {recorded['points']} points a setting, this run {points}: use --points "
                         f"{recorded['points']}")
    if recorded and recorded["scenario"] != scenario_of(environment):
        raise ValueError(f"the file holds {recorded['scenario']}'s points, this run {scenario_of(environment)}'s: "
                         f"write them to {results_file(environment).relative_to(ROOT)}")
    if recorded and recorded.get("fingerprint") != fingerprint:
        raise ValueError(f"the file holds the points of {recorded['scenario']} as it resolved when they were measured "
                         f"(fingerprint {recorded.get('fingerprint')}), this run trains it as it resolves now "
                         f"({fingerprint}): a default changed since. Its rows stay a record of what they trained; "
                         "write these to a file of their own (-o)")
    machines = dict(recorded.get("machines", {}))
    machines[this_machine] = dict(machines.get(this_machine, {})) | measured
    settings = {name: variables | ({"arguments": " ".join(SETTING_ARGUMENTS[name])} if name in SETTING_ARGUMENTS
                                   else {})
                for name, variables in SETTINGS.items()}
    return {"scenario": scenario_of(environment), "fingerprint": fingerprint,
            "command": " ".join(command_of(environment)), "settings": settings, "points": points,
            "notes": recorded.get("notes", []), "machines": machines}


def agreement(recorded: dict) -> dict[str, list[list[str]]]:
    """Per setting, the machines that measured it grouped by identical returns (largest group first): a setting
    with one group over two or more machines reproduces across them."""
    found: dict[str, dict[tuple, list[str]]] = {}
    for name, settings in recorded.get("machines", {}).items():
        for setting, returns in settings.items():
            found.setdefault(setting, {}).setdefault(tuple(returns), []).append(name)
    return {setting: sorted(groups.values(), key=len, reverse=True) for setting, groups in found.items()}


def report(recorded: dict, record_curve: list[float] | None = None) -> list[str]:
    """:func:`agreement` as lines: per setting how many results over how many machines, then each group's returns
    (marked where they are ``record_curve``'s first points) and its machines."""
    lines = []
    for setting, groups in agreement(recorded).items():
        machines = sum(len(group) for group in groups)
        verdict = ("one result" if len(groups) == 1 else f"{len(groups)} different results") + f" on {machines} machine(s)"
        lines.append(f"{setting}: {verdict}")
        for group in groups:
            returns = recorded["machines"][group[0]][setting]
            same = " (the committed record's curve)" if record_curve and returns == record_curve[:len(returns)] else ""
            lines.append(f"  {returns[:8]}{same}: " + "; ".join(group))
    return lines


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--env", default=DEFAULT_ENVIRONMENT, help="whose main scenario (default wind_farm_control)")
    parser.add_argument("--points", type=int, default=8, help="summary points a setting (its summary_freq each)")
    parser.add_argument("--setting", action="append", choices=sorted(SETTINGS), help="only these (repeatable)")
    parser.add_argument("-o", "--output", type=Path, help="merge this machine's row into this JSON file")
    parser.add_argument("--report", type=Path, nargs="?", const=True,
                        help="report a results file's agreement instead of measuring (default --env's file)")
    args = parser.parse_args(argv)
    if args.report:
        recorded = json.loads((results_file(args.env) if args.report is True else args.report).read_text("utf-8"))
        print("\n".join(report(recorded, record_curve(recorded))))
        return 0
    measured = {name: first_points(name, args.points, args.env) for name in args.setting or SETTINGS}
    recorded = json.loads(args.output.read_text(encoding="utf-8")) if args.output and args.output.is_file() else {}
    merged = merge(recorded, machine(), measured, args.points, args.env)
    if args.output:
        args.output.write_text(dumps(merged, args.output, 1), encoding="utf-8")
    print("\n".join(report(merged, record_curve(merged))))
    return 0


def record_curve(recorded: dict) -> list[float] | None:
    """The returns of the record a results file's rows are of, rounded as the rows are: its own ``record_curve``
    where it keeps one (a record replaced since), else the committed record of its scenario (its environment's
    main) while the scenario resolves as when the rows were measured; None otherwise."""
    if "record_curve" in recorded:
        return recorded["record_curve"]
    environment = Path(recorded["scenario"]).parent.name
    if recorded.get("fingerprint") != fingerprint_of(environment):
        return None
    record = ROOT / "benchmarks" / "baselines" / f"{environment}.json"
    return [round(point[2], 4) for point in json.loads(record.read_text(encoding="utf-8"))["curve"]]


if __name__ == "__main__":
    sys.exit(main())
