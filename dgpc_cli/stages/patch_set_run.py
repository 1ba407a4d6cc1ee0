"""A stage given a patch set (``io.patch_set``) runs on each member: member ``pK`` of the set
``STEM`` is written to ``OUT.pK``, and ``OUT.json`` becomes the patch set of the outputs.

One line per member on stderr (its output, or why it failed); the exit code is the worst of the
members'. A member whose stage fails without writing its output is left out of the new set; a
member that writes it anyway (``optimize`` not converged: exit 3) stays in, with its code.
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
from dgpc_cli.io.patch_set import member_files, member_stems, patch_set_bytes, previous_files


class MembersFailed(DgpcError):
    """Some members of a patch set failed; the exit code is the worst of theirs."""

    def __init__(self, message: str, exit_code: int, source=None):
        super().__init__(message, source=source)
        self.exit_code = exit_code


def member_kind(json_path: Path) -> str:
    """The ``kind`` of the member artifact ``json_path``."""
    return str(json.loads(Path(json_path).read_bytes()).get("kind"))


def write_patch_set(output: Path, stage: str, members: list[dict], *, force: bool) -> Path:
    """Write ``OUT.json`` as the patch set of ``members`` (see
    :func:`~dgpc_cli.io.patch_set.patch_set_bytes`), removing (with ``force``) the files of the
    output it replaces that no member lists; its JSON path."""
    json_path, _ = artifact_paths(output)
    keep = {Path(f).resolve() for m in members for f in m["files"]} | {json_path.resolve()}
    stale = [p for p in previous_files(json_path) if Path(p).resolve() not in keep]
    write_files({json_path: patch_set_bytes(json_path, stage, members)}, force=force,
                replaces=stale)
    return json_path


def each_member(stem: Path, output: Path, stage: str, run: Callable[[Path, Path], None], *,
                force: bool, say: Callable[[str], None] | None = None,
                extra: Callable[[Path], tuple[Path, ...]] = lambda out: ()) -> Path:
    """Run ``run(member, OUT.pK)`` on every member of the patch set ``stem`` and write the
    patch set of the outputs at ``output``; its JSON path. ``extra(OUT.pK)``: files a member
    writes that its artifact does not list. Raises :class:`MembersFailed` (the worst code)
    when a member failed, after the set is written."""
    members, worst, failed = [], 0, []
    out_json, _ = artifact_paths(output)
    for name, member in member_stems(stem):
        target = out_json.parent / f"{out_json.name[:-len('.json')]}.{name}"
        target_json, _ = artifact_paths(target)
        code, why = 0, ""
        try:
            run(member, target)
        except DgpcError as err:
            code, why = err.exit_code, str(err)
        worst = max(worst, code)
        written = target_json.is_file() and (code == 0 or code == 3)
        if say is not None:
            say(f"{stage}: {name}: " + (f"{target_json}" if code == 0 else
                                        f"exit {code}: {why}"))
        if code:
            failed.append(name)
        if written:
            members.append({"name": name, "kind": member_kind(target_json),
                            "json": target_json, "exit_code": code,
                            "files": member_files(target_json, extra(target))})
    if not members:
        raise MembersFailed(f"no member of the patch set was written ({', '.join(failed)} "
                            "failed)", worst or 1, source=stem)
    written_json = write_patch_set(output, stage, members, force=force)
    if worst:
        raise MembersFailed(f"{len(failed)} of the patch set's members failed "
                            f"({', '.join(failed)}); the set lists the others' outputs",
                            worst, source=written_json)
    return written_json
