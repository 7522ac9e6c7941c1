"""Headless Chromium through playwright, for tests that look at what a browser draws.

The ``browser`` fixture is shared through ``conftest.py``; tests using it are skipped,
with the reason, when playwright or Debian's chromium is missing.
"""

import io
import os
import shutil

import numpy as np
import pytest

CHROMIUM = os.environ.get("ISOTWEEN_CHROMIUM") or shutil.which("chromium") or "/usr/bin/chromium"
ARGS = ["--no-sandbox", "--disable-gpu", "--disable-background-networking", "--disable-component-update",
        "--disable-sync"]


@pytest.fixture(scope="module")
def browser():
    """A playwright Browser on the system chromium (module scope: one start per file)."""
    if not os.path.exists(CHROMIUM):
        pytest.skip("chromium is not installed (apt-get install chromium)")
    sync_api = pytest.importorskip("playwright.sync_api", reason="playwright is not installed (the test extra)")
    with sync_api.sync_playwright() as p:
        b = p.chromium.launch(executable_path=CHROMIUM, args=ARGS)
        try:
            yield b
        finally:
            b.close()


def screenshot(page, selector=None):
    """(H, W, 3) uint8 pixels of the page (or of one element)."""
    from PIL import Image

    target = page.locator(selector) if selector else page
    with Image.open(io.BytesIO(target.screenshot())) as im:
        return np.asarray(im.convert("RGB"))
