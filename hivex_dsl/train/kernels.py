"""Which CPU math kernels a run trains with: the processor's own (``native``) or code paths that compute alike on
Intel's and AMD's processors (``portable``).

A run reproduces its record to the last digit only on a processor that takes the same kernels: MKL, ATen and oneDNN
pick theirs by the instruction sets and caches they find, and a last-bit difference in one update grows into another
run (Wind Farm Control's seed 0 parts from its record at 240,040 agent-steps on an Intel Xeon). ``portable`` pins
each library to one code path, in this process, before its first product:

- MKL's Conditional Numerical Reproducibility, the compatible branch, strict (what ``MKL_CBWR=COMPATIBLE,STRICT``
  sets), through ``mkl_cbwr_set``, which torch's own MKL exports as ``mkl_serv_cbwr_set``; MKL keeps a branch for
  the life of the process once it computed, and says so (``MKL_CBWR_ERR_MODE_CHANGE_FAILURE``);
- ATen's vector kernels at their ``default`` capability (what ``ATEN_CPU_CAPABILITY=default`` sets; torch reads it
  at the first dispatch and keeps it);
- oneDNN off (``torch.backends.mkldnn``), so that convolutions take ATen's im2col and MKL's products.

``benchmarks/kernel_portability.py`` measures it (``benchmarks/results/kernel_portability.json``): the first points
of Wind Farm Control's record (an MLP) agree to the last digit on an Intel Xeon and two AMD EPYCs under it, where
they part under ``native``, and so do the first 40 points of Aerial Wildfire Suppression's (under its fire before
session 89) and Drone-Based Reforestation's convolutions and Wildfire Resource Management's MLP
(``kernel_portability_<environment>*.json``, each naming the fingerprint of the scenario its rows trained) on an
Intel Xeon and an AMD EPYC. The price is speed (the README's training section; the results file's notes). NumPy's
kernels need no pin: its exp, log, arctan2 and ** take AVX-512 kernels where the processor has them and libm's
elsewhere, so the simulators compute those with :mod:`hivex_dsl.base.portable`, which reaches libm on every
processor (tests/test_portable_math.py imitates AVX2-only and SSE4.2-only processors by
``NPY_DISABLE_CPU_FEATURES``). A GPU's own kernels are another matter: ``portable`` pins the CPU's only. `hivex
evaluate` plays a checkpoint under the kernels it trained with; the other commands that play one (render, replay,
audit) compute with their process's own.
"""

from __future__ import annotations

import contextlib
import ctypes
import os
from pathlib import Path
from typing import Iterator

import torch

from .config import CpuKernels, TrainError

MKL_CBWR_BRANCH = 1  # mkl_cbwr_get's argument: the branch alone
MKL_CBWR_ALL = -1  # ~0: the branch and its flags
MKL_CBWR_COMPATIBLE = 3
MKL_CBWR_STRICT = 0x10000
MKL_CBWR_SUCCESS = 0
PORTABLE_MKL = MKL_CBWR_COMPATIBLE | MKL_CBWR_STRICT
PORTABLE_ENVIRONMENT = {"MKL_CBWR": "COMPATIBLE,STRICT", "ATEN_CPU_CAPABILITY": "default"}  # the same, set outside
MKL_BRANCHES = {2: "automatic", 3: "compatible", 4: "SSE2", 6: "SSSE3", 7: "SSE4.1", 8: "SSE4.2", 9: "AVX",
                10: "AVX2", 11: "AVX-512 (Xeon Phi)", 12: "AVX-512", 13: "AVX-512 E1 (Xeon Phi)",
                14: "AVX-512 E1"}  # mkl_cbwr.h

_portable_since: list[bool] = []  # set once this process pinned the portable paths (they cannot be undone)


def _mkl() -> ctypes.CDLL | None:
    """torch's CPU library with MKL's reproducibility calls, or None where this torch has no MKL (ARM, macOS) or does
    not export them."""
    if not torch.backends.mkl.is_available():
        return None
    for name in ("libtorch_cpu.so", "libtorch_cpu.dylib", "torch_cpu.dll"):
        path = Path(torch.__file__).parent / "lib" / name
        if path.is_file():
            try:
                library = ctypes.CDLL(str(path))
                library.mkl_serv_cbwr_get.restype = library.mkl_serv_cbwr_set.restype = ctypes.c_int
                return library
            except (OSError, AttributeError):
                return None
    return None


