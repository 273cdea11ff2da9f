"""`hivex render`: small GIFs (one palette shared by every frame) of every --frame-step-th decision.

The size bound: one bit per pixel and frame, an eighth of the 8-bit palette indices a GIF holds before LZW.
Per-frame palettes with dithering (Pillow's default, what `hivex render` wrote before) took about two bits on
Wind Farm Control, whose wind field shifts a little every frame: the dither noise changed every pixel every time
(6.3 MB for the 121 frames of a render then). One undithered palette takes about 0.6 bits.
"""

from __future__ import annotations

import math

import pytest
from PIL import Image

from hivex_dsl.cli import FRAME_STEP, main

WFC = "wind_farm_control/main"


def rendered(path) -> tuple[int, int, int]:
    """(frames, width, height) of a GIF."""
    with Image.open(path) as im:
        return im.n_frames, *im.size


@pytest.mark.parametrize("steps, step", [(600, None), (40, 7)])
def test_a_render_keeps_every_nth_frame_under_a_bit_per_pixel(steps, step, tmp_path, capsys):
    out = tmp_path / "wfc.gif"
    args = ["render", WFC, "-o", str(out), "--steps", str(steps)] + (["--frame-step", str(step)] if step else [])
    assert main(args) == 0
    frames, width, height = rendered(out)
    assert frames == math.ceil((steps + 1) / (step or FRAME_STEP))  # states 0..steps, every step-th kept
    assert out.stat().st_size < frames * width * height / 8
    assert f"({frames} frames)" in capsys.readouterr().out


def test_every_is_the_old_name_of_frame_step(tmp_path, capsys):
    out = tmp_path / "wfc.gif"
    assert main(["render", WFC, "-o", str(out), "--steps", "12", "--every", "4"]) == 0
    assert rendered(out)[0] == 4


@pytest.mark.parametrize("args, message", [
    (["--frame-step", "0"], "argument --frame-step/--every: expected a positive integer, got 0"),
    (["--frame-step", "x"], "argument --frame-step/--every: expected a positive integer, got 'x'"),
])
def test_a_frame_step_that_is_not_a_positive_integer_is_a_usage_error(args, message, tmp_path, capsys):
    with pytest.raises(SystemExit) as stopped:
        main(["render", WFC, "-o", str(tmp_path / "wfc.gif"), *args])
    assert stopped.value.code == 2
    assert capsys.readouterr().err.rstrip().endswith(f"error: {message}")


def test_a_frame_step_past_the_steps_is_refused_before_anything_is_played(tmp_path, capsys):
    out = tmp_path / "wfc.gif"
    assert main(["render", WFC, "-o", str(out), "--steps", "40", "--frame-step", "50"]) == 2
    assert capsys.readouterr().err == ("hivex: --frame-step 50 is more than --steps 40: the GIF would hold the first "
                                       "frame only; give a step of at most 40\n")
    assert not out.exists()
