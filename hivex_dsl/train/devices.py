"""The torch device a run trains or a checkpoint plays on."""

from __future__ import annotations

import contextlib
from typing import Iterator

import torch

from .config import DEVICES, TrainError


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
