"""A start-up a shell user does not notice: `dgpc --help`, `--version` and completion load no
numerical library; the lazily loaded commands are the ones their help lists."""

import subprocess
import sys

from click.testing import CliRunner

from dgpc_cli.cli.main import COMMANDS, cli

HEAVY = ("numpy", "scipy", "trimesh", "ezdxf", "matplotlib", "shapely", "igl", "pymeshlab")


def _loaded_after(code: str) -> set[str]:
    """Top-level packages of ``HEAVY`` imported after running ``code`` in a fresh interpreter."""
    probe = (f"import sys\n{code}\n"
             f"print('LOADED', *sorted({{m.split('.')[0] for m in sys.modules}} & "
             f"{set(HEAVY)!r}), file=sys.stderr)")
    err = subprocess.run([sys.executable, "-c", probe], capture_output=True, text=True,
                         check=True).stderr
    line = [ln for ln in err.splitlines() if ln.startswith("LOADED")][-1]
    return set(line.split()[1:])


def test_help_version_and_completion_load_no_numerical_library():
    run = "from dgpc_cli.cli.main import cli\ntry:\n    cli([{args}])\nexcept SystemExit:\n    pass"
    assert _loaded_after(run.format(args="'--version'")) == set()
    assert _loaded_after(run.format(args="'--help'")) == set()
    completion = ("import os\nos.environ.update(_DGPC_COMPLETE='bash_complete', "
                  "COMP_WORDS='dgpc op', COMP_CWORD='1')\n"
                  + run.format(args="").replace("cli([])", "cli(prog_name='dgpc')"))
    assert _loaded_after(completion) == set()
    # a command that needs them loads them: the probe can fail
    assert "numpy" in _loaded_after("import dgpc_cli.cli.optimize")


def test_the_help_lists_every_command_with_its_own_short_help():
    ctx = cli.make_context("dgpc", ["--help"], resilient_parsing=True)
    for name, (_, _, short) in COMMANDS.items():
        command = cli.get_command(ctx, name)
        assert command is not None and command.name == name
        assert command.get_short_help_str(limit=200) == short
    out = CliRunner().invoke(cli, ["--help"]).output
    assert all(name in out for name in COMMANDS)
    assert cli.get_command(ctx, "no-such-command") is None
