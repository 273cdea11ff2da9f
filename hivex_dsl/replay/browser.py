"""A headless system Chromium driven by Playwright's Python package: what the replay page's browser tests and its
docs screenshot use. Nothing here downloads a browser: it runs the one installed (Debian's ``chromium``), found at
``$HIVEX_CHROMIUM`` or on the PATH, through ``executable_path`` (never ``playwright install``)."""

from __future__ import annotations

import os
import shutil
from contextlib import contextmanager
from pathlib import Path
from typing import Iterator, Optional

from ..base.errors import HivexError

FLAGS = ("--headless", "--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run",
         "--disable-background-networking", "--disable-component-update", "--disable-sync")
NAMES = ("chromium", "chromium-browser", "google-chrome")


def find_chromium() -> Optional[str]:
    """The browser to run: ``$HIVEX_CHROMIUM`` if set (None if it is no executable), else the first of :data:`NAMES`
    on the PATH; None if none."""
    chosen = os.environ.get("HIVEX_CHROMIUM")
    if chosen:
        return shutil.which(chosen)
    return next((found for found in map(shutil.which, NAMES) if found), None)


@contextmanager
def chromium(executable: Optional[str] = None) -> Iterator[object]:
    """A launched headless browser (a Playwright ``Browser``), closed after the block."""
    try:
        from playwright.sync_api import sync_playwright
    except ImportError:
        raise HivexError("the browser needs the playwright package: pip install 'hivex-dsl[browser]'") from None
    path = executable or find_chromium()
    if path is None:
        raise HivexError("no Chromium found: install Debian's chromium (apt-get install chromium) or set "
                         "HIVEX_CHROMIUM to a Chromium executable")
    with sync_playwright() as playwright:
        browser = playwright.chromium.launch(executable_path=path, args=list(FLAGS))
        try:
            yield browser
        finally:
            browser.close()


def open_page(browser: object, page_path: Path, width: int = 1400, height: int = 1000) -> tuple[object, list[str]]:
    """``page_path`` opened from disk (a file:// URL) in a new page, its script done (the body's data-ready); ->
    the page and a live list of its console errors and uncaught exceptions. Any request off the disk is refused,
    so a page that needs the network fails to load."""
    page = browser.new_page(viewport={"width": width, "height": height})
    errors: list[str] = []
    page.on("console", lambda message: errors.append(message.text) if message.type == "error" else None)
    page.on("pageerror", lambda error: errors.append(str(error)))
    page.route(lambda url: not url.startswith(("file:", "data:", "blob:")), lambda route: route.abort())
    page.goto(Path(page_path).resolve().as_uri())
    page.wait_for_selector("body[data-ready='true']", timeout=30_000)
    return page, errors


__all__ = ["FLAGS", "chromium", "find_chromium", "open_page"]
