"""``dgpc edit``: the page in a headless Chromium (Debian's ``chromium``, which ``.ci/run``
installs; missing, the test fails saying so): it shows the net; a mouse drag of a handle's
gizmo arrow (pointer events at the arrow as it is drawn) moves the handle, the net and the
status; a click on a vertex adds a handle; Save writes the artifact; the page listens on this
machine only unless --host is given."""

import io
import json
import socket
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest
from browser import HEIGHT, WIDTH, Browser
from cli_helpers import dgpc, wall_net
from PIL import Image
from scipy import ndimage

ROOT = Path(__file__).resolve().parents[1]
HANDLES = ROOT / "samples" / "handles" / "wall-21x13.json"
#: Seconds the server may take to print its address, at most.
START_TIMEOUT = 120


@pytest.fixture(scope="module")
def wall(tmp_path_factory):
    d = tmp_path_factory.mktemp("edit-page")
    wall_net(d, 21, 13)
    return d


def serve(d: Path, *extra):
    """Start ``dgpc edit`` on the wall; return the process and the address it printed."""
    proc = subprocess.Popen(
        [sys.executable, "-m", "dgpc_cli.cli.main", "edit", str(d / "wall"), "--handles",
         str(HANDLES), "--steps", "5", "-o", str(d / "out"), "--force", *extra],
        stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, cwd=d)
    end = time.monotonic() + START_TIMEOUT
    line = ""
    while not line.startswith("http") and time.monotonic() < end and proc.poll() is None:
        line = proc.stdout.readline().strip()
    if not line.startswith("http"):
        proc.kill()
        raise AssertionError(f"no address on stdout: {line!r} {proc.stderr.read()!r}")
    return proc, line


def stop(proc) -> None:
    proc.terminate()
    try:
        proc.wait(timeout=20)
    except subprocess.TimeoutExpired:
        proc.kill()
        proc.wait(timeout=20)


def status_line(text: str) -> str:
    lines = [ln for ln in text.splitlines() if ln.strip().startswith(("✅", "⚠", "⏳"))
             or "converged" in ln or "dragging" in ln or "missed" in ln]
    return lines[0] if lines else ""


def pixels(png: bytes) -> np.ndarray:
    return np.asarray(Image.open(io.BytesIO(png)).convert("RGB")).astype(int)


def net_pixels(im: np.ndarray) -> tuple[int, int]:
    """Pixels of the net's grey surface and of its red geodesics, left of the panel."""
    net = im[:, : int(0.55 * im.shape[1])]
    grey = (abs(net[..., 0] - net[..., 1]) < 12) & (net[..., 0] < 200) & (net[..., 0] > 60)
    red = (net[..., 0] > 150) & (net[..., 1] < 90) & (net[..., 2] < 90)
    return int(grey.sum()), int(red.sum())


def drawn(browser, path: Path, timeout: float = 180) -> np.ndarray:
    """A screenshot once the net is drawn in full colour (software WebGL fades the scene in
    slowly; a mouse move over the empty canvas asks for a new frame)."""
    end = time.monotonic() + timeout
    k = 0
    while True:
        im = pixels(browser.screenshot(path))
        grey, red = net_pixels(im)
        if grey > 8000 and red > 200:
            return im
        assert time.monotonic() < end, f"the net is not drawn: {grey} grey, {red} red pixels"
        k += 1
        browser.call("Input.dispatchMouseEvent", type="mouseMoved", x=40 + k % 5, y=HEIGHT - 40)
        time.sleep(2)


#: Colour of a gizmo's y arrow as the page draws it (drei's PivotControls, software GL).
ARROW = (120, 216, 155)


