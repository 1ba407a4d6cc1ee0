"""The ``report`` run: the artifacts named (a patch set as its members), each one's kind, and
the report written: one artifact's figures and index, or the overview of several."""

from __future__ import annotations

from collections.abc import Callable, Sequence
from pathlib import Path

from dgpc_cli.io.artifact import artifact_paths
from dgpc_cli.io.atomic import write_files
from dgpc_cli.io.patch_set import with_members
from dgpc_cli.stages.inspect_kinds import artifact_kind
from dgpc_cli.stages.report import overview_files, previous_report_files, report_files


def run_report(stems: Sequence[Path], output: Path, *, force: bool,
               written: Callable[[Path], None]) -> None:
    """Write the report of the artifacts ``stems`` under the prefix ``output``, replacing
    an earlier report there; ``written(path)`` is called per file at their commit, the index
    last (nothing is written when it fails)."""
    json_paths = [artifact_paths(stem)[0] for stem in with_members(stems)]
    kinds = [artifact_kind(p) for p in json_paths]
    if len(json_paths) == 1:
        files = report_files(json_paths[0], kinds[0], output)
    else:
        files = overview_files(list(zip(json_paths, kinds, strict=True)), output)
    write_files(files, force=force, replaces=previous_report_files(output),
                announce=lambda: [written(p) for p in files])
