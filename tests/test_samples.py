"""The pipelines' inputs in samples/ are what samples/generate.py makes, byte for byte."""

import importlib.util
import shutil
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


def test_committed_samples_are_the_generators_output():
    r = subprocess.run([sys.executable, str(ROOT / "samples" / "generate.py"), "--check"],
                       capture_output=True, text=True, cwd=ROOT)
    assert r.returncode == 0, r.stderr


def test_check_names_an_edited_sample(tmp_path, capsys):
    shutil.copytree(ROOT / "samples", tmp_path / "samples")
    spec = importlib.util.spec_from_file_location("generate", ROOT / "samples" / "generate.py")
    generate = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(generate)
    generate.ROOT, generate.HERE = tmp_path, tmp_path / "samples"
    felt = tmp_path / "samples" / "meshes" / "felt.obj"
    felt.write_bytes(felt.read_bytes().replace(b"v ", b"v  ", 1))
    before = felt.read_bytes()
    assert generate.main(["--check"]) == 1
    assert "differs: samples/meshes/felt.obj" in capsys.readouterr().err
    assert felt.read_bytes() == before                      # --check writes nothing
    assert generate.main([]) == 0 and generate.main(["--check"]) == 0
