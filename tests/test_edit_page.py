"""``dgpc edit``: the page in a headless Chromium (Debian's ``chromium``, which ``.ci/run``
installs; missing, the test fails saying so): it shows the net, a drag of a handle's gizmo
(the push slider of a handle added by clicking a vertex) changes the net and the status, Save
writes the artifact; the page listens on this machine
only unless --host is given."""

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
from cli_helpers import wall_net
from PIL import Image

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
    net = im[:, : int(0.55 * WIDTH)]
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
        if grey > 20000 and red > 200:
            return im
        assert time.monotonic() < end, f"the net is not drawn: {grey} grey, {red} red pixels"
        k += 1
        browser.call("Input.dispatchMouseEvent", type="mouseMoved", x=40 + k % 5, y=HEIGHT - 40)
        time.sleep(2)


def slider_thumb(browser) -> tuple[float, float]:
    """The centre of the push slider's thumb."""
    res = browser.call("Runtime.evaluate", returnByValue=True, expression=(
        "(() => { const r = document.querySelector('[role=slider]').getBoundingClientRect();"
        " return [r.left + r.width / 2, r.top + r.height / 2]; })()"))
    x, y = res["result"]["value"]
    return float(x), float(y)


def click(browser, x: float, y: float) -> None:
    browser.call("Input.dispatchMouseEvent", type="mouseMoved", x=x, y=y)
    browser.call("Input.dispatchMouseEvent", type="mousePressed", x=x, y=y, button="left",
                 buttons=1, clickCount=1)
    browser.call("Input.dispatchMouseEvent", type="mouseReleased", x=x, y=y, button="left",
                 buttons=0, clickCount=1)


def test_page_shows_the_net_and_a_drag_changes_it(wall, tmp_path):
    proc, url = serve(wall)
    try:
        assert url.startswith("http://127.0.0.1:")
        with Browser() as browser:
            browser.open(url)
            first = status_line(browser.wait_text("converged", 180))
            before = drawn(browser, tmp_path / "before.png")
            net = before[:, : int(0.55 * WIDTH)]

            # click a vertex in the middle of the net: it becomes a handle, selected
            grey = np.nonzero((abs(net[..., 0] - net[..., 1]) < 12) & (net[..., 0] < 200)
                              & (net[..., 0] > 60))
            click(browser, float(np.median(grey[1])), float(np.median(grey[0])))
            browser.wait_text("): a handle.", 120)
            end = time.monotonic() + 300                 # the new handle's net settles
            while status_line(browser.text()).startswith("⏳") and time.monotonic() < end:
                time.sleep(1)
            first = status_line(browser.text())
            # drag the push slider: the handle moves along the normal, the net follows
            x, y = slider_thumb(browser)
            browser.drag((x, y), (x + 60, y), steps=6, pause=0.3)
            end = time.monotonic() + 300
            now = first
            while now == first and time.monotonic() < end:
                time.sleep(1)
                now = status_line(browser.text())
            assert now != first, "the status did not change after the drag"
            after = pixels(browser.screenshot(tmp_path / "after.png"))
            moved = np.abs(after[:, : int(0.55 * WIDTH)] - net).sum(axis=-1) > 60
            assert moved.sum() > 500, moved.sum()

            browser.call("Runtime.evaluate", expression=(
                "[...document.querySelectorAll('button')].find(b => b.innerText.includes("
                "'Save artifact')).click()"))
            browser.wait_text("Saved", 300)
        saved = json.loads((wall / "out-handles.json").read_text())["handles"]
        assert len(saved) == len(json.loads(HANDLES.read_text())["handles"]) + 1
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
