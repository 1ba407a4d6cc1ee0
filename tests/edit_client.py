"""A bare websocket client of the ``dgpc edit`` page (no browser): it reads the scene and the
controls the server sends, and sends the page's messages as a client would, or any bytes at
all, to try the server with what a stale tab or a hostile client may send."""

from __future__ import annotations

import time

import msgspec
import viser
import zstandard
from websockets.sync.client import connect


class PageClient:
    """One connection to the page at ``url`` (``http://host:port/``)."""

    def __init__(self, url: str, timeout: float = 30.0):
        self.ws = connect(url.replace("http://", "ws://"), max_size=2 ** 26,
                          subprotocols=[f"viser-v{viser.__version__}"], open_timeout=timeout)
        self.messages: list[dict] = []
        self.read(until="ReplayDoneMessage", timeout=timeout)
        # the server counts a client as connected from its first camera message
        self.send({"type": "ViewerCameraMessage", "wxyz": [1.0, 0.0, 0.0, 0.0],
                   "position": [0.0, 0.0, 10.0], "fov": 1.0, "near": 0.01, "far": 1000.0,
                   "image_height": 480, "image_width": 640, "look_at": [0.0, 0.0, 0.0],
                   "up_direction": [0.0, 0.0, 1.0]})

    def read(self, until: str | None = None, timeout: float = 5.0) -> list[dict]:
        """The server's messages received within ``timeout`` s (or up to one of type
        ``until``); also kept in ``messages``."""
        got = []
        end = time.monotonic() + timeout
        while time.monotonic() < end:
            try:
                raw = self.ws.recv(timeout=max(0.05, end - time.monotonic()))
            except TimeoutError:
                break
            size = int.from_bytes(raw[:8], "little")
            packed = int.from_bytes(raw[8:16], "little")
            inner = zstandard.ZstdDecompressor().decompress(raw[16:16 + packed],
                                                            max_output_size=size)
            batch = msgspec.msgpack.decode(inner)["messages"]
            got += batch
            if until is not None and any(m["type"] == until for m in batch):
                break
        self.messages += got
        return got

    def control(self, label: str) -> str:
        """The uuid of the control labelled ``label`` (a button, slider, checkbox)."""
        for m in self.messages:
            if m["type"].startswith("Gui") and m.get("props", {}).get("label") == label:
                return m["uuid"]
        raise KeyError(label)

    def gizmos(self) -> list[str]:
        """The names of the handles' gizmos on the page."""
        return [m["name"] for m in self.messages if m["type"] == "TransformControlsMessage"]

    def send(self, message: dict) -> None:
        self.ws.send(msgspec.msgpack.encode(message))

    def send_raw(self, data: bytes | str) -> None:
        self.ws.send(data)

    def update(self, label: str, **updates) -> None:
        """Set properties of a control (``value=…``), as the page does when it is used."""
        self.send({"type": "GuiUpdateMessage", "uuid": self.control(label), "updates": updates})

    def press(self, label: str) -> None:
        self.update(label, value=True)

    def move_gizmo(self, name: str, position, phase: str = "update") -> None:
        """A gizmo's drag: ``phase`` start, update (to ``position``) or end."""
        if phase == "start":
            self.send({"type": "TransformControlsDragStartMessage", "name": name, "owner": ""})
        elif phase == "end":
            self.send({"type": "TransformControlsDragEndMessage", "name": name, "owner": ""})
        else:
            self.send({"type": "TransformControlsUpdateMessage", "name": name,
                       "wxyz": [1.0, 0.0, 0.0, 0.0], "position": position, "owner": ""})

    def click(self, origin, direction, name: str = "/net") -> None:
        self.send({"type": "SceneNodeClickMessage", "name": name, "instance_index": None,
                   "ray_origin": origin, "ray_direction": direction, "screen_pos": [0.5, 0.5],
                   "modifier": None, "owner": ""})

    def close(self) -> None:
        self.ws.close()

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()
