"""cpu_kernels: what `portable` pins in a process, that it computes as the environment variables it stands for, and
the clear refusals where a process cannot be pinned. Each case runs in a fresh Python: MKL and ATen keep the code
path of their first product for the life of a process, and this one has computed already."""

from __future__ import annotations

import json
import os
import subprocess
import sys
import textwrap
from pathlib import Path

import pytest

from hivex_dsl.train.config import TrainError, make_config, parse_assignments
from hivex_dsl.train.devices import cpu_model
from hivex_dsl.train.kernels import PORTABLE_ENVIRONMENT, words_of_mode

ROOT = Path(__file__).resolve().parents[2]
KERNEL_VARIABLES = ("MKL_CBWR", "ATEN_CPU_CAPABILITY")

PRODUCT = """
import hashlib, torch
generator = torch.Generator().manual_seed(0)
a, b = torch.randn(257, 513, generator=generator), torch.randn(513, 129, generator=generator)
hidden = torch.tanh(a @ b) @ torch.randn(129, 65, generator=generator)
print(hashlib.sha256(hidden.numpy().tobytes()).hexdigest())
"""


def python(code: str, **variables: str) -> subprocess.CompletedProcess:
    """``code`` run by a fresh Python of this environment, the kernel variables of this shell cleared and
    ``variables`` set."""
    env = {k: v for k, v in os.environ.items() if k not in KERNEL_VARIABLES} | variables
    return subprocess.run([sys.executable, "-c", textwrap.dedent(code)], capture_output=True, text=True, env=env,
                          cwd=ROOT, timeout=300)


def last_line(done: subprocess.CompletedProcess) -> str:
    assert done.returncode == 0, done.stderr[-2000:]
    return done.stdout.strip().splitlines()[-1]


def test_portable_pins_mkl_s_compatible_path_aten_s_default_kernels_and_no_onednn_inside():
    shown = last_line(python("""
        import json, torch
        from hivex_dsl.train.kernels import cpu_kernels, mkl_mode
        from hivex_dsl.train.devices import machine
        with cpu_kernels("portable"):
            inside = [mkl_mode(), torch.backends.cpu.get_cpu_capability(), torch.backends.mkldnn.enabled, machine()]
        print(json.dumps(inside + [torch.backends.mkldnn.enabled]))
    """))
    mode, capability, onednn_inside, words, onednn_after = json.loads(shown)
    assert mode == 0x10003  # MKL_CBWR_COMPATIBLE | MKL_CBWR_STRICT, as mkl_cbwr.h numbers them
    assert capability == "DEFAULT" and onednn_inside is False and onednn_after is True
    assert "torch's DEFAULT kernels, MKL's compatible path, strict," in words


def test_pinned_in_the_process_a_product_is_the_one_the_environment_variables_give():
    """The variables are what benchmarks/kernel_portability.py measured alike on Intel's and AMD's processors; the
    in-process pin must give their result to the last bit."""
    by_variables = last_line(python(PRODUCT, **PORTABLE_ENVIRONMENT))
    pinned = last_line(python("from hivex_dsl.train.kernels import pin_portable\npin_portable()\n" + PRODUCT))
    assert pinned == by_variables


def test_portable_is_refused_in_a_process_that_computed_natively_and_leaves_it_as_it_was():
    shown = python("""
        import os, torch
        from hivex_dsl.train.config import TrainError
        from hivex_dsl.train.kernels import PORTABLE_MKL, mkl_mode, pin_portable
        torch.randn(64, 64) @ torch.randn(64, 64)
        try:
            pin_portable()
        except TrainError as error:
            print(error)
            print(os.environ.get("ATEN_CPU_CAPABILITY"), mkl_mode() == PORTABLE_MKL)
    """)
    message, left = shown.stdout.strip().splitlines()[-2:] if shown.returncode == 0 else (shown.stderr, "")
    assert message.startswith("cpu_kernels portable must be pinned before this process computes anything")
    assert "train in a process of its own" in message and "MKL_CBWR=COMPATIBLE,STRICT" in message
    assert left == "None False"  # no variable left for the processes it starts, MKL's path untouched


