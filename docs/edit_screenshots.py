"""The README's screenshots of ``dgpc edit`` (docs/edit-*.png), taken from the page in a
headless Chromium: the demo wall as the page opens (fabrication figures on), after a drag of a
gizmo's arrow, and after a push along the normal that pleats the net.

    .venv/bin/python docs/edit_screenshots.py
"""

from __future__ import annotations

import io
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np
from PIL import Image
from scipy import ndimage

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "tests"))
from browser import Browser  # noqa: E402

WIDTH, HEIGHT = 1400, 860
#: Colour of a gizmo's y arrow as the page draws it.
ARROW = (120, 216, 155)


def dgpc(*args, **kw):
    return subprocess.Popen([sys.executable, "-m", "dgpc_cli.cli.main", *map(str, args)], **kw)


def pixels(png: bytes) -> np.ndarray:
    return np.asarray(Image.open(io.BytesIO(png)).convert("RGB")).astype(int)


def status(browser) -> str:
    lines = [ln for ln in browser.text().splitlines() if ln.strip().startswith(("✅", "⚠", "⏳"))
             or "converged" in ln or "dragging" in ln or "missed" in ln]
    return lines[0] if lines else ""


def settled(browser, before: str, timeout: float = 600) -> str:
    end = time.monotonic() + timeout
    now = before
    while (now == before or "dragging" in now) and time.monotonic() < end:
        time.sleep(1)
        now = status(browser)
    return now


def js(browser, expression: str):
    return browser.call("Runtime.evaluate", expression=expression, returnByValue=True)


def shot(browser, path: Path) -> np.ndarray:
    """A screenshot once the scene is drawn anew (software WebGL paints slowly; a mouse move
    in a corner asks for a frame)."""
    for k in range(8):
        browser.call("Input.dispatchMouseEvent", type="mouseMoved", x=20 + k, y=HEIGHT - 20)
        time.sleep(2)
    return pixels(browser.screenshot(path))


def main() -> None:
    d = Path(tempfile.mkdtemp())
    subprocess.run([sys.executable, "-m", "dgpc_cli.cli.main", "-q", "init", "--surface",
                    "revolution", "--profile", ROOT / "samples/profiles/wall.csv", "--rows", "21",
                    "--cols", "13", "--span", "60", "--units", "m", "-o", d / "wall"], check=True)
    proc = dgpc("edit", d / "wall", "--mode", "isometric", "--handles",
                ROOT / "samples/handles/wall-21x13.json", "--steps", 5, "-o", d / "mywall",
                stdout=subprocess.PIPE, stderr=subprocess.DEVNULL, text=True)
    url = proc.stdout.readline().strip()
    try:
        with Browser(width=WIDTH, height=HEIGHT) as b:
            b.open(url)
            print("page", url, flush=True)
            b.wait_text("converged", 600)
            print("settled", flush=True)
            time.sleep(3)
            # the notice about software WebGL is about this headless browser, not the page
            js(b, "[...document.querySelectorAll('button')].filter(x => x.closest("
                  "'.mantine-Notification-root')).forEach(x => x.click())")
            b.check()                                  # Fabrication figures
            print("fabrication figures on", flush=True)
            b.wait_text("as planarize-strips and unfold make them", 1200)
            first = status(b)
            im = shot(b, ROOT / "docs" / "edit-page.png")

            # drag the arrow of a gizmo (the largest one seen) outwards a little
            mask = (np.abs(im[:, : int(0.68 * WIDTH)] - np.array(ARROW)) < 14).all(-1)
            labels, count = ndimage.label(mask)
            sizes = ndimage.sum(mask, labels, range(1, count + 1))
            ys, xs = np.nonzero(labels == 1 + int(np.argmax(sizes)))
            pts = np.stack([xs, ys], 1).astype(float)
            centre = np.median(pts, axis=0)
            axis = np.linalg.svd(pts - pts.mean(0), full_matrices=False)[2][0]
            b.call("Input.dispatchMouseEvent", type="mouseMoved", x=float(centre[0]),
                   y=float(centre[1]))
            b.drag(tuple(centre), tuple(centre + 8 * axis), steps=8, pause=0.3)
            after = settled(b, first)
            b.wait_text("as planarize-strips and unfold make them", 1200)
            shot(b, ROOT / "docs" / "edit-drag.png")
            print("after the drag:", after, flush=True)

            # click the middle of the net, push it along the normal by 0.8 edge lengths
            c = js(b, "(() => { const t = document.querySelector('[role=slider]'); const r = "
                      "t.getBoundingClientRect(); const s = t.closest('[class*=Slider-root]')"
                      ".getBoundingClientRect(); return [r.left, r.top, r.width, r.height, "
                      "s.width]; })()")
            x, y, w, h, track = c["result"]["value"]
            grey = np.nonzero((np.abs(im[..., 0] - im[..., 1]) < 12) & (im[..., 0] < 200)
                              & (im[..., 0] > 60) & (np.arange(WIDTH)[None, :] < 0.68 * WIDTH))
            before = status(b)
            b.click(float(np.median(grey[1])), float(np.median(grey[0])))
            b.wait_text("): a handle.", 300)
            before = settled(b, before)
            cx, cy = x + w / 2, y + h / 2
            b.drag((cx, cy), (cx + 0.8 / 6 * track, cy), steps=6, pause=0.3)
            pushed = settled(b, before)
            shot(b, ROOT / "docs" / "edit-pleated.png")
            print("after the push:", pushed)
    finally:
        proc.terminate()
        proc.wait(timeout=30)


if __name__ == "__main__":
    main()
