"""Layering: the command line (``dgpc_cli.cli``) calls the stages, never the other way round;
and ``dgpc init``'s stage runs without the command line."""

import ast
from pathlib import Path

import numpy as np

import dgpc_cli
from dgpc_cli.stages.init import init_nets

PACKAGE = Path(dgpc_cli.__file__).parent


def cli_imports(source: str, package: str = "cli") -> list[str]:
    """The modules of ``dgpc_cli.PACKAGE`` (default: the command line) that ``source``
    imports."""
    found = []
    top = f"dgpc_cli.{package}"
    for node in ast.walk(ast.parse(source)):
        names = ([a.name for a in node.names] if isinstance(node, ast.Import)
                 else [node.module or ""] if isinstance(node, ast.ImportFrom) else [])
        found += [n for n in names if n == top or n.startswith(top + ".")]
    return found


def test_the_probe_finds_an_upward_import():
    assert cli_imports("from dgpc_cli.cli.options import show_progress\n") == [
        "dgpc_cli.cli.options"]
    assert cli_imports("def f():\n    import dgpc_cli.cli.progress\n") == [
        "dgpc_cli.cli.progress"]
    assert cli_imports('"""see dgpc_cli.cli.length"""\nimport dgpc_cli.io\n') == []


def test_no_package_below_the_command_line_imports_it():
    upward = {}
    for path in sorted(PACKAGE.rglob("*.py")):
        rel = path.relative_to(PACKAGE)
        if rel.parts[0] == "cli" or rel.name == "__main__.py":
            continue
        found = cli_imports(path.read_text(encoding="utf-8"))
        if found:
            upward[str(rel)] = found
    assert upward == {}


def test_nothing_below_the_editor_imports_it():
    """``dgpc_cli.edit`` sits above the stages: only the command line imports it."""
    upward = {}
    for path in sorted(PACKAGE.rglob("*.py")):
        rel = path.relative_to(PACKAGE)
        if rel.parts[0] in ("cli", "edit") or rel.name == "__main__.py":
            continue
        found = cli_imports(path.read_text(encoding="utf-8"), "edit")
        if found:
            upward[str(rel)] = found
    assert upward == {}
    assert cli_imports("from dgpc_cli.edit.session import EditSession\n", "edit")


def test_the_layout_of_nets_imports_no_stage():
    """``dgpc_cli.layout`` (laying nets on meshes) sits below the stages: it imports neither
    them nor anything above them."""
    assert cli_imports("from dgpc_cli.stages.init import init_nets\n", "stages") == [
        "dgpc_cli.stages.init"]
    upward = {}
    for path in sorted((PACKAGE / "layout").rglob("*.py")):
        source = path.read_text(encoding="utf-8")
        found = [m for package in ("stages", "cli", "edit", "batch")
                 for m in cli_imports(source, package)]
        if found:
            upward[path.name] = found
    assert upward == {}


def test_init_stage_makes_and_writes_a_net_without_the_command(tmp_path):
    lines, checked = [], []
    written = init_nets(tmp_path / "cone", units="m", units_given=False, fmt="obj",
                        force=False, check=lambda *a: checked.append(a),
                        surface="revolution", profile="cone", rows=5, cols=6,
                        say=lines.append)
    assert written == [tmp_path / "cone.json"]
    assert (tmp_path / "cone.json").exists() and (tmp_path / "cone.obj").exists()
    assert checked == []                                  # only patch nets are checked here
    assert len(lines) == 1 and lines[0].startswith("init: no --units given: the net is in m,")
    from dgpc_cli.io.net import read_net

    net = read_net(tmp_path / "cone")
    assert net.units == "m" and net.f.shape == (5, 6, 3) and np.isfinite(net.f).all()