def gizmo_arrow(im: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The centre and the on-screen direction (unit) of the largest y arrow of a gizmo seen in
    the net's part of the screenshot ``im``."""
    net = im[:, : int(0.6 * WIDTH)]
    mask = (np.abs(net - np.array(ARROW)) < 14).all(axis=-1)
    labels, count = ndimage.label(mask)
    assert count, "no gizmo arrow on the page"
    sizes = ndimage.sum(mask, labels, range(1, count + 1))
    ys, xs = np.nonzero(labels == 1 + int(np.argmax(sizes)))
    pts = np.stack([xs, ys], axis=1).astype(float)
    centre = np.median(pts, axis=0)
    axis = np.linalg.svd(pts - pts.mean(axis=0), full_matrices=False)[2][0]
    return centre, axis


def test_page_shows_the_net_and_a_drag_changes_it(wall, tmp_path):
    proc, url = serve(wall)
    try:
        assert url.startswith("http://127.0.0.1:")
        with Browser() as browser:
            browser.open(url)
            first = status_line(browser.wait_text("converged", 180))
            before = drawn(browser, tmp_path / "before.png")

            # press on a gizmo's arrow and drag along it, as a designer does with the mouse
            centre, axis = gizmo_arrow(before)
            browser.call("Input.dispatchMouseEvent", type="mouseMoved", x=float(centre[0]),
                         y=float(centre[1]))
            browser.drag(tuple(centre), tuple(centre + 16 * axis), steps=8, pause=0.3)
            end = time.monotonic() + 300
            now = first
            while (now == first or "dragging" in now) and time.monotonic() < end:
                time.sleep(1)
                now = status_line(browser.text())
            assert now != first, "the status did not change after the drag"
            after = drawn(browser, tmp_path / "after.png")
            moved = np.abs(after[:, : int(0.55 * WIDTH)] - before[:, : int(0.55 * WIDTH)])
            assert (moved.sum(axis=-1) > 60).sum() > 500
            assert np.linalg.norm(gizmo_arrow(after)[0] - centre) > 4     # the gizmo moved too

            # click a vertex in the middle of the net: it becomes a handle, selected
            net = after[:, : int(0.55 * WIDTH)]
            grey = np.nonzero((abs(net[..., 0] - net[..., 1]) < 12) & (net[..., 0] < 200)
                              & (net[..., 0] > 60))
            browser.click(float(np.median(grey[1])), float(np.median(grey[0])))
            browser.wait_text("): a handle.", 120)

            browser.call("Runtime.evaluate", expression=(
                "[...document.querySelectorAll('button')].find(b => b.innerText.includes("
                "'Save artifact')).click()"))
            browser.wait_text("Saved", 300)
        saved = json.loads((wall / "out-handles.json").read_text())["handles"]
        start = json.loads(HANDLES.read_text())["handles"]
        assert len(saved) == len(start) + 1
        # one handle's target went where the gizmo was dragged, the others stayed
        targets = {tuple(h["index"]): np.array(h["target"]) for h in saved}
        shifts = sorted(float(np.linalg.norm(targets[tuple(h["index"])] - h["target"]))
                        for h in start)
        assert shifts[-1] > 1e-3 and shifts[-2] < 1e-9, shifts
        art = json.loads((wall / "out.json").read_text())
        assert art["kind"] == "net" and art["inputs"]["handles"]["path"] == "out-handles.json"
    finally:
        stop(proc)


def _outside_address() -> str | None:
    """An address of this machine that is not loopback, if it has one."""
    try:
        with socket.socket(socket.AF_INET, socket.SOCK_DGRAM) as s:
            s.connect(("192.0.2.1", 9))           # TEST-NET: nothing is sent
            address = s.getsockname()[0]
    except OSError:
        return None
    return None if address.startswith("127.") else address


def test_the_page_listens_on_loopback_only_unless_host_is_given(wall):
    proc, url = serve(wall)
    try:
        port = int(url.rstrip("/").rsplit(":", 1)[1])
        with socket.create_connection(("127.0.0.1", port), timeout=10):
            pass
        outside = _outside_address()
        assert outside is not None, "this machine has no address but loopback to try"
        with pytest.raises(OSError):
            socket.create_connection((outside, port), timeout=10).close()
    finally:
        stop(proc)
    proc, url = serve(wall, "--host", "0.0.0.0")
    try:
        port = int(url.rstrip("/").rsplit(":", 1)[1])
        with socket.create_connection((outside, port), timeout=10):
            pass
    finally:
        stop(proc)


def _figures_line(text: str) -> str:
    lines = [ln for ln in text.splitlines() if ln.startswith("Strips")]
    return lines[0] if lines else ""


def test_the_page_shows_the_pipelines_template_count_and_column_0_on_the_left(wall, tmp_path):
    """The demo wall with its handles: the page's strips figures, once settled, give the
    template count and quantities that planarize-strips and unfold give for the net optimize
    writes for the same handles; a click at the net's left edge selects a vertex of a low
    column, one at its right edge a vertex of a high column (column 0 on the left)."""
    import re

    dgpc("optimize", wall / "wall", "--mode", "isometric", "--handles", HANDLES, "--steps", 5,
         "-o", tmp_path / "opt")
    dgpc("planarize-strips", tmp_path / "opt", "-o", tmp_path / "strips", expect=None)
    dgpc("unfold", tmp_path / "strips", "-o", tmp_path / "flat")
    classes = json.loads((tmp_path / "flat.json").read_text())["data"]["classes"]
    quantities = [c["quantity"] for c in classes]
    expected = (f"one template ({quantities[0]} copies)" if len(classes) == 1 else
                f"{len(classes)} templates ({' + '.join(map(str, quantities))})")
    proc, url = serve(wall)
    width, height = 1400, 860                    # the whole panel in the window
    try:
        with Browser(width=width, height=height) as browser:
            browser.open(url)
            browser.wait_text("converged", 300)
            browser.check()                          # Fabrication figures
            text = browser.wait_text("as planarize-strips and unfold make them", 1200)
            assert expected in _figures_line(text), (expected, _figures_line(text))
            im = drawn(browser, tmp_path / "page.png")
            net = im[:, : int(0.7 * width)]                          # left of the panel
            ys, xs = np.nonzero((abs(net[..., 0] - net[..., 1]) < 12) & (net[..., 0] < 200)
                                & (net[..., 0] > 60))
            band = np.abs(ys - 0.5 * (ys.min() + ys.max())) < 15       # halfway up
            picked = {}
            for side, x in (("left", np.percentile(xs[band], 2)),
                            ("right", np.percentile(xs[band], 98))):
                browser.click(float(x), float(np.median(ys[band])))
                end = time.monotonic() + 120
                found = None
                while found is None and time.monotonic() < end:
                    found = re.search(r"Selected vertex \((\d+), (\d+)\)", browser.text())
                    if found and picked and (int(found[1]), int(found[2])) == picked["left"]:
                        found = None
                    time.sleep(0.5)
                assert found, side
                picked[side] = (int(found[1]), int(found[2]))
            # column 0 on the left: the left click's column is low and below the right one's
            assert picked["left"][1] <= 4 and picked["left"][1] < picked["right"][1], picked
    finally:
        stop(proc)