def test_native_is_refused_after_portable_in_one_process():
    done = python("""
        from hivex_dsl.train.kernels import cpu_kernels
        with cpu_kernels("portable"):
            pass
        with cpu_kernels("native"):
            pass
    """)
    assert done.returncode != 0 and "train a native run in a process of its own" in done.stderr


def test_an_environment_asking_for_other_aten_kernels_is_named_not_overridden():
    done = python("from hivex_dsl.train.kernels import pin_portable\npin_portable()", ATEN_CPU_CAPABILITY="avx2")
    assert done.returncode != 0 and "asks for ATEN_CPU_CAPABILITY=avx2: unset it" in done.stderr


INTEL = "Intel" in cpu_model()  # the processor as a run's machine names it


@pytest.mark.parametrize("variable, words", [
    ("COMPATIBLE,STRICT", "MKL's compatible path, strict, "),
    # MKL takes an instruction set's branch on Intel's processors alone; elsewhere it reports its automatic one
    # (session 88, an AMD EPYC of family 25 model 17: mkl_cbwr_get gives 2, and 0x10002 under AVX2,STRICT)
    ("AVX2", "MKL's AVX2 path, " if INTEL else None),
    ("AVX2,STRICT", "MKL's AVX2 path, strict, " if INTEL else "MKL's automatic path, strict, "),
    (None, None)])
def test_the_machine_names_mkl_s_path_where_something_pinned_it(variable, words):
    shown = last_line(python("from hivex_dsl.train.devices import machine\nprint(machine())",
                             **({"MKL_CBWR": variable} if variable else {})))
    assert (words in shown) if words else "MKL's" not in shown


@pytest.mark.parametrize("mode, words", [
    (None, None), (0, None), (2, None),  # no MKL, MKL's default, its automatic branch unpinned
    (0x10002, "MKL's automatic path, strict"),  # strict changes its sums even on the automatic branch
    (3, "MKL's compatible path"), (0x10003, "MKL's compatible path, strict"), (0x1000A, "MKL's AVX2 path, strict"),
    (0x10063, "MKL's branch 99 path, strict")])
def test_mkl_s_modes_read_as_mkl_cbwr_h_names_them(mode, words):
    assert words_of_mode(mode) == words


def test_cpu_kernels_is_a_checked_hyperparameter_native_by_default():
    assert make_config("wind_farm_control").cpu_kernels == "native"
    assert make_config("wind_farm_control", parse_assignments(["cpu_kernels=portable"])).cpu_kernels == "portable"
    with pytest.raises(TrainError, match=r"--set: cpu_kernels: 'fast' is not allowed: expected 'native' or 'portable'"):
        make_config("wind_farm_control", parse_assignments(["cpu_kernels=fast"]))


def test_hivex_train_and_evaluate_run_a_portable_run_as_it_says(tmp_path, capsys):
    run = tmp_path / "run"
    trained = subprocess.run([sys.executable, "-m", "hivex_dsl.cli", "train", "scenarios/wind_farm_control/main.yaml",
                              "--steps", "16000", "--set", "cpu_kernels=portable", "--set", "torch_threads=1",
                              "--no-progress", "-o", str(run)], capture_output=True, text=True, cwd=ROOT, timeout=600,
                             env={k: v for k, v in os.environ.items() if k not in KERNEL_VARIABLES})
    assert trained.returncode == 0, trained.stderr[-2000:]
    assert json.loads((run / "config.json").read_text())["hyperparameters"]["cpu_kernels"] == "portable"
    (machine,) = json.loads((run / "summary.json").read_text())["machines"]
    assert "torch's DEFAULT kernels, MKL's compatible path, strict," in machine
    evaluated = subprocess.run([sys.executable, "-m", "hivex_dsl.cli", "evaluate", str(run / "checkpoint.pt"),
                                "--episodes", "1", "--json"], capture_output=True, text=True, cwd=ROOT, timeout=600)
    assert evaluated.returncode == 0, evaluated.stderr[-2000:]
    assert json.loads(evaluated.stdout)["cpu_kernels"] == "portable"
    # called from Python, `hivex evaluate` cannot start its process again: it says what is needed instead
    from hivex_dsl.cli import main

    assert main(["evaluate", str(run / "checkpoint.pt"), "--episodes", "1"]) == 2
    assert "cpu_kernels portable must be pinned before this process computes" in capsys.readouterr().err
