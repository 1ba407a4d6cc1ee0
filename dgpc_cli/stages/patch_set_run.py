"""A stage given a patch set (``io.patch_set``) runs on each member: member ``pK`` of the set
``STEM`` is written to ``OUT.pK``, and ``OUT.json`` becomes the patch set of the outputs.

One line per member on stderr (its output, or why it failed); the exit code is the worst of the
members'. A member whose stage fails without writing its output is recorded in the new set as
failed (``data.failed``: its stage, exit code and reason), which every later stage then refuses;
a member that writes it anyway (``optimize`` not converged: exit 3) stays in, with its code.
When every member fails, nothing is written (a set of failures only is no output).

The members' writes are held (:func:`~dgpc_cli.io.atomic.held_writes`) and committed with the
set's JSON in one write: a process killed at any moment leaves the old set and its members, or
the new ones, never a mix. With ``--force``, the files the previous output at ``OUT.json``
wrote and the new one does not (:func:`~dgpc_cli.io.patch_set.previous_files`) are removed.
"""

from __future__ import annotations

import json
from collections.abc import Callable
from pathlib import Path

from dgpc_cli.errors import DgpcError
from dgpc_cli.io.artifact import artifact_paths
from dgpc_cli.io.atomic import Held, held_writes, write_files
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


def member_kind(json_path: Path, read=lambda path: Path(path).read_bytes()) -> str:
    """The ``kind`` of the member artifact ``json_path`` (``read(path)``: its bytes)."""
    return str(json.loads(read(json_path)).get("kind"))


def write_patch_set(output: Path, stage: str, members: list[dict], *, force: bool,
                    failed: list[dict] = (), held: Held | None = None,
                    announce: Callable[[], None] | None = None) -> Path:
    """Write ``OUT.json`` as the patch set of ``members`` and the ``failed`` ones (see
    :func:`~dgpc_cli.io.patch_set.patch_set_bytes`), removing (with ``force``) the files of the
    output it replaces that no member lists; its JSON path. ``held``: the members' writes,
    held so far (:func:`~dgpc_cli.io.atomic.held_writes`), committed with the set in one
    write; ``announce`` prints the set's path once it is committed."""
    json_path, _ = artifact_paths(output)
    keep = {Path(f).resolve() for m in members for f in m["files"]} | {json_path.resolve()}
    stale = [p for p in previous_files(json_path) if Path(p).resolve() not in keep]
    read = held.read if held is not None else None
    files = {json_path: patch_set_bytes(json_path, stage, members, failed=failed, read=read)}
    if held is not None:
        files.update(held.files)
        stale += held.stale

    def said() -> None:
        if held is not None:
            held.announce()
        if announce is not None:
            announce()

    write_files(files, force=force, replaces=stale, announce=said)
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
                extra: Callable[[Path], tuple[Path, ...]] = lambda out: (),
                announce: Callable[[Path], None] | None = None) -> Path:
    """Run ``run(member, OUT.pK)`` on every member of the patch set ``stem`` and write the
    patch set of the outputs at ``output`` with them, in one commit; its JSON path.
    ``extra(OUT.pK)``: files a member writes that its artifact does not list. ``say`` gets one
    line per member, once the set is written; ``announce(json_path)`` prints the set's path
    at the commit. Raises :class:`MembersFailed` (the worst code) when a member failed: after
    the set is written, or, when every member failed, with nothing written."""
    members, failed, lines = [], [], []          # failed: the members without their output
    out_json, _ = artifact_paths(output)
    with held_writes() as held:
        for name, member in member_stems(stem):
            target = out_json.parent / f"{out_json.name[:-len('.json')]}.{name}"
            target_json, _ = artifact_paths(target)
            code, why, reason = 0, "", ""
            mark = held.mark()
            try:
                run(member, target)
            except DgpcError as err:
                code, why = err.exit_code, str(err)
                reason = failure_reason(err, out_json.parent)
            lines.append(f"{stage}: {name}: " + (f"{target_json}" if code == 0 else
                                                 f"exit {code}: {why}"))
            if held.holds(target_json) and code in (0, 3):
                members.append({"name": name, "kind": member_kind(target_json, held.read),
                                "json": target_json, "exit_code": code,
                                "files": member_files(target_json, extra(target),
                                                      read=held.read)})
            else:
                held.drop_since(mark)           # a member that failed leaves nothing
                failed.append({"name": name, "exit_code": code or 1,
                               "reason": reason or f"{stage} wrote no output"})
    if not members:
        names = ", ".join(m["name"] for m in failed)
        raise MembersFailed(f"every member of the patch set failed ({names}), so nothing was "
                            f"written; {failed[0]['name']}: {failed[0]['reason']}",
                            max(m["exit_code"] for m in failed),
                            source=artifact_paths(stem)[0])
    written_json = write_patch_set(output, stage, members, force=force, failed=failed,
                                   held=held, announce=(None if announce is None else
                                                        lambda: announce(out_json)))
    if say is not None:
        for line in lines:
            say(line)
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
