"""The torch device a run trains or a checkpoint plays on."""

from __future__ import annotations

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
