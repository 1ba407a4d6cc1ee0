"""``dgpc edit``'s socket is an input: what a hostile or stale client sends the page (garbage
frames, unknown messages, NaN or far-off values from the slider, a gizmo or a click, a share
request, another viser version) is dropped with one warning line on stderr, no traceback,
nothing on stdout; Save then writes finite JSON. An address that cannot be bound, or a port
in use, is one line and exit 1 (no endless retry); a replay's times are bounded."""

import json
import math
import socket
import subprocess
import sys
import time
from pathlib import Path

import msgspec
import numpy as np
import pytest
from cli_helpers import dgpc, wall_net
from edit_client import PageClient

from dgpc_cli.edit.session import EditSession
from dgpc_cli.errors import DgpcError
from dgpc_cli.fitting.modes import mode_weights
from dgpc_cli.io.net import read_net
from dgpc_cli.stages.optimize_artifact import OptimizeSettings, prepare_optimize

M, N = 9, 7
#: Seconds a command may take to give up on a bad address, at most (it used to never end).
GIVE_UP = 120


@pytest.fixture(scope="module")
def wall(tmp_path_factory):
    d = tmp_path_factory.mktemp("edit-socket")
    wall_net(d, M, N)
    held = [{"index": [M - 1, 0], "offset": [0, 0, 0]},
            {"index": [M - 1, N - 1], "offset": [0, 0, 0]}]
    (d / "held.json").write_text(json.dumps({"handles": held}))
    return d


def command(d: Path, *extra, out: Path | None = None) -> list[str]:
    return [sys.executable, "-m", "dgpc_cli.cli.main", "edit", str(d / "wall"), "--handles",
            str(d / "held.json"), "--max-strain", "1e-3", "--gpc-tol", "1e-3", "-o",
            str(out or d / "out"), "--force", *extra]


class Served:
    """``dgpc edit`` running on the wall; stderr to a file, read as it grows."""

    def __init__(self, d: Path, *extra):
        self.err_path = d / f"stderr-{time.monotonic_ns()}.txt"
        self.err = self.err_path.open("w")
        self.proc = subprocess.Popen(command(d, *extra), stdout=subprocess.PIPE,
                                     stderr=self.err, text=True, cwd=d)
        self.url = self.proc.stdout.readline().strip()
        assert self.url.startswith("http://"), (self.url, self.stderr())

    def stderr(self) -> str:
        return self.err_path.read_text()

    def dropped(self) -> list[str]:
        return [ln for ln in self.stderr().splitlines() if "dropped" in ln or "refused" in ln]

    def wait_dropped(self, count: int, timeout: float = 60) -> list[str]:
        end = time.monotonic() + timeout
        while len(self.dropped()) < count and time.monotonic() < end:
            time.sleep(0.1)
        return self.dropped()

    def stop(self) -> str:
        self.proc.terminate()
        out, _ = self.proc.communicate(timeout=30)
        self.err.close()
        return out


NAN = float("nan")


def hostile(client: PageClient, gizmo: str) -> list:
    """The messages each to be dropped with one line (sent on ``client``), and what the line
    says (a part of it)."""
    return [
        (lambda: client.update("Push selected (edges)", value=NAN), "push"),
        (lambda: client.update("Push selected (edges)", value=1e308), "push"),
        (lambda: client.update("Push selected (edges)", value="abc"), "abc"),
        (lambda: client.update("Push selected (edges)", nosuch=1), "AssertionError"),
        (lambda: client.move_gizmo(gizmo, [NAN, 0.0, 0.0]), "non-finite"),
        (lambda: client.move_gizmo(gizmo, [1e6, 0.0, 0.0]), "diagonals"),
        (lambda: client.move_gizmo(gizmo, [1.0]), "three numbers"),
        (lambda: client.click([NAN, 0.0, 0.0], [0.0, 0.0, 1.0]), "ray origin"),
        (lambda: client.click([0.0, 0.0, 50.0], [0.0, 0.0, 0.0]), "zero direction"),
        (lambda: client.click([0.0, 0.0, 50.0], [0.0, 0.0, 1e400]), "ray direction"),
        (lambda: client.send({"type": "ShareUrlRequest"}), "share link"),
    ]


def test_bad_messages_are_dropped_with_one_line_each_and_save_writes_finite_json(wall):
    served = Served(wall)
    try:
        with PageClient(served.url) as client:
            gizmo = client.gizmos()[0]
            cases = hostile(client, gizmo)
            for k, (send, says) in enumerate(cases, start=1):
                send()
                lines = served.wait_dropped(k)
                assert len(lines) == k, (says, lines)
                assert says in lines[-1], (says, lines[-1])
            client.press("Save artifact")
            end = time.monotonic() + 300
            while not (wall / "out.json").exists() and time.monotonic() < end:
                time.sleep(0.2)
        # frames the server cannot decode end their connection: one line each too
        unknown = msgspec.msgpack.encode({"type": "NoSuchMessage", "x": 1})
        words = msgspec.msgpack.encode({"type": "TransformControlsUpdateMessage", "name": gizmo,
                                        "wxyz": [1, 0, 0, 0], "position": ["a", "b", "c"]})
        for frame, says in ((b"\x00\x01garbage", "DecodeError"), ("text", "AssertionError"),
                            (unknown, "NoSuchMessage"), (words, "ValueError")):
            count = len(served.dropped())
            with PageClient(served.url) as client:
                client.send_raw(frame)
                lines = served.wait_dropped(count + 1)
            assert len(lines) == count + 1 and says in lines[-1], lines
    finally:
        out = served.stop()
    err = served.stderr()
    assert "Traceback" not in err and "Task exception" not in err, err
    assert all(ln.split(":")[0] in ("warning", "info") for ln in err.splitlines()), err
    # stdout: the address (read above) and the saved artifact, nothing else
    assert out.splitlines() == [str(wall / "out.json")]

    def strict(text):
        return json.loads(text, parse_constant=lambda c: pytest.fail(f"{c} in the JSON"))

    handles = strict((wall / "out-handles.json").read_text())["handles"]
    assert len(handles) == 2
    assert all(math.isfinite(c) for h in handles for c in h["target"])
    strict((wall / "out.json").read_text())
    assert np.isfinite(read_net(wall / "out").f).all()


