"""The torch device a run trains or a checkpoint plays on, and the machine it ran on in words."""

from __future__ import annotations

import contextlib
import os
import platform
from pathlib import Path
from typing import Iterator

import torch

from .config import DEVICES, TrainError
from .kernels import mkl_words


def torch_device(name: str) -> torch.device:
    """A torch device that exists here, or a clear error: ``cpu``, ``cuda`` or ``cuda:N``, which the
    training loop is written and tested for (torch's other device types are refused, not tried)."""
    try:
        device = torch.device(name)
    except RuntimeError:
        device = None
    if device is None or device.type not in ("cpu", "cuda"):
        raise TrainError(f"unknown device {name!r}: expected {DEVICES}")
    if device.type == "cuda" and not torch.cuda.is_available():
        raise TrainError(f"device {name} was asked for, but torch sees no CUDA GPU here (use --device cpu)")
    if device.index is not None and device.index >= torch.cuda.device_count():
        count = torch.cuda.device_count()
        raise TrainError(f"device {name} was asked for, but torch sees {count} CUDA GPU{'s' * (count != 1)} "
                         f"here (cuda:0 to cuda:{count - 1})")
    return device


def autocast(precision: str, device: torch.device) -> contextlib.AbstractContextManager:
    """The forward passes' context: bfloat16 autocast for ``bf16``, nothing otherwise (``exact`` and ``tf32``,
    whose float32 tensors take TensorFloat-32 products through :func:`matmul_precision` instead)."""
    if precision == "bf16":
        return torch.autocast(device_type=device.type, dtype=torch.bfloat16)
    return contextlib.nullcontext()


@contextlib.contextmanager
def matmul_precision(precision: str) -> Iterator[None]:
    """Within: CUDA matrix products and cuDNN convolutions in TensorFloat-32 for ``tf32`` (torch's flags are
    process-wide, so they are restored on the way out); nothing changes for the other precisions."""
    if precision != "tf32":
        yield
        return
    before = torch.backends.cuda.matmul.allow_tf32, torch.backends.cudnn.allow_tf32
    torch.backends.cuda.matmul.allow_tf32 = torch.backends.cudnn.allow_tf32 = True
    try:
        yield
    finally:
        torch.backends.cuda.matmul.allow_tf32, torch.backends.cudnn.allow_tf32 = before


def machine(device: str = "cpu") -> str:
    """The machine in words: processor (its model and the kernels torch picks on it), cores, OS, Python, and the GPU
    when ``device`` is a CUDA one. A run reproduces its record to the digit only on a processor taking the same
    kernels: MKL and torch pick them by the instruction sets they find, and a last-bit difference in one update
    grows into another run (WFC's seed 0 left its record at 240k agent-steps on an AVX-512 Xeon). MKL's code path is
    named where something pinned it (``cpu_kernels portable``, or MKL_CBWR in the environment)."""
    processor = platform.processor() or platform.machine()
    pinned = mkl_words()
    words = (f"{processor}, {cpu_model()}, torch's {torch.backends.cpu.get_cpu_capability()} kernels, "
             + (f"{pinned}, " if pinned else "")
             + f"{os.cpu_count()} cores, {platform.system()}, Python {platform.python_version()}")
    if device.startswith("cuda"):
        words += f", {torch.cuda.get_device_name(torch.device(device))} (torch {torch.__version__})"
    return words


def cpu_model(cpuinfo: Path = Path("/proc/cpuinfo")) -> str:
    """The first processor's model as the kernel reports it in ``cpuinfo``: its name, with its family and model
    numbers where given (a virtual machine's name is often generic: "Intel(R) Xeon(R) Processor"), or "an
    unnamed processor" where there is no such file or name (not Linux, some ARM boards)."""
    try:
        text = cpuinfo.read_text()
    except OSError:
        return "an unnamed processor"
    first = {}
    for line in text.split("\n\n", 1)[0].splitlines():
        key, colon, value = line.partition(":")
        if colon:
            first[key.strip()] = value.strip()
    name = first.get("model name") or "an unnamed processor"
    numbers = " ".join(f"{word} {first[key]}" for key, word in (("cpu family", "family"), ("model", "model"))
                       if first.get(key))
    return f"{name} {numbers}" if numbers else name
