"""``dgpc inspect`` of every artifact kind: which kind an artifact is, and one inspector per
kind reading it and computing its metrics (SPEC §7); a patch set's, member by member."""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path

from dgpc_cli.errors import DgpcError
from dgpc_cli.io.artifact import KINDS, artifact_paths
from dgpc_cli.io.journal import finish_interrupted
from dgpc_cli.io.jsonable import read_json
from dgpc_cli.io.net import read_net
from dgpc_cli.stages.inspect import inspect_net


def _inspect_net(json_path: Path, axis=None, against=None, coverage_tol=None) -> dict:
    from dgpc_cli.io.units import same_units

    net = read_net(json_path)
    reference = read_net(against) if against is not None else None
    if reference is not None:
        same_units([(str(json_path), net.units), (str(artifact_paths(against)[0]),
                                                  reference.units)], source="--against")
    return inspect_net(net, json_path, axis=axis, against=reference, coverage_tol=coverage_tol)


#: One inspector per artifact kind: ``inspector(json_path, axis=..., against=...) -> dict``.
#: Stages register theirs here.
INSPECTORS = {"net": _inspect_net}


def _inspect_strips(json_path: Path, **_) -> dict:
    from dgpc_cli.stages.strip_fabrication import inspect_strips

    return inspect_strips(json_path)


def _inspect_flat(json_path: Path, **_) -> dict:
    from dgpc_cli.io.flat import read_flat
    from dgpc_cli.stages.unfold import flat_metrics

    flat = read_flat(json_path)
    return flat_metrics(flat.parts, flat.classes, flat.units)


INSPECTORS.update(strips=_inspect_strips, flat=_inspect_flat)


def _inspect_mold(json_path: Path, **_) -> dict:
    from dgpc_cli.io.mold import read_mold
    from dgpc_cli.mold.extract import inspect_mold

    return inspect_mold(read_mold(json_path))


INSPECTORS.update(mold=_inspect_mold)


def _inspect_sheets(json_path: Path, **_) -> dict:
    from dgpc_cli.io.sheets import read_sheets
    from dgpc_cli.stages.nest import sheets_metrics

    return sheets_metrics(read_sheets(json_path).data)


INSPECTORS.update(sheets=_inspect_sheets)


def _inspect_laths(json_path: Path, **_) -> dict:
    from dgpc_cli.io.laths import read_laths

    return read_laths(json_path).metrics


INSPECTORS.update(laths=_inspect_laths)


def _inspect_patchset(json_path: Path, **options) -> dict:
    """Every member's metrics, by name (``members``), as its own kind's; the members whose
    stage failed (``failed``: stage, exit code, reason), when there are some."""
    from dgpc_cli.io.patch_set import failed_members, listed_members, read_patch_set

    members = {}
    for name, stem in listed_members(json_path):
        member_json, _ = artifact_paths(stem)
        kind = artifact_kind(member_json)
        if kind not in INSPECTORS or kind == "patchset":
            raise DgpcError(f"inspecting '{kind}' artifacts is not supported yet",
                            source=member_json)
        members[name] = {"kind": kind, **INSPECTORS[kind](member_json, **options)}
    failed = {m["name"]: {k: m[k] for k in ("stage", "exit_code", "reason")}
              for m in failed_members(read_patch_set(json_path))}
    return {"kind": "patchset", "members": members, **({"failed": failed} if failed else {})}


INSPECTORS.update(patchset=_inspect_patchset)


def artifact_kind(json_path: Path) -> str:
    """The kind of the artifact ``json_path`` (finishing an interrupted write first)."""
    finish_interrupted(json_path)
    doc = read_json(json_path)
    kind = doc.get("kind") if isinstance(doc, dict) else None
    if kind not in (*KINDS, "patchset"):
        raise DgpcError(f"kind: {kind!r} is not a dgpc artifact kind ({', '.join(KINDS)})",
                        source=json_path)
    return kind


def inspect_artifact(stem: Path, *, check_kind: Callable[[str, Path], None], axis=None,
                     against=None, coverage_tol=None) -> dict:
    """The metrics of the artifact ``stem``, by its kind's inspector; ``check_kind(kind,
    json_path)`` is called once the kind is known and supported, before any metric (to refuse
    options the kind does not take); ``coverage_tol`` None is the inspector's default."""
    json_path, _ = artifact_paths(stem)
    kind = artifact_kind(json_path)
    if kind not in INSPECTORS:
        raise DgpcError(f"inspecting '{kind}' artifacts is not supported yet", source=json_path)
    check_kind(kind, json_path)
    return INSPECTORS[kind](json_path, axis=axis, against=against,
                            **({} if coverage_tol is None else {"coverage_tol": coverage_tol}))
