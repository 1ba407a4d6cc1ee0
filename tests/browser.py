"""A headless Chromium driven over the DevTools protocol (Debian's ``chromium``; no browser
download): open a page, take screenshots, drag the mouse, read the page's text."""

from __future__ import annotations

import base64
import itertools
import json
import shutil
import subprocess
import tempfile
import time
import urllib.request
from pathlib import Path

from websockets.sync.client import connect

#: Launch flags: headless, no sandbox (containers), software GL, no network of its own.
FLAGS = ["--headless", "--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run",
         "--disable-background-networking", "--disable-component-update", "--disable-sync",
         "--enable-unsafe-swiftshader", "--use-angle=swiftshader"]
WIDTH, HEIGHT = 1000, 640


def chromium_path() -> str:
    """The Chromium executable; a clear failure when it is missing (``.ci/run`` installs it)."""
    path = shutil.which("chromium") or shutil.which("chromium-browser")
    if path is None:
        raise RuntimeError("Chromium is not installed (apt-get install -y chromium; .ci/run "
                           "installs it before the tests)")
    return path


class Browser:
    """One headless Chromium with a fresh profile and one page; use as a context manager."""

    def __init__(self, timeout: float = 120.0, width: int = WIDTH, height: int = HEIGHT):
        self.timeout = timeout
        self.profile = tempfile.mkdtemp(prefix="chromium-profile-")
        self.proc = subprocess.Popen(
            [chromium_path(), *FLAGS, f"--user-data-dir={self.profile}",
             "--remote-debugging-port=0", f"--window-size={width},{height}", "about:blank"],
            stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        port_file = Path(self.profile) / "DevToolsActivePort"
        end = time.monotonic() + timeout
        while not (port_file.exists() and port_file.read_text().count("\n") >= 1):
            if time.monotonic() > end or self.proc.poll() is not None:
                self.close()
                raise RuntimeError("Chromium did not start its DevTools endpoint")
            time.sleep(0.1)
        port = int(port_file.read_text().splitlines()[0])
        with urllib.request.urlopen(f"http://127.0.0.1:{port}/json/list", timeout=10) as r:
            pages = [t for t in json.load(r) if t["type"] == "page"]
        self.ws = connect(pages[0]["webSocketDebuggerUrl"], max_size=2 ** 26,
                          open_timeout=timeout)
        self._ids = itertools.count(1)
        self.call("Page.enable")
        self.call("Emulation.setDeviceMetricsOverride", width=width, height=height,
                  deviceScaleFactor=1, mobile=False)

    def call(self, method: str, **params):
        """Send a DevTools command and return its result (events in between are dropped)."""
        mid = next(self._ids)
        self.ws.send(json.dumps({"id": mid, "method": method, "params": params}))
        end = time.monotonic() + self.timeout
        while True:
            msg = json.loads(self.ws.recv(timeout=max(0.1, end - time.monotonic())))
            if msg.get("id") == mid:
                if "error" in msg:
                    raise RuntimeError(f"{method}: {msg['error']}")
                return msg.get("result", {})

    def open(self, url: str) -> None:
        self.call("Page.navigate", url=url)

    def text(self) -> str:
        """The page's visible text."""
        res = self.call("Runtime.evaluate", expression="document.body.innerText",
                        returnByValue=True)
        return res["result"].get("value", "")

    def wait_text(self, needle: str, timeout: float = 60.0) -> str:
        end = time.monotonic() + timeout
        while True:
            text = self.text()
            if needle in text:
                return text
            if time.monotonic() > end:
                raise AssertionError(f"{needle!r} not on the page after {timeout} s: {text!r}")
            time.sleep(0.25)

    def screenshot(self, path: Path) -> bytes:
        data = base64.b64decode(self.call("Page.captureScreenshot", format="png")["data"])
        Path(path).write_bytes(data)
        return data

    def click(self, x: float, y: float) -> None:
        """Move to ``(x, y)`` and click the left button there."""
        self.call("Input.dispatchMouseEvent", type="mouseMoved", x=x, y=y)
        self.call("Input.dispatchMouseEvent", type="mousePressed", x=x, y=y, button="left",
                  buttons=1, clickCount=1)
        self.call("Input.dispatchMouseEvent", type="mouseReleased", x=x, y=y, button="left",
                  buttons=0, clickCount=1)

    def check(self, index: int = 0, timeout: float = 120.0) -> None:
        """Tick the ``index``-th visible checkbox of the page with the mouse, again until it
        is ticked (a page still laying out its panel moves it under the first click)."""
        where = ("[...document.querySelectorAll('input[type=checkbox]')]"
                 f".filter(x => x.getBoundingClientRect().width > 0)[{index}]")
        end = time.monotonic() + timeout
        while True:
            box = self.call("Runtime.evaluate", returnByValue=True, expression=(
                f"(() => {{ const x = {where}; const r = x.getBoundingClientRect(); "
                "return [r.left + r.width / 2, r.top + r.height / 2, x.checked]; })()"))
            x, y, checked = box["result"]["value"]
            if checked:
                return
            if time.monotonic() > end:
                raise AssertionError(f"the checkbox at ({x}, {y}) does not tick")
            self.click(x, y)
            time.sleep(2)

    def drag(self, start: tuple[float, float], stop: tuple[float, float], steps: int = 12,
             pause: float = 0.05) -> None:
        """Press the left button at ``start``, move to ``stop`` in ``steps``, release."""
        x0, y0 = start
        x1, y1 = stop
        self.call("Input.dispatchMouseEvent", type="mouseMoved", x=x0, y=y0)
        self.call("Input.dispatchMouseEvent", type="mousePressed", x=x0, y=y0, button="left",
                  buttons=1, clickCount=1)
        for k in range(1, steps + 1):
            t = k / steps
            self.call("Input.dispatchMouseEvent", type="mouseMoved", x=x0 + t * (x1 - x0),
                      y=y0 + t * (y1 - y0), button="left", buttons=1)
            time.sleep(pause)
        self.call("Input.dispatchMouseEvent", type="mouseReleased", x=x1, y=y1, button="left",
                  buttons=0, clickCount=1)

    def close(self) -> None:
        try:
            if getattr(self, "ws", None) is not None:
                self.ws.close()
        finally:
            self.proc.terminate()
            try:
                self.proc.wait(timeout=10)
            except subprocess.TimeoutExpired:
                self.proc.kill()
                self.proc.wait(timeout=10)
            shutil.rmtree(self.profile, ignore_errors=True)

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()
