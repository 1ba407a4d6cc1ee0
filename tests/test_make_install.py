"""`make install` puts the dgpc command on PATH (README "Reaching dgpc"): a link BINDIR/dgpc to
the checkout's .venv/bin/dgpc that runs, a line saying whether BINDIR is on PATH, and `make
uninstall` removing only its own link."""

import os
import subprocess
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
VENV_DGPC = ROOT / ".venv" / "bin" / "dgpc"

pytestmark = pytest.mark.skipif(not VENV_DGPC.is_file(), reason="no .venv in the checkout")


def make(*args, path_extra=None):
    path = os.environ["PATH"] if path_extra is None else f"{path_extra}{os.pathsep}" \
        f"{os.environ['PATH']}"
    return subprocess.run(["make", "-s", "--no-print-directory", "-o", ".venv/.installed",
                           *args], cwd=ROOT, env={**os.environ, "PATH": path},
                          capture_output=True, text=True, check=False)


def test_install_links_dgpc_and_says_whether_it_is_on_path(tmp_path):
    bindir = tmp_path / "bin"
    r = make("install", f"BINDIR={bindir}")
    assert r.returncode == 0, r.stderr
    link = bindir / "dgpc"
    assert link.is_symlink() and Path(os.readlink(link)) == VENV_DGPC
    assert f"{bindir} is not on your PATH" in r.stdout and "export PATH=" in r.stdout
    version = subprocess.run([str(link), "--version"], capture_output=True, text=True,
                             check=True)
    assert version.stdout.startswith("dgpc")
    r = make("install", f"BINDIR={bindir}", path_extra=bindir)
    assert f"{bindir} is on your PATH" in r.stdout
    r = make("uninstall", f"BINDIR={bindir}")
    assert r.returncode == 0 and not link.exists() and "removed" in r.stdout


def test_install_and_uninstall_leave_a_file_that_is_not_their_link(tmp_path):
    bindir = tmp_path / "bin"
    bindir.mkdir()
    mine = bindir / "dgpc"
    mine.write_text("#!/bin/sh\necho mine\n")
    r = make("install", f"BINDIR={bindir}")
    assert r.returncode != 0 and "not a link: left alone" in r.stderr
    r = make("uninstall", f"BINDIR={bindir}")
    assert "left alone" in r.stdout
    assert mine.read_text() == "#!/bin/sh\necho mine\n"
