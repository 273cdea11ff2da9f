"""Write rendered (H, W, 3) uint8 frames to disk as an animated GIF or a PNG (Pillow, imported lazily)."""

from __future__ import annotations

import math
import os
from collections.abc import Iterable, Sequence
from pathlib import Path

import numpy as np

from ...base.errors import is_integer

PALETTE_SAMPLES = 16  # frames the shared palette is drawn from


def _check_frame(frame, index: int, expected_shape: tuple[int, ...] | None = None) -> np.ndarray:
    """Validate one frame: an (H, W, 3) uint8 array, matching expected_shape when given."""
    if not isinstance(frame, np.ndarray):
        raise ValueError(f"frame {index} must be a numpy array, got {type(frame).__name__}")
    if frame.dtype != np.uint8:
        raise ValueError(f"frame {index} must have dtype uint8, got {frame.dtype}")
    if frame.ndim != 3 or frame.shape[2] != 3 or frame.shape[0] < 1 or frame.shape[1] < 1:
        raise ValueError(f"frame {index} must have shape (H, W, 3), got {frame.shape}")
    if expected_shape is not None and frame.shape != expected_shape:
        raise ValueError(f"frame {index} has shape {frame.shape}, but frame 0 has shape {expected_shape}")
    return np.ascontiguousarray(frame)


def _output_path(path: str | os.PathLike) -> Path:
    """The output path, after checking that its directory exists (it is never created)."""
    out = Path(os.fspath(path))
    parent = out.parent if str(out.parent) else Path(".")
    if not parent.is_dir():
        raise FileNotFoundError(f"output directory does not exist: {parent}")
    return out


def save_gif(frames: Sequence[np.ndarray] | Iterable[np.ndarray], path: str | os.PathLike,
             fps: float = 20.0, loop: int = 0) -> int:
    """Write frames, each (H, W, 3) uint8 of one common shape, as an animated GIF.

    fps: frames per second (> 0); each frame lasts round(1000 / fps) milliseconds (at least 1;
    GIF stores centiseconds). loop: 0 repeats forever, n > 0 plays n extra times.
    Colours are quantised, without dithering, to one palette of at most 256 colours shared by every frame
    (:func:`shared_palette`): a pixel that did not change keeps its palette index, so each frame after the
    first compresses to little more than what moved. Pillow merges consecutive identical frames into one
    longer frame, so the file may hold fewer frames than were given.
    Returns the number of frames given. Raises ValueError on no frames, bad frames or bad fps/loop,
    FileNotFoundError when the output directory does not exist.
    """
    if not (isinstance(fps, (int, float, np.integer, np.floating)) and math.isfinite(fps) and fps > 0):
        raise ValueError(f"fps must be a finite number > 0, got {fps!r}")
    if not is_integer(loop) or loop < 0:
        raise ValueError(f"loop must be an integer >= 0, got {loop!r}")
    if isinstance(frames, np.ndarray) and frames.ndim == 3:
        raise ValueError("frames must be a sequence of (H, W, 3) arrays, got a single (H, W, 3) array")
    checked: list[np.ndarray] = []
    for index, frame in enumerate(frames):
        checked.append(_check_frame(frame, index, checked[0].shape if checked else None))
    if not checked:
        raise ValueError("save_gif needs at least one frame")
    out = _output_path(path)

    from PIL import Image

    palette = shared_palette(checked)
    images = [Image.fromarray(frame).quantize(palette=palette, dither=Image.Dither.NONE) for frame in checked]
    images[0].save(out, format="GIF", save_all=True, append_images=images[1:],
                   duration=max(1, round(1000.0 / fps)), loop=int(loop), optimize=True)
    return len(checked)


def shared_palette(frames: Sequence[np.ndarray]):
    """A P-mode Pillow image whose palette (at most 256 colours) serves every frame: Pillow's fast octree
    quantiser, undithered, on up to PALETTE_SAMPLES frames spread evenly over the animation.

    Per-frame adaptive palettes with dithering (Pillow's default) made a 121-frame Wind Farm Control render
    6.3 MB: its wind field shifts a little every frame, and the dither noise changed every pixel every time.
    """
    from PIL import Image

    picks = np.unique(np.linspace(0, len(frames) - 1, min(len(frames), PALETTE_SAMPLES)).round().astype(int))
    sample = np.concatenate([frames[i] for i in picks], axis=0)
    return Image.fromarray(sample).quantize(colors=256, method=Image.Quantize.FASTOCTREE, dither=Image.Dither.NONE)


def save_png(frame: np.ndarray, path: str | os.PathLike) -> None:
    """Write one (H, W, 3) uint8 frame as a lossless PNG; FileNotFoundError if the directory is missing."""
    checked = _check_frame(frame, 0)
    out = _output_path(path)

    from PIL import Image

    Image.fromarray(checked).save(out, format="PNG")
