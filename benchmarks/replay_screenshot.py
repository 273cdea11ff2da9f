"""The replay page's screenshot on docs/quickstart.md and docs/replay.md (docs/images/replay.png), taken with the
browser tooling of the page's tests (hivex_dsl.replay.browser: Playwright driving the system's Chromium).

It does what the quickstart says: writes its task, trains it (`hivex train ... --steps 300000`, about a minute on two
busy cores), replays the run (`hivex replay RUN_DIR`), opens the page headless and shows the first decision after
the hundredth at which the trained turbine_0 paid for a rotor turn, so both terms of the task are on screen.

    python benchmarks/replay_screenshot.py [-o docs/images/replay.png] [--keep DIR]
"""

from __future__ import annotations

import argparse
import io
import json
import os
import re
import tempfile
from pathlib import Path

from hivex_dsl.cli import main as hivex
from hivex_dsl.replay.browser import chromium, open_page

ROOT = Path(__file__).resolve().parents[1]
QUICKSTART = ROOT / "docs" / "quickstart.md"
WIDTH, HEIGHT = 1280, 1120  # the top of the page: controls, frame, table and the agent's two charts


def quickstart_task() -> str:
    (task,) = re.findall(r"```yaml\n(.*?)```", QUICKSTART.read_text(), flags=re.S)
    return task


def shown_decision(trace: dict, agent: int = 0, after: int = 100) -> int:
    """The first decision after ``after`` at which ``agent`` paid for a turn (``after`` + 1 if it never did)."""
    turns = trace["weighted"]["rotor_turn"]
    return next((t + 1 for t in range(after, len(turns)) if turns[t][agent] != 0), after + 1)


def screenshot(page_path: Path, decision: int, output: Path) -> None:
    from PIL import Image

    with chromium() as browser:
        page, errors = open_page(browser, page_path, width=WIDTH, height=HEIGHT)
        page.evaluate(f"window.replay.setDecision({decision})")
        png = page.screenshot(clip={"x": 0, "y": 0, "width": WIDTH, "height": HEIGHT})
        if errors:
            raise SystemExit(f"the page logged errors: {errors}")
    image = Image.open(io.BytesIO(png)).convert("RGB")
    image.quantize(colors=256, method=Image.Quantize.FASTOCTREE, dither=Image.Dither.NONE).save(output, optimize=True)


def main(argv=None) -> Path:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("-o", "--output", type=Path, default=ROOT / "docs" / "images" / "replay.png")
    parser.add_argument("--keep", type=Path, help="work in this directory (kept) instead of a temporary one")
    args = parser.parse_args(argv)
    output, home = args.output.resolve(), Path.cwd()
    with tempfile.TemporaryDirectory() as scratch:
        work = args.keep or Path(scratch)
        work.mkdir(parents=True, exist_ok=True)
        os.chdir(work)  # the page shows the paths as the quickstart's reader has them
        task, run = Path("my_task.yaml"), Path("runs") / "my-steady-farm"
        task.write_text(quickstart_task())
        if not (run / "checkpoint.pt").is_file():
            assert hivex(["train", str(task), "-o", str(run), "--steps", "300000", "--no-progress"]) == 0
        page, trace = Path("my-steady-farm.html"), Path("my-steady-farm.json")
        assert hivex(["replay", str(run), "-o", str(page), "--trace", str(trace)]) == 0
        episode = json.loads(trace.read_text())["episodes"][0]
        screenshot(page, shown_decision(episode), output)
        os.chdir(home)
    print(f"wrote {output} ({output.stat().st_size / 1e3:.0f} kB)")
    return output


if __name__ == "__main__":
    main()
