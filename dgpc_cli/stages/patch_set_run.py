"""A stage given a patch set (``io.patch_set``) runs on each member: member ``pK`` of the set
``STEM`` is written to ``OUT.pK``, and ``OUT.json`` becomes the patch set of the outputs.

One line per member on stderr (its output, or why it failed); the exit code is the worst of the
members'. A member whose stage fails without writing its output is recorded in the new set as
failed (``data.failed``: its stage, exit code and reason), which every later stage then refuses;
a member that writes it anyway (``optimize`` not converged: exit 3) stays in, with its code.
With ``--force``, the files the previous output at ``OUT.json`` wrote and the new one does not
(its members, as it lists them) are removed.
"""

from __future__ import annotations

import json
from collections.abc import Callable
from pathlib import Path

from dgpc_cli.errors import DgpcError
from dgpc_cli.io.artifact import artifact_paths
from dgpc_cli.io.atomic import write_files
from dgpc_cli.io.patch_set import (
    member_files,
    member_stems,
    patch_set_bytes,
    previous_files,
    relative_path,
)


class MembersFailed(DgpcError):
    """Some members of a patch set failed; the exit code is the worst of theirs."""

    def __init__(self, message: str, exit_code: int, source=None):
        super().__init__(message, source=source)
        self.exit_code = exit_code


def member_kind(json_path: Path) -> str:
    """The ``kind`` of the member artifact ``json_path``."""
    return str(json.loads(Path(json_path).read_bytes()).get("kind"))


def write_patch_set(output: Path, stage: str, members: list[dict], *, force: bool,
                    failed: list[dict] = ()) -> Path:
    """Write ``OUT.json`` as the patch set of ``members`` and the ``failed`` ones (see
    :func:`~dgpc_cli.io.patch_set.patch_set_bytes`), removing (with ``force``) the files of the
    output it replaces that no member lists; its JSON path."""
    json_path, _ = artifact_paths(output)
    keep = {Path(f).resolve() for m in members for f in m["files"]} | {json_path.resolve()}
    stale = [p for p in previous_files(json_path) if Path(p).resolve() not in keep]
    write_files({json_path: patch_set_bytes(json_path, stage, members, failed=failed)},
                force=force, replaces=stale)
    return json_path


def failure_reason(err: DgpcError, folder: Path) -> str:
    """The one-line reason of ``err`` as a set in ``folder`` records it: a file it names
    relative to that folder (POSIX), so that the set's bytes do not depend on where it runs."""
    source = err.source
    if source is not None and Path(source).exists():
        source = relative_path(source, folder)
    return f"{source}: {err.reason}" if source else err.reason


def each_member(stem: Path, output: Path, stage: str, run: Callable[[Path, Path], None], *,
                force: bool, say: Callable[[str], None] | None = None,
                extra: Callable[[Path], tuple[Path, ...]] = lambda out: ()) -> Path:
    """Run ``run(member, OUT.pK)`` on every member of the patch set ``stem`` and write the
    patch set of the outputs at ``output``; its JSON path. ``extra(OUT.pK)``: files a member
    writes that its artifact does not list. Raises :class:`MembersFailed` (the worst code)
    when a member failed, after the set is written."""
    members, failed = [], []                    # failed: the members without their output
    out_json, _ = artifact_paths(output)
    for name, member in member_stems(stem):
        target = out_json.parent / f"{out_json.name[:-len('.json')]}.{name}"
        target_json, _ = artifact_paths(target)
        code, why, reason = 0, "", ""
        try:
            run(member, target)
        except DgpcError as err:
            code, why = err.exit_code, str(err)
            reason = failure_reason(err, out_json.parent)
        if say is not None:
            say(f"{stage}: {name}: " + (f"{target_json}" if code == 0 else
                                        f"exit {code}: {why}"))
        if target_json.is_file() and code in (0, 3):
            members.append({"name": name, "kind": member_kind(target_json),
                            "json": target_json, "exit_code": code,
                            "files": member_files(target_json, extra(target))})
        else:
            failed.append({"name": name, "exit_code": code or 1,
                           "reason": reason or f"{stage} wrote no output"})
    written_json = write_patch_set(output, stage, members, force=force, failed=failed)
    worst = max((m["exit_code"] for m in (*members, *failed)), default=0)
    if failed:
        names = ", ".join(m["name"] for m in failed)
        raise MembersFailed(f"{len(failed)} of the patch set's {len(members) + len(failed)} "
                            f"members failed ({names}): the set records "
                            f"{'them' if len(failed) > 1 else 'it'}, and later stages refuse "
                            "it", worst, source=written_json)
    if worst:
        names = ", ".join(m["name"] for m in members if m["exit_code"])
        raise MembersFailed(f"exit {worst} from member(s) {names}, output written; the set "
                            "lists them", worst, source=written_json)
    return written_json
