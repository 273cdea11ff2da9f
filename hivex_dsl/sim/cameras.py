"""Whether a downward camera sends its picture or the blank image the original's runs received.

Every config that ran the original (training and test, ``../shared/paper/original-configs``) sets
``engine_settings: no_graphics: true``, so mlagents-learn started the Unity build with ``-nographics``:
its graphics device is Null and nothing is rendered. ML-Agents' CameraSensor (the build's
Unity.ML-Agents.dll, ``ObservationToTexture``) logs "GraphicsDeviceType is Null. This will likely crash
when trying to render.", renders into a temporary texture and reads it back into its own texture, neither
of which happens without a device, and sends that untouched texture every step (ML-Agents' docs: in
headless mode you cannot collect visual observations). Aerial Wildfire Suppression's planes and
Drone-Based Reforestation's drones see with CameraSensors, so the original's policies learned and were
tested on one constant picture. The value of that picture (a fresh Texture2D's) is not on record; any
constant tells a network nothing, and ``blank`` sends zeros.
"""

from __future__ import annotations

from typing import Any, ClassVar, Literal

import numpy as np
from pydantic import Field

from ..lang.spec.common import StrictModel

CameraImages = Literal["blank", "rendered"]


class CameraParams(StrictModel):
    ADDED_FIELDS: ClassVar[dict[str, Any]] = {"camera_images": "rendered"}  # locks and checkpoints from before drew

    camera_images: CameraImages = Field("blank", description=(
        "[records] 'blank': the camera observation keeps its shape and space but is all zeros, as the original's "
        "runs saw it: every config that ran sets no_graphics true, under which ML-Agents' CameraSensor renders "
        "nothing and sends one unchanged picture (hivex_dsl/sim/cameras.py). 'rendered': the paper's downward "
        "camera, drawn every step (this toolkit's default before issue 52's session 42)."))

    @property
    def cameras_render(self) -> bool:
        return self.camera_images == "rendered"


def blank_images(shape: tuple[int, ...]) -> np.ndarray:
    """float32 zeros of ``shape``: the pictures of cameras that render nothing."""
    return np.zeros(shape, np.float32)