def mkl_mode() -> int | None:
    """MKL's reproducibility mode in this process (branch and flags, ``mkl_cbwr_get(MKL_CBWR_ALL)``), None without
    MKL."""
    library = _mkl()
    return None if library is None else library.mkl_serv_cbwr_get(MKL_CBWR_ALL)


def mkl_words() -> str | None:
    """MKL's code path in words where something pinned it ("MKL's compatible path, strict"), None where MKL picks
    by the processor (its default) or there is no MKL."""
    return words_of_mode(mkl_mode())


def words_of_mode(mode: int | None) -> str | None:
    """:func:`mkl_words` of the mode ``mkl_cbwr_get(MKL_CBWR_ALL)`` returned. MKL's automatic branch (2) is its
    default, and what it reports on a processor not Intel's when asked for an instruction set's branch (MKL_CBWR=AVX2
    on an AMD EPYC): named only where the strict flag is set, which changes its sums."""
    if mode is None:
        return None
    branch, strict = mode & 0xFFFF, bool(mode & MKL_CBWR_STRICT)
    if branch in (0, 1) or (branch == 2 and not strict):
        return None
    return f"MKL's {MKL_BRANCHES.get(branch, f'branch {branch}')} path" + (", strict" if strict else "")


def pin_portable() -> None:
    """Pin this process's CPU kernels to the portable paths (module docstring), or a clear error where it has
    computed with other ones already, changing nothing then. Idempotent. ATen first: any product dispatches through
    it, so a process that computed is refused there, before MKL's path is touched."""
    library = _mkl()
    if library is None:
        raise TrainError("cpu_kernels portable pins MKL's compatible code path, and this torch has no MKL (or does "
                         "not export its mkl_cbwr calls): train with cpu_kernels native here")
    asked = os.environ.get("ATEN_CPU_CAPABILITY")
    if asked is not None and asked.lower() != "default":
        raise TrainError(f"cpu_kernels portable runs ATen's default kernels, and this process's environment asks for "
                         f"ATEN_CPU_CAPABILITY={asked}: unset it, or train with cpu_kernels native")
    os.environ["ATEN_CPU_CAPABILITY"] = "default"  # read at torch's first dispatch, if it is still to come
    capability = torch.backends.cpu.get_cpu_capability()
    if capability != "DEFAULT":
        if asked is None:  # not left behind for the processes this one starts
            del os.environ["ATEN_CPU_CAPABILITY"]
        raise TrainError(_too_late(f"torch has dispatched to its {capability} kernels"))
    if library.mkl_serv_cbwr_get(MKL_CBWR_ALL) != PORTABLE_MKL:
        if library.mkl_serv_cbwr_set(PORTABLE_MKL) != MKL_CBWR_SUCCESS:
            raise TrainError(_too_late("MKL has computed in its " + (mkl_words() or "processor's own") + " path"))
    _portable_since.append(True)


def _too_late(what: str) -> str:
    settings = " ".join(f"{k}={v}" for k, v in PORTABLE_ENVIRONMENT.items())
    return (f"cpu_kernels portable must be pinned before this process computes anything with torch, and {what}, "
            "which it keeps for the life of the process: train in a process of its own (`hivex train` is one), or "
            f"start Python with {settings} in its environment")


@contextlib.contextmanager
def cpu_kernels(setting: CpuKernels) -> Iterator[None]:
    """Within: torch computes on the CPU with ``setting``'s kernels. ``portable`` pins them for the rest of the
    process (:func:`pin_portable`) and turns oneDNN off inside the block (restored after); ``native`` refuses a
    process pinned portable, whose paths cannot be undone."""
    if setting == "native":
        if _portable_since:
            raise TrainError("this process pinned cpu_kernels portable for an earlier run, and MKL keeps its code "
                             "path for the life of the process: train a native run in a process of its own")
        yield
        return
    pin_portable()
    before = torch.backends.mkldnn.enabled
    torch.backends.mkldnn.enabled = False
    try:
        yield
    finally:
        torch.backends.mkldnn.enabled = before