def test_a_client_of_another_viser_version_is_one_line_on_stderr(wall):
    from websockets.sync.client import connect

    served = Served(wall)
    try:
        with connect(served.url.replace("http://", "ws://"), subprotocols=["viser-v0.0.1"],
                     open_timeout=30) as ws:
            with pytest.raises(Exception):       # noqa: B017 - closed by the server
                ws.recv(timeout=30)
        end = time.monotonic() + 30
        while "refused" not in served.stderr() and time.monotonic() < end:
            time.sleep(0.1)
    finally:
        out = served.stop()
    assert out == ""                              # the address (read above) only
    lines = [ln for ln in served.stderr().splitlines() if "refused" in ln]
    assert len(lines) == 1 and "0.0.1" in lines[0], served.stderr()


def _session(d):
    settings = OptimizeSettings("isometric", mode_weights("isometric"), max_strain=1e-3,
                                gpc_tol=1e-3)
    return EditSession(prepare_optimize(d / "wall", settings))


def test_the_session_refuses_non_finite_or_far_targets_and_save_writes_nothing(wall, tmp_path):
    s = _session(wall)
    s.pin(M - 1, 0)
    for target in ((NAN, 0.0, 0.0), (1e6, 0.0, 0.0), (0.0, 0.0)):
        with pytest.raises(ValueError):
            s.drag(0, N // 2, target)
    assert len(s.handles) == 1                   # nothing taken from the refused drags
    s.handles[0 * N + N // 2] = (NAN, 0.0, 0.0)  # past every check: save still refuses it
    with pytest.raises(DgpcError, match="not finite"):
        s.save(tmp_path / "x")
    assert list(tmp_path.iterdir()) == []


def _one_line_exit_1(result, names: str):
    assert result.returncode == 1, (result.returncode, result.stderr)
    lines = result.stderr.strip().splitlines()
    assert len(lines) == 1 and names in lines[0], result.stderr
    assert "Traceback" not in result.stderr and result.stdout == ""


@pytest.mark.parametrize("host", ["999.1.1.1", "not a host!", "192.0.2.1"])
def test_a_host_that_cannot_be_bound_is_one_line_and_exit_1(wall, host, tmp_path):
    result = subprocess.run(command(wall, "--host", host, out=tmp_path / "out"),
                            capture_output=True, text=True, timeout=GIVE_UP, cwd=tmp_path)
    _one_line_exit_1(result, "--host")
    assert list(tmp_path.iterdir()) == []


def test_a_port_in_use_is_one_line_or_the_next_free_one_with_the_flag(wall):
    with socket.socket() as taken:
        taken.bind(("127.0.0.1", 0))
        taken.listen()
        port = taken.getsockname()[1]
        result = subprocess.run(command(wall, "--port", str(port)), capture_output=True,
                                text=True, timeout=GIVE_UP, cwd=wall)
        _one_line_exit_1(result, "--port")
        assert f"port {port}" in result.stderr
        served = Served(wall, "--port", str(port), "--next-free-port")
        try:
            got = int(served.url.rstrip("/").rsplit(":", 1)[1])
            assert got > port
            with socket.create_connection(("127.0.0.1", got), timeout=10):
                pass
        finally:
            served.stop()
    said = [ln for ln in served.stderr().splitlines() if "in use" in ln]
    assert said == [f"warning: edit: port {port} on 127.0.0.1 is in use; using {got}"]


@pytest.mark.parametrize("time_", [1e308, 3601, "NaN"])
def test_replay_times_are_bounded(wall, tmp_path, time_):
    text = json.dumps({"events": [{"handle": [0, 0], "target": [0, 0, 0], "time": 0},
                                  {"handle": [0, 0], "target": [0, 0, 0], "time": 1.0}]})
    text = text.replace('"time": 1.0', f'"time": {time_}')
    (tmp_path / "d.json").write_text(text)
    result = dgpc("edit", wall / "wall", "--replay", tmp_path / "d.json", "-o",
                  tmp_path / "out", expect=1)
    lines = result.stderr.strip().splitlines()
    assert len(lines) == 1 and "events[1].time" in lines[0], result.stderr
    assert sorted(p.name for p in tmp_path.iterdir()) == ["d.json"]
