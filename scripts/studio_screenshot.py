"""The README's screenshot of isotween studio: docs/gallery/studio.png.

Opens the 'regions' example ('j' into 'B') in headless Chromium, pauses on an
in-between, drags one point (the frame becomes a key) and takes the picture.

Usage: python scripts/studio_screenshot.py [OUT]
"""

import sys
from pathlib import Path

HERE = Path(__file__).parent
sys.path.insert(0, str(HERE.parent / "tests"))

from browser import ARGS, CHROMIUM  # noqa: E402


def main():
    from playwright.sync_api import sync_playwright

    from isotween.studio import StudioServer

    out = Path(sys.argv[1]) if len(sys.argv) > 1 else HERE.parent / "docs" / "gallery" / "studio.png"
    server = StudioServer().start()
    try:
        with sync_playwright() as p:
            browser = p.chromium.launch(executable_path=CHROMIUM, args=ARGS)
            page = browser.new_page(viewport={"width": 1280, "height": 760})
            page.goto(server.url)
            page.wait_for_function("window.__studio && window.__studio.ready")
            page.select_option("#example", "regions")
            page.wait_for_function("window.__studio.seq !== null && !window.__studio.state.preview", timeout=300_000)
            k = page.evaluate("window.__studio.seq.count") // 2
            page.evaluate(f"window.__studio.setFrame({k})")
            x, y = page.evaluate(f"window.__studio.vertexOnPage({k}, 0)")
            page.mouse.move(x, y)
            page.mouse.down()
            for step in range(1, 6):
                page.mouse.move(x - 12 * step, y - 8 * step)
                page.wait_for_timeout(40)
            page.mouse.up()
            page.wait_for_function("window.__studio.seq.keys.length === 3", timeout=60_000)
            page.evaluate(f"window.__studio.setFrame({k})")
            page.screenshot(path=str(out))
            browser.close()
    finally:
        server.stop()
    print(out)


if __name__ == "__main__":
    main()
