"""How pytest-xdist spreads the tests over its workers (``make test``: ``-n auto``).

Every test is a unit of its own, given to whichever worker is free, except the tests that share
a module- or class-scoped fixture: those of one module are one unit, so that one worker builds
the fixture once. Nothing to mark by hand: each worker lists the tests it collected that use
such a fixture in a file the controller named, and the controller's scheduler reads it. (xdist's
own ``--dist loadgroup`` would do the same from ``xdist_group`` marks, but it tags node ids in a
way pytest 9 no longer reads.) The units run largest first, then in the order collected.
"""

from __future__ import annotations

import json
import os
import tempfile
from pathlib import Path

from xdist.scheduler import LoadScopeScheduling

#: The key of the workers' input that names the file of shared-fixture groups.
GROUPS_KEY = "shared_fixture_groups"


def shared_fixture_groups(items) -> dict[str, str]:
    """``{node id: its module's path}`` of the tests that use a module- or class-scoped fixture."""
    groups = {}
    for item in items:
        info = getattr(item, "_fixtureinfo", None)
        defs = info.name2fixturedefs.values() if info is not None else ()
        if any(d.scope in ("module", "class") for fixturedefs in defs for d in fixturedefs):
            groups[item.nodeid] = item.nodeid.split("::")[0]
    return groups


def groups_file(config) -> Path:
    """The file the controller reads the groups from (made once, removed by :func:`cleanup`)."""
    if not hasattr(config, "_shared_fixture_groups"):
        fd, name = tempfile.mkstemp(prefix="pytest-groups-", suffix=".json")
        os.close(fd)
        config._shared_fixture_groups = Path(name)
    return config._shared_fixture_groups


def record(config, items) -> None:
    """In a worker: write the groups of its collection where the controller asked."""
    path = getattr(config, "workerinput", {}).get(GROUPS_KEY)
    if path:
        tmp = Path(f"{path}.{config.workerinput['workerid']}")
        tmp.write_text(json.dumps(shared_fixture_groups(items)))
        tmp.replace(path)                  # every worker collects the same: any copy will do


def cleanup(config) -> None:
    path = getattr(config, "_shared_fixture_groups", None)
    if path is not None:
        path.unlink(missing_ok=True)


class SharedFixtureScheduling(LoadScopeScheduling):
    """xdist's scope scheduling with the scopes above: a module whose tests share a fixture,
    else the test itself."""

    def __init__(self, config, log=None):
        super().__init__(config, log)
        self._groups_path = groups_file(config)
        self._groups: dict[str, str] | None = None

    def _split_scope(self, nodeid: str) -> str:
        if self._groups is None:
            text = self._groups_path.read_text() if self._groups_path.exists() else ""
            # no file (no worker wrote one): every module one unit, as --dist loadscope has it
            self._groups = json.loads(text) if text else {}
            self._by_module = not text
        if self._by_module:
            return nodeid.split("::")[0]
        return self._groups.get(nodeid, nodeid)
