"""Tests for hivex_dsl.sim.render.gif: round trips through Pillow and argument checking."""

import numpy as np
import pytest
from PIL import Image

from hivex_dsl.sim.render.canvas import Canvas
from hivex_dsl.sim.render.gif import save_gif, save_png

FLAT_COLOURS = [(255, 255, 255), (200, 30, 30), (30, 30, 200), (20, 160, 60)]


def flat_frames(height: int = 12, width: int = 20) -> list[np.ndarray]:
    """Distinct frames made of few flat colours, so palette quantisation is lossless."""
    frames = []
    for k in range(1, len(FLAT_COLOURS)):
        frame = np.empty((height, width, 3), dtype=np.uint8)
        frame[...] = FLAT_COLOURS[0]
        frame[:, : 5 * k] = FLAT_COLOURS[k]  # a coloured band whose width grows each frame
        frames.append(frame)
    return frames


def read_gif_frames(path) -> list[np.ndarray]:
    with Image.open(path) as im:
        frames = []
        for index in range(im.n_frames):
            im.seek(index)
            frames.append(np.asarray(im.convert("RGB")))
        return frames


def test_gif_round_trip_keeps_frames_size_and_colours(tmp_path):
    frames = flat_frames()
    path = tmp_path / "anim.gif"
    assert save_gif(frames, path, fps=20.0) == 3
    with Image.open(path) as im:
        assert im.format == "GIF"
        assert im.n_frames == 3
        assert im.size == (20, 12)  # Pillow reports (width, height)
        assert im.info["duration"] == 50
        assert im.info["loop"] == 0
    decoded = read_gif_frames(path)
    for original, back in zip(frames, decoded):
        assert back.shape == original.shape
        assert np.abs(back.astype(int) - original.astype(int)).max() <= 8


def test_gif_of_a_canvas_drawing_keeps_its_layout(tmp_path):
    canvas = Canvas(32, 1.0)
    canvas.disks(np.array([[0.0, 0.5]]), 0.3, (200, 30, 30))  # in the upper half
    frames = [canvas.image()]
    canvas.disks(np.array([[0.0, -0.5]]), 0.3, (30, 30, 200))
    frames.append(canvas.image())
    path = tmp_path / "canvas.gif"
    save_gif(iter(frames), path, fps=10, loop=2)  # any iterable works
    first, second = read_gif_frames(path)
    assert np.abs(first[8, 16].astype(int) - [200, 30, 30]).max() <= 8
    assert np.abs(first[24, 16].astype(int) - [255, 255, 255]).max() <= 8
    assert np.abs(second[24, 16].astype(int) - [30, 30, 200]).max() <= 8


def test_png_round_trip_is_exact(tmp_path):
    rng = np.random.default_rng(0)
    frame = rng.integers(0, 256, size=(7, 9, 3), dtype=np.uint8)
    path = tmp_path / "frame.png"
    save_png(frame, str(path))
    with Image.open(path) as im:
        np.testing.assert_array_equal(np.asarray(im.convert("RGB")), frame)


@pytest.mark.parametrize(
    "frames",
    [
        [],
        iter(()),
        [np.zeros((4, 4, 3), np.uint8), np.zeros((4, 5, 3), np.uint8)],  # mismatched shapes
        [np.zeros((4, 4, 3), np.float64)],                                # wrong dtype
        [np.zeros((4, 4), np.uint8)],                                     # not RGB
        np.zeros((4, 4, 3), np.uint8),                                    # one frame, not a sequence
    ],
)
def test_save_gif_rejects_bad_frames(tmp_path, frames):
    path = tmp_path / "bad.gif"
    with pytest.raises(ValueError):
        save_gif(frames, path)
    assert not path.exists()


@pytest.mark.parametrize("fps, loop", [(0.0, 0), (-5.0, 0), (float("nan"), 0), (20.0, -1), (20.0, 1.5)])
def test_save_gif_rejects_bad_timing(tmp_path, fps, loop):
    with pytest.raises(ValueError):
        save_gif(flat_frames(), tmp_path / "bad.gif", fps=fps, loop=loop)


def test_missing_directory_is_an_error_not_created(tmp_path):
    missing = tmp_path / "no" / "such" / "dir"
    with pytest.raises(FileNotFoundError, match="does not exist"):
        save_gif(flat_frames(), missing / "anim.gif")
    with pytest.raises(FileNotFoundError):
        save_png(flat_frames()[0], missing / "frame.png")
    assert not (tmp_path / "no").exists()


def test_save_png_rejects_bad_frame(tmp_path):
    with pytest.raises(ValueError):
        save_png(np.zeros((4, 4, 4), np.uint8), tmp_path / "bad.png")
